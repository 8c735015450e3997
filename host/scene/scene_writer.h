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
// the extensions of README "Scene files").
std::string sceneXml(const Scene& scene);

// The <camera> element alone, indented by `indent` spaces.
std::string sceneCameraXml(const Camera& camera, int indent = 0);

// Writes sceneXml(scene) to `path` atomically (temporary file + rename).
void writeSceneFile(const Scene& scene, const std::filesystem::path& path);

}  // namespace whitted
