// The ray-tree inspector in the window: a picked pixel's rays
// (render/ray_tree.h) drawn over the image, projected through the camera,
// and a panel listing the tree with each ray's contribution. Hovering a row
// highlights its segment and hovering a segment highlights its row.
#pragma once

#include "render/ray_tree.h"
#include "scene/scene.h"

#include <glm/glm.hpp>

#include <optional>

namespace whitted {

// Segment colours (RGBA8, as ImGui packs them: 0xAABBGGRR), one per kind.
inline constexpr uint32_t kOverlayCameraColour = 0xff00ffffu;      // yellow
inline constexpr uint32_t kOverlayReflectionColour = 0xffffff00u;  // cyan
inline constexpr uint32_t kOverlayRefractionColour = 0xffff00ffu;  // magenta
inline constexpr uint32_t kOverlayTotalInternalColour = 0xff0080ffu;  // orange
inline constexpr uint32_t kOverlayShadowColour = 0xff00ff00u;      // green: reaches its light (lit or filtered)
inline constexpr uint32_t kOverlayBlockedColour = 0xff0000ffu;     // red: up to its blocker

struct RayTreeView {
    std::optional<glm::ivec2> pixel;  // the picked pixel, in image pixels
    std::optional<RayTree> tree;      // its tree for the current scene and camera
    bool picking = false;             // T pressed: the next click picks
    int hoveredRay = -1;              // from the panel or the image
    int hoveredShadowRay = -1;
};

// Where a world point appears in a window of `windowSize` showing the
// camera's image stretched over it; none behind the eye.
std::optional<glm::vec2> projectToWindow(const Camera& camera, glm::vec2 imageSize, glm::vec2 windowSize,
                                         glm::vec3 point);

// Draws the segments (into ImGui's background list, so over the image and
// under the panels) and the panel. Call between ImGui frames' begin and
// render; the image fills the window.
void drawRayTreeView(RayTreeView& view, const Scene& scene, const Camera& camera, glm::vec2 imageSize,
                     glm::vec2 windowSize);

}  // namespace whitted
