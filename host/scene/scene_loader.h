// Reads a scene from the seed's XML format (plus this project's extensions,
// see README "Scene files") into the CPU scene model. Bad input is refused
// with the file, the line and what was expected; nothing is guessed and no
// element is silently ignored.
#pragma once

#include "scene/scene.h"

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

namespace whitted {

// Any refused input. what() is "FILE:LINE: message"; when no line applies
// (line 0: the file cannot be read, or an XML error without a position) it
// is "FILE: message".
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

// Reads and loads the file at `path`; a file that cannot be read gives
// SceneError(path, 0, "cannot read file: <reason>").
Scene loadScene(const std::filesystem::path& path);

// Loads XML text; `name` is used in messages and stored as Scene::sourcePath.
Scene loadSceneFromString(std::string_view xml, const std::filesystem::path& name);

}  // namespace whitted
