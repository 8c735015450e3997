// The ray tree (render/ray_tree.h) as JSON: every field of every ray,
// shadow ray and crossing, the objects named; the one builder of the text
// `whitted trace --json` prints (indented by 2, a newline at the end).
#pragma once

#include "render/ray_tree.h"
#include "scene/scene.h"

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace whitted {

// Each object named carries its "id": the object_id mask's id for it, which
// is its index in the scene's list unless `objectIds` (one per object, the
// Python module's stable ids) says otherwise.
std::string rayTreeJson(const RayTree& tree, const Scene& scene, std::span<const uint64_t> objectIds = {});
// Several pixels' trees (`whitted trace` with --pixel given more than once):
// a JSON array of the records rayTreeJson writes, in the order given.
std::string rayTreesJson(const std::vector<RayTree>& trees, const Scene& scene);

}  // namespace whitted
