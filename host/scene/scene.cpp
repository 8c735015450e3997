#include "scene/scene.h"

#include "scene/xml_reader.h"

#include <limits>

namespace whitted {

CameraFrameProblem cameraFrameProblem(const Camera& camera) {
    // Unit vectors closer to parallel than |cross| 1e-6 count as parallel.
    constexpr double kParallelTolerance = 1e-6;
    glm::dvec3 forward = camera.windowCenter - camera.eye;
    double distance = glm::length(forward);
    if (!(distance > xml::kMinLength)) return CameraFrameProblem::EyeAtWindow;
    if (!(glm::length(glm::cross(forward / distance, glm::normalize(camera.up))) >= kParallelTolerance))
        return CameraFrameProblem::UpAlongView;
    return CameraFrameProblem::None;
}

bool rectEdgesSpan(const glm::dvec3& u, const glm::dvec3& v) {
    // Unit edges closer to parallel than |cross| 1e-6 span no area (as the camera's up above).
    constexpr double kParallelTolerance = 1e-6;
    double lu = glm::length(u), lv = glm::length(v);
    return lu > 0.0 && lv > 0.0 && glm::length(glm::cross(u / lu, v / lv)) >= kParallelTolerance;
}

double Camera::focusDistanceOrDefault() const { return focusDistance.value_or(glm::length(windowCenter - eye)); }

double glossyLobeExponent(double roughness) {
    double alpha = roughness * roughness;
    return alpha > 0 ? 2.0 / (alpha * alpha) - 2.0 : std::numeric_limits<double>::infinity();
}

size_t csgLeafCount(const Csg& csg) {
    size_t count = 0;
    for (const CsgChild& child : csg.children) {
        const Csg* nested = std::get_if<Csg>(&child.shape);
        count += nested ? csgLeafCount(*nested) : 1;
    }
    return count;
}

}  // namespace whitted
