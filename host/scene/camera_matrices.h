// A camera from and to matrices, as computer-vision tools give them: an
// intrinsic matrix K (pixels) and a camera-to-world pose, in OpenCV's or
// OpenGL's camera axes. Python's Camera.set_from_matrices / intrinsics() /
// cam_to_world() (host/python/README.md "Cameras from matrices").
//
// K's pixels are OpenCV's in both conventions: u right, v down, (0, 0) the
// centre of the top-left pixel, so a centred camera has cx = (width - 1) / 2.
// Camera axes: OpenCV x right, y down, z forward (the way the camera looks);
// OpenGL x right, y up, -z forward. cam_to_world's columns are the camera's
// x, y, z axes and its position in the scene.
#pragma once

#include "scene/scene.h"

#include <glm/glm.hpp>

namespace whitted {

enum class CameraConvention { OpenCV, OpenGL };

// The camera set from K and cam_to_world for a width x height image: eye,
// look-at (one unit along forward), up and the intrinsics; the rest of
// `base` kept (projection becomes perspective). Throws
// std::invalid_argument naming the field ("K: ...", "cam_to_world: ...",
// "width: ...") for a K with fx or fy <= 0, skew or a last row other than
// (0, 0, 1), a value not finite or beyond the scene format's ±1e6
// (xml_reader.h kMaxMagnitude, so that the scene writer's <intrinsics> loads
// back), a pose that is not a rotation and a
// translation (orthonormal to 1e-6, determinant +1, last row (0, 0, 0, 1)).
// glm matrices are column-major: K[col][row].
Camera cameraFromMatrices(const Camera& base, const glm::dmat3& K, const glm::dmat4& camToWorld, int width, int height,
                          CameraConvention convention);

// The vertical field of view (degrees) that intrinsics give at the image's
// centre for an image `height` pixels high: what Camera::verticalFovDegrees
// reads while they are set (set_from_matrices, the loader's <intrinsics>).
double intrinsicsVerticalFov(const Camera::Intrinsics& k, int height);

// K of a perspective camera: its intrinsics, or those its vertical field of
// view gives (square pixels, centred). Throws std::invalid_argument for an
// orthographic camera (no K).
glm::dmat3 cameraIntrinsicMatrix(const Camera& camera);

// The camera's pose: columns x, y, z axes (unit, orthogonal) and the eye.
glm::dmat4 cameraToWorld(const Camera& camera, CameraConvention convention);

}  // namespace whitted
