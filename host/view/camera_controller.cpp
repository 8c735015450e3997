#include "view/camera_controller.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <variant>

#include "scene/scene_writer.h"
#include "shapes/shapes.h"

namespace whitted {
namespace {

constexpr double kOrbitRadiansPerPixel = 0.005;
constexpr double kMaxPitch = 1.5;  // radians; keeps the view off the up axis
constexpr double kZoomPerStep = 0.9;

}  // namespace

CameraController::CameraController(const Camera& home, double radius) {
    setHome(home, radius);
}

void CameraController::setHome(const Camera& home, double radius) {
    home_ = home;
    sceneRadius_ = std::max(radius, 1e-3);
    reset();
}

// The view direction is kept as yaw and pitch in a frame around the scene's
// up, so orbiting never rolls the camera.
void CameraController::reset() {
    camera_ = home_;
    glm::dvec3 forward = home_.windowCenter - home_.eye;
    windowDistance_ = glm::length(forward);
    forward /= windowDistance_;
    up_ = glm::normalize(home_.up);
    glm::dvec3 flat = forward - glm::dot(forward, up_) * up_;
    reference_ = glm::length(flat) > 1e-9 ? glm::normalize(flat) : glm::normalize(glm::cross(up_, glm::dvec3(1, 0, 0)));
    side_ = glm::cross(reference_, up_);
    yaw_ = 0;
    pitch_ = std::asin(std::clamp(glm::dot(forward, up_), -1.0, 1.0));
    distance_ = sceneRadius_;
    pivot_ = home_.eye + forward * distance_;
    changed_ = true;
}

void CameraController::apply() {
    glm::dvec3 horizontal = std::cos(yaw_) * reference_ + std::sin(yaw_) * side_;
    glm::dvec3 forward = std::cos(pitch_) * horizontal + std::sin(pitch_) * up_;
    camera_.eye = pivot_ - forward * distance_;
    camera_.windowCenter = camera_.eye + forward * windowDistance_;
    camera_.up = home_.up;
    changed_ = true;
}

void CameraController::setLens(double apertureRadius, std::optional<double> focusDistance) {
    camera_.apertureRadius = home_.apertureRadius = apertureRadius;
    camera_.focusDistance = home_.focusDistance = focusDistance;
    changed_ = true;
}

void CameraController::orbit(double dx, double dy) {
    yaw_ += dx * kOrbitRadiansPerPixel;
    pitch_ = std::clamp(pitch_ - dy * kOrbitRadiansPerPixel, -kMaxPitch, kMaxPitch);
    apply();
}

void CameraController::pan(double dx, double dy, int viewportHeight) {
    // One pixel moves the pivot by one pixel's width at the pivot distance.
    glm::dvec3 forward = glm::normalize(camera_.windowCenter - camera_.eye);
    glm::dvec3 right = glm::normalize(glm::cross(forward, up_));
    glm::dvec3 up = glm::cross(right, forward);
    double perPixel =
        2.0 * distance_ * std::tan(glm::radians(camera_.verticalFovDegrees) / 2) / std::max(viewportHeight, 1);
    pivot_ += (-dx * right + dy * up) * perPixel;
    apply();
}

void CameraController::zoom(double steps) {
    distance_ = std::max(distance_ * std::pow(kZoomPerStep, steps), 1e-3 * sceneRadius_);
    apply();
}

void CameraController::fly(const glm::dvec3& direction, double seconds) {
    glm::dvec3 forward = glm::normalize(camera_.windowCenter - camera_.eye);
    glm::dvec3 right = glm::normalize(glm::cross(forward, up_));
    double speed = 0.5 * sceneRadius_;  // scene radii per second
    pivot_ += (direction.x * right + direction.y * up_ + direction.z * forward) * speed * seconds;
    apply();
}

bool CameraController::takeChanged() {
    bool c = changed_;
    changed_ = false;
    return c;
}

std::string cameraXml(const Camera& camera, int indent) {
    return sceneCameraXml(camera, indent);
}

double sceneRadius(const Scene& scene) {
    // The shapes' own bounds (host/shapes/); a plane, unbounded, by its point.
    Aabb box;
    for (const Light& l : scene.lights) box.extend(glm::vec3(l.position));
    for (const Object& o : scene.objects)
        std::visit(
            [&](const auto& s) {
                using T = std::decay_t<decltype(s)>;
                if constexpr (std::is_same_v<T, Sphere>) box.extend(boundsSphere(s));
                else if constexpr (std::is_same_v<T, Cylinder>) box.extend(boundsCylinder(s));
                else if constexpr (std::is_same_v<T, Plane>) box.extend(glm::vec3(s.point));
                else if constexpr (std::is_same_v<T, Triangle>) box.extend(boundsTriangle(s));
                else if constexpr (std::is_same_v<T, Box>) box.extend(boundsBox(s));
                else if constexpr (std::is_same_v<T, Csg>) box.extend(boundsCsg(s));
                else
                    for (const Triangle& t : s.triangles) box.extend(boundsTriangle(t));
            },
            o.shape);
    if (box.empty()) return 1.0;
    return std::max(0.5 * glm::length(glm::dvec3(box.max - box.min)), 1e-3);
}

}  // namespace whitted
