// Reads a scene from the seed's XML format (plus this project's extensions,
// see README "Scene files") into the CPU scene model. Bad input is refused
// with the file, the line and what was expected; nothing is guessed.
#pragma once

#include "scene/scene.h"

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

namespace whitted {

// what() is "FILE:LINE: message", or "FILE: message" when no line applies.
class SceneError : public std::runtime_error {
public:
    SceneError(std::string file, int line, std::string message);
    const std::string& file() const { return file_; }
    int line() const { return line_; }
    const std::string& message() const { return message_; }

private:
    std::string file_;
    int line_;
    std::string message_;
};

Scene loadScene(const std::filesystem::path& path);
Scene loadSceneFromString(std::string_view xml, const std::filesystem::path& name);

}  // namespace whitted
