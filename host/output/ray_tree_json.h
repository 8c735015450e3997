// The ray tree (render/ray_tree.h) as JSON: every field of every ray,
// shadow ray and crossing, the objects named; the one builder of the text
// `whitted trace --json` prints (indented by 2, a newline at the end).
#pragma once

#include "render/ray_tree.h"
#include "scene/scene.h"

#include <string>
#include <vector>

namespace whitted {

std::string rayTreeJson(const RayTree& tree, const Scene& scene);
// Several pixels' trees (`whitted trace` with --pixel given more than once):
// a JSON array of the records rayTreeJson writes, in the order given.
std::string rayTreesJson(const std::vector<RayTree>& trees, const Scene& scene);

}  // namespace whitted
