// Files that appear whole or not at all: written under a temporary name in
// the destination folder, then renamed over the target.
#pragma once

#include <filesystem>
#include <string>

namespace whitted {

// Writes text to a file atomically (temporary file, then rename); throws
// std::runtime_error naming the file when it cannot be written.
void writeTextFile(const std::filesystem::path& path, const std::string& text);

}  // namespace whitted
