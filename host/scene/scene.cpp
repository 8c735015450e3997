#include "scene/scene.h"

namespace whitted {

CameraFrameProblem cameraFrameProblem(const Camera& camera) {
    // The XML format's tolerances (scene/xml_reader.h kMinLength; unit
    // vectors closer to parallel than |cross| 1e-6 count as parallel).
    constexpr double kMinLength = 1e-12, kParallelTolerance = 1e-6;
    glm::dvec3 forward = camera.windowCenter - camera.eye;
    double distance = glm::length(forward);
    if (!(distance > kMinLength)) return CameraFrameProblem::EyeAtWindow;
    if (!(glm::length(glm::cross(forward / distance, glm::normalize(camera.up))) >= kParallelTolerance))
        return CameraFrameProblem::UpAlongView;
    return CameraFrameProblem::None;
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
