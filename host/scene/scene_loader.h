// Reads a scene from the seed's XML format (plus this project's extensions,
// see scenes/README.md "Scene files") into the CPU scene model. Bad input is refused
// with the file, the line and what was expected; nothing is guessed and no
// element is silently ignored.
#pragma once

#include "scene/scene.h"
#include "scene/scene_error.h"
#include "scene/xml_reader.h"

#include <filesystem>
#include <string_view>

namespace whitted {

// The format's own value ranges beside the XML reader's (scene/xml_reader.h),
// shared with what builds scenes in code (the Python module).
inline constexpr xml::Range kIorRange{0.1, 10, false, false};
inline constexpr xml::Range kShininessRange{0, 1e5, true, false};
inline constexpr xml::Range kFovRange{0, 180, true, true};
// A spot's cone: 0 <= inner < outer <= 90 degrees.
inline constexpr xml::Range kInnerAngleRange{0, 90, false, true};
inline constexpr xml::Range kOuterAngleRange{0, 90, true, false};
// An area light (scenes/README.md "Area lights"): a sphere's radius, its
// shadow rays per camera sample.
inline constexpr xml::Range kLightRadiusRange{0, 1e6, false, false};
inline constexpr int kMaxShadowSamples = 256;

// Reads and loads the file at `path`; a file that cannot be read gives
// SceneError(path, 0, "cannot read file: <reason>").
Scene loadScene(const std::filesystem::path& path);

// Loads XML text; `name` is used in messages and stored as Scene::sourcePath.
Scene loadSceneFromString(std::string_view xml, const std::filesystem::path& name);

}  // namespace whitted
