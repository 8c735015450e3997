// Turns mouse and keyboard input into a scene Camera: orbit about a pivot in
// front of the eye (left drag), pan (right or middle drag), zoom towards the
// pivot (wheel), fly (W/S forward/back, A/D left/right, Q/E down/up), reset to
// the scene file's camera (R). The scene's <up> stays the up direction; the
// window distance and field of view stay as the file gives them.
#pragma once

#include <string>

#include "scene/scene.h"

namespace whitted {

class CameraController {
public:
    // `sceneRadius` scales pan and fly speeds and the initial pivot distance.
    CameraController(const Camera& home, double sceneRadius);

    void setHome(const Camera& home, double sceneRadius);  // a reloaded file
    void reset();

    void orbit(double dxPixels, double dyPixels);
    void pan(double dxPixels, double dyPixels, int viewportHeight);
    void zoom(double wheelSteps);
    // `direction` in camera space: x right, y up, z forward; seconds of flight.
    void fly(const glm::dvec3& direction, double seconds);

    const Camera& camera() const { return camera_; }
    // The lens (depth of field) from the editor panel; the pose stays.
    void setLens(double apertureRadius, std::optional<double> focusDistance);
    // True once after any change; the caller restarts accumulation.
    bool takeChanged();

private:
    void apply();  // eye, yaw, pitch, distance -> camera_

    Camera home_;
    Camera camera_;
    double sceneRadius_ = 1;
    double windowDistance_ = 1;
    glm::dvec3 pivot_{0};
    double distance_ = 1;                                          // eye to pivot
    double yaw_ = 0, pitch_ = 0;                                   // of the view direction, about up
    glm::dvec3 up_{0, 1, 0}, reference_{1, 0, 0}, side_{0, 0, 1};  // orthonormal frame
    bool changed_ = false;
};

// The camera as the scene file's <camera> element (seed schema plus up,
// fov, width and height), indented by `indent` spaces.
std::string cameraXml(const Camera& camera, int indent = 0);

// A radius that bounds the scene's objects and lights (at least 1e-3).
double sceneRadius(const Scene& scene);

}  // namespace whitted
