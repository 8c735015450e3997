#include "view/ray_tree_overlay.h"

#include "render/gpu_scene.h"

#include <imgui/imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>

namespace whitted {
namespace {

// The camera as the tracer sees it (FrameParams: eye, forward, right and up
// scaled to the image window at unit distance), from the same packing.
struct CameraFrame {
    glm::vec3 eye, forward, right, up;
};

CameraFrame cameraFrame(const Camera& camera, glm::vec2 imageSize) {
    Scene cameraOnly;
    cameraOnly.camera = camera;
    RenderSettings settings{.width = int(imageSize.x), .height = int(imageSize.y)};
    gpu::FrameParams p = packScene(cameraOnly, settings).params;
    return {p.eye, p.forward, p.right, p.up};
}

// Camera space: x, y on the image window at unit distance, z along forward.
glm::vec3 toCamera(const CameraFrame& f, glm::vec3 point) {
    glm::vec3 v = point - f.eye;
    return {glm::dot(v, f.right) / glm::dot(f.right, f.right), glm::dot(v, f.up) / glm::dot(f.up, f.up),
            glm::dot(v, f.forward)};
}

// generateCameraRay (shaders/camera.glsl) inverted: ndc = (x, y) / z.
glm::vec2 toWindow(glm::vec3 c, glm::vec2 windowSize) {
    glm::vec2 ndc(c.x / c.z, c.y / c.z);
    return {(ndc.x + 1.0f) * 0.5f * windowSize.x, (1.0f - ndc.y) * 0.5f * windowSize.y};
}

constexpr float kNear = 1e-3f;

// The segment a..b clipped to the part in front of the eye, in window
// coordinates; the window's edges clip the rest (ImGui's clip rectangle).
bool projectSegment(const CameraFrame& f, glm::vec2 windowSize, glm::vec3 a, glm::vec3 b, ImVec2& pa, ImVec2& pb) {
    glm::vec3 ca = toCamera(f, a), cb = toCamera(f, b);
    if (ca.z < kNear && cb.z < kNear) return false;
    if (ca.z < kNear) ca = glm::mix(ca, cb, (kNear - ca.z) / (cb.z - ca.z));
    if (cb.z < kNear) cb = glm::mix(cb, ca, (kNear - cb.z) / (ca.z - cb.z));
    glm::vec2 wa = toWindow(ca, windowSize), wb = toWindow(cb, windowSize);
    // Far outside the window ImGui's float vertices lose precision: keep the
    // part within a generous box around it (Liang-Barsky on that box).
    glm::vec2 lo = -windowSize * 4.0f, hi = windowSize * 5.0f, d = wb - wa;
    float t0 = 0.0f, t1 = 1.0f;
    for (int axis = 0; axis < 2; ++axis) {
        if (std::abs(d[axis]) < 1e-9f) {
            if (wa[axis] < lo[axis] || wa[axis] > hi[axis]) return false;
            continue;
        }
        float ta = (lo[axis] - wa[axis]) / d[axis], tb = (hi[axis] - wa[axis]) / d[axis];
        t0 = std::max(t0, std::min(ta, tb));
        t1 = std::min(t1, std::max(ta, tb));
    }
    if (t0 > t1) return false;
    glm::vec2 qa = wa + t0 * d, qb = wa + t1 * d;
    pa = ImVec2(qa.x, qa.y);
    pb = ImVec2(qb.x, qb.y);
    return true;
}

uint32_t rayColour(uint32_t kind) {
    switch (kind) {
        case gpu::kRayCamera: return kOverlayCameraColour;
        case gpu::kRayReflection: return kOverlayReflectionColour;
        case gpu::kRayRefraction: return kOverlayRefractionColour;
        default: return kOverlayTotalInternalColour;
    }
}

// Distance from p to the segment a..b in window pixels.
float distanceToSegment(ImVec2 p, ImVec2 a, ImVec2 b) {
    glm::vec2 ga(a.x, a.y), gb(b.x, b.y), gp(p.x, p.y), d = gb - ga;
    float len2 = glm::dot(d, d);
    float t = len2 > 0.0f ? std::clamp(glm::dot(gp - ga, d) / len2, 0.0f, 1.0f) : 0.0f;
    return glm::length(gp - (ga + t * d));
}

std::string rgbText(glm::vec3 c) {
    char text[64];
    std::snprintf(text, sizeof text, "%.4f %.4f %.4f", c.r, c.g, c.b);
    return text;
}

void swatch(const char* id, glm::vec3 c) {
    glm::vec3 shown = glm::clamp(c, 0.0f, 1.0f);
    ImGui::ColorButton(id, ImVec4(shown.r, shown.g, shown.b, 1.0f), ImGuiColorEditFlags_NoTooltip,
                       ImVec2(12, 12));
}

}  // namespace

std::optional<glm::vec2> projectToWindow(const Camera& camera, glm::vec2 imageSize, glm::vec2 windowSize,
                                         glm::vec3 point) {
    glm::vec3 c = toCamera(cameraFrame(camera, imageSize), point);
    if (c.z < kNear) return std::nullopt;
    return toWindow(c, windowSize);
}

void drawRayTreeView(RayTreeView& view, const Scene& scene, const Camera& camera, glm::vec2 imageSize,
                     glm::vec2 windowSize) {
    if (!view.tree) return;
    const RayTree& tree = *view.tree;
    CameraFrame frame = cameraFrame(camera, imageSize);
    ImDrawList* draw = ImGui::GetBackgroundDrawList();
    ImVec2 mouse = ImGui::GetIO().MousePos;
    bool mouseFree = !ImGui::GetIO().WantCaptureMouse;
    int hoverRay = -1, hoverShadow = -1;
    float nearest = 6.0f;  // pixels: how close the cursor must come to a segment

    // A miss is drawn out to well past the scene.
    float far = 10.0f * float(std::max(1.0, glm::length(camera.windowCenter - camera.eye))) + 1e3f;
    auto segmentEnd = [&](const gpu::RayTreeRay& r) {
        return r.primitive == gpu::kNoObject ? r.origin + far * r.direction : r.point;
    };
    for (size_t s = 0; s < tree.shadowRays.size(); ++s) {
        const gpu::RayTreeShadowRay& sr = tree.shadowRays[s];
        float length = sr.outcome == gpu::kShadowBlocked ? sr.blockerT : sr.distance;
        ImVec2 a, b;
        if (!projectSegment(frame, windowSize, sr.origin, sr.origin + length * sr.direction, a, b)) continue;
        bool highlighted = int(s) == view.hoveredShadowRay;
        draw->AddLine(a, b, sr.outcome == gpu::kShadowBlocked ? kOverlayBlockedColour : kOverlayShadowColour,
                      highlighted ? 5.0f : 2.0f);
        if (sr.outcome == gpu::kShadowBlocked) draw->AddCircleFilled(b, 4.0f, kOverlayBlockedColour);
        float d = distanceToSegment(mouse, a, b);
        if (mouseFree && d < nearest) {
            nearest = d;
            hoverShadow = int(s);
            hoverRay = -1;
        }
    }
    for (size_t i = 0; i < tree.rays.size(); ++i) {
        const gpu::RayTreeRay& r = tree.rays[i];
        ImVec2 a, b;
        if (!projectSegment(frame, windowSize, r.origin, segmentEnd(r), a, b)) continue;
        bool highlighted = int(i) == view.hoveredRay;
        draw->AddLine(a, b, rayColour(r.kind), highlighted ? 6.0f : 3.0f);
        if (r.kind == gpu::kRayCamera) draw->AddCircle(b, highlighted ? 9.0f : 6.0f, kOverlayCameraColour, 0, 2.0f);
        float d = distanceToSegment(mouse, a, b);
        if (mouseFree && d < nearest) {
            nearest = d;
            hoverRay = int(i);
            hoverShadow = -1;
        }
    }

    // The panel: the tree with each ray's contribution as numbers and a swatch.
    int panelRay = -1, panelShadow = -1;
    ImGui::SetNextWindowPos(ImVec2(8, windowSize.y - 8), ImGuiCond_Always, ImVec2(0, 1));
    ImGui::SetNextWindowBgAlpha(0.85f);
    std::string title = "Ray tree of pixel " + std::to_string(tree.x) + "," + std::to_string(tree.y) + "###raytree";
    if (ImGui::Begin(title.c_str(), nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        swatch("##pixel", tree.color());
        ImGui::SameLine();
        ImGui::Text("pixel colour %s = sum of %zu contributions", rgbText(tree.color()).c_str(), tree.rays.size());
        if (tree.dropped > 0) ImGui::TextColored(ImVec4(1, 0.5f, 0, 1), "%u rays left out (record full)", tree.dropped);
        tree.walk(
            [&](uint32_t i, int) {
                const gpu::RayTreeRay& r = tree.rays[i];
                std::string what = r.primitive == gpu::kNoObject
                                       ? std::string("misses")
                                       : std::string(shapeName(r.shape)) + " of " + objectLabel(scene, r.material);
                char label[256];
                std::snprintf(label, sizeof label, "%s: %s  t %.3g###ray%u", rayKindName(r.kind), what.c_str(), r.t, i);
                ImGuiTreeNodeFlags flags = ImGuiTreeNodeFlags_DefaultOpen | ImGuiTreeNodeFlags_SpanAvailWidth;
                if (int(i) == view.hoveredRay) flags |= ImGuiTreeNodeFlags_Selected;
                ImGui::PushStyleColor(ImGuiCol_Text, ImGui::ColorConvertU32ToFloat4(rayColour(r.kind)));
                bool open = ImGui::TreeNodeEx(label, flags);
                ImGui::PopStyleColor();
                if (ImGui::IsItemHovered()) panelRay = int(i);
                ImGui::SameLine();
                swatch(("##c" + std::to_string(i)).c_str(), r.contribution);
                ImGui::SameLine();
                ImGui::Text("%s", rgbText(r.contribution).c_str());
                if (!open) return false;
                std::span<const gpu::RayTreeShadowRay> shadows = tree.shadowRaysOf(i);
                for (size_t k = 0; k < shadows.size(); ++k) {
                    const gpu::RayTreeShadowRay& sr = shadows[k];
                    int s = int(r.firstShadowRay + k);
                    std::string outcome = shadowOutcomeName(sr.outcome);
                    if (sr.outcome == gpu::kShadowBlocked) outcome += " by " + objectLabel(scene, sr.blockerMaterial);
                    if (sr.outcome == gpu::kShadowFiltered) {
                        const char* separator = " by ";
                        for (const gpu::RayTreeCrossing& c : tree.crossingsOf(sr)) {
                            outcome += separator + objectLabel(scene, c.material) + " (" + rgbText(c.filterColour) + ")";
                            separator = ", ";
                        }
                    }
                    bool selected = s == view.hoveredShadowRay;
                    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::ColorConvertU32ToFloat4(
                                                             sr.outcome == gpu::kShadowBlocked ? kOverlayBlockedColour
                                                                                               : kOverlayShadowColour));
                    ImGui::Selectable(("shadow ray to light " + std::to_string(sr.light) + ": " + outcome + "##s" +
                                       std::to_string(s)).c_str(),
                                      selected);
                    ImGui::PopStyleColor();
                    if (ImGui::IsItemHovered()) panelShadow = s;
                    ImGui::SameLine();
                    swatch(("##l" + std::to_string(s)).c_str(), r.weight * (sr.diffuse + sr.specular));
                }
                return true;
            },
            [](uint32_t) { ImGui::TreePop(); });
    }
    ImGui::End();
    // Next frame highlights what the cursor is over now, in the image or the panel.
    view.hoveredRay = panelRay >= 0 || panelShadow >= 0 ? panelRay : hoverRay;
    view.hoveredShadowRay = panelRay >= 0 || panelShadow >= 0 ? panelShadow : hoverShadow;
}

}  // namespace whitted
