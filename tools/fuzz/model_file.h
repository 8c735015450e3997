// The fuzz targets of file readers (tools/fuzz/*_fuzzer.cpp) hand their
// bytes to the readers as files, the way the renderer meets them: each
// process writes them into a folder of its own under the temporary folder.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

namespace whitted::fuzz {

inline const std::filesystem::path& scratchFolder() {
    static const std::filesystem::path folder = [] {
        std::string pattern = (std::filesystem::temp_directory_path() / "whitted-fuzz-XXXXXX").string();
        if (!mkdtemp(pattern.data())) __builtin_trap();
        return std::filesystem::path(pattern);
    }();
    return folder;
}

inline std::filesystem::path writeScratch(const std::string& name, std::string_view bytes) {
    std::filesystem::path path = scratchFolder() / name;
    std::ofstream(path, std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(bytes.size()));
    return path;
}

}  // namespace whitted::fuzz
