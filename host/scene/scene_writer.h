// Writes the CPU scene model back as a scene file that scene_loader reads
// again to an equal Scene (up to the last bit of directions the loader
// renormalises and of box corners it re-adds). Every number is written with
// 17 significant digits so that doubles survive the text round trip.
#pragma once

#include <filesystem>
#include <string>

#include "scene/scene.h"

namespace whitted {

// The scene as XML text (this project's schema: the seed's elements plus
// the extensions of scenes/README.md "Scene files"). A mesh read from a model file is
// written as its <file> (with <scale> and <rotation>), the path relative to
// the folder of `destination`, the file the text is for (absolute without).
std::string sceneXml(const Scene& scene, const std::filesystem::path& destination = {});

// The <camera> element alone, indented by `indent` spaces.
std::string sceneCameraXml(const Camera& camera, int indent = 0);

// Writes sceneXml(scene) to `path` atomically (temporary file + rename).
void writeSceneFile(const Scene& scene, const std::filesystem::path& path);

}  // namespace whitted
