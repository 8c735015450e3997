#include "scene/camera_matrices.h"

#include "scene/xml_reader.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace whitted {
namespace {

[[noreturn]] void refuse(const std::string& field, const std::string& why) { throw std::invalid_argument(field + ": " + why); }

std::string shown(double v) {
    std::ostringstream s;
    s.precision(17);
    s << v;
    return s.str();
}

}  // namespace

Camera cameraFromMatrices(const Camera& base, const glm::dmat3& K, const glm::dmat4& camToWorld, int width, int height,
                          CameraConvention convention) {
    if (width < 1 || width > 16384) refuse("width", "must be in 1..16384, got " + std::to_string(width));
    if (height < 1 || height > 16384) refuse("height", "must be in 1..16384, got " + std::to_string(height));
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            if (!std::isfinite(K[c][r])) refuse("K", "every value must be finite, got " + shown(K[c][r]) + " at [" + std::to_string(r) + "][" + std::to_string(c) + "]");
    double fx = K[0][0], fy = K[1][1], cx = K[2][0], cy = K[2][1];
    if (fx <= 0) refuse("K", "fx (K[0][0]) must be > 0, got " + shown(fx));
    for (double v : {fx, fy, cx, cy})
        if (std::abs(v) > xml::kMaxMagnitude) refuse("K", "fx, fy, cx and cy must be within ±1e6 (the scene format's limit), got " + shown(v));
    if (fy <= 0) refuse("K", "fy (K[1][1]) must be > 0, got " + shown(fy));
    if (K[1][0] != 0) refuse("K", "skew (K[0][1]) must be 0 (the shader's pixels are rectangular), got " + shown(K[1][0]));
    if (K[0][1] != 0) refuse("K", "K[1][0] must be 0, got " + shown(K[0][1]));
    if (K[0][2] != 0 || K[1][2] != 0 || K[2][2] != 1)
        refuse("K", "the last row must be (0, 0, 1), got (" + shown(K[0][2]) + ", " + shown(K[1][2]) + ", " + shown(K[2][2]) + ")");

    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(camToWorld[c][r]))
                refuse("cam_to_world", "every value must be finite, got " + shown(camToWorld[c][r]) + " at [" + std::to_string(r) + "][" + std::to_string(c) + "]");
    if (camToWorld[0][3] != 0 || camToWorld[1][3] != 0 || camToWorld[2][3] != 0 || camToWorld[3][3] != 1)
        refuse("cam_to_world", "the last row must be (0, 0, 0, 1)");
    glm::dmat3 R(camToWorld);
    glm::dmat3 RtR = glm::transpose(R) * R;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            if (std::abs(RtR[c][r] - (c == r ? 1.0 : 0.0)) > 1e-6)
                refuse("cam_to_world", "the rotation part must be orthonormal (a rigid pose, no scale or shear)");
    if (glm::determinant(R) < 0) refuse("cam_to_world", "the rotation part must have determinant +1 (no mirroring)");

    // OpenCV axes of the camera in the scene.
    glm::dvec3 x = R[0];
    glm::dvec3 down = convention == CameraConvention::OpenCV ? R[1] : -R[1];
    glm::dvec3 forward = convention == CameraConvention::OpenCV ? R[2] : -R[2];
    Camera c = base;
    c.eye = glm::dvec3(camToWorld[3]);
    c.windowCenter = c.eye + forward;
    c.up = -down;
    (void)x;  // cross(forward, up) gives it back: a rotation is right-handed
    c.projection = Camera::Projection::Perspective;
    c.width = width;
    c.height = height;
    c.intrinsics = Camera::Intrinsics{.fx = fx, .fy = fy, .cx = cx, .cy = cy};
    // What fov reads: the vertical field of view these intrinsics give at the centre.
    c.verticalFovDegrees = intrinsicsVerticalFov(*c.intrinsics, height);
    return c;
}

double intrinsicsVerticalFov(const Camera::Intrinsics& k, int height) {
    return glm::degrees(2.0 * std::atan(height / (2.0 * k.fy)));
}

glm::dmat3 cameraIntrinsicMatrix(const Camera& camera) {
    if (camera.projection == Camera::Projection::Orthographic)
        throw std::invalid_argument("intrinsics: an orthographic camera has no intrinsic matrix");
    Camera::Intrinsics in;
    if (camera.intrinsics) {
        in = *camera.intrinsics;
    } else {
        // gpu_scene.cpp packCamera: half height tan(fov / 2) at unit distance.
        double f = camera.height / (2.0 * std::tan(glm::radians(camera.verticalFovDegrees) / 2.0));
        in = {.fx = f, .fy = f, .cx = (camera.width - 1) / 2.0, .cy = (camera.height - 1) / 2.0};
    }
    glm::dmat3 K(0.0);
    K[0][0] = in.fx;
    K[1][1] = in.fy;
    K[2][0] = in.cx;
    K[2][1] = in.cy;
    K[2][2] = 1;
    return K;
}

glm::dmat4 cameraToWorld(const Camera& camera, CameraConvention convention) {
    glm::dvec3 forward = glm::normalize(camera.windowCenter - camera.eye);
    glm::dvec3 right = glm::normalize(glm::cross(forward, camera.up));
    glm::dvec3 up = glm::cross(right, forward);
    bool cv = convention == CameraConvention::OpenCV;
    glm::dmat4 m(1.0);
    m[0] = glm::dvec4(right, 0);
    m[1] = glm::dvec4(cv ? -up : up, 0);
    m[2] = glm::dvec4(cv ? forward : -forward, 0);
    m[3] = glm::dvec4(camera.eye, 1);
    return m;
}

}  // namespace whitted
