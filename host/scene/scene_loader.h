// Reads a scene from the seed's XML format (plus this project's extensions,
// see scenes/README.md "Scene files") into the CPU scene model. Bad input is refused
// with the file, the line and what was expected; nothing is guessed and no
// element is silently ignored.
#pragma once

#include "scene/scene.h"
#include "scene/scene_error.h"

#include <filesystem>
#include <string_view>

namespace whitted {

// Reads and loads the file at `path`; a file that cannot be read gives
// SceneError(path, 0, "cannot read file: <reason>").
Scene loadScene(const std::filesystem::path& path);

// Loads XML text; `name` is used in messages and stored as Scene::sourcePath.
Scene loadSceneFromString(std::string_view xml, const std::filesystem::path& name);

}  // namespace whitted
