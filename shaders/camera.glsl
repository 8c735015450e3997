#ifndef WHITTED_CAMERA_GLSL
#define WHITTED_CAMERA_GLSL
#include "device_types.h"
#include "ray.glsl"
#include "sampling.glsl"

// Camera ray through the point `pixel` (pixel units, origin at the
// top-left corner of the image), the window spanning [-1, 1]^2 of right/up.
// Pinhole: right/up are pre-scaled by the half extents of the image window
// at unit distance. Orthographic (kProjectionOrthographic): by the window's
// half extents in the scene, and every ray runs along forward from its
// point of the window through eye.
Ray generateCameraRay(vec2 pixel, vec2 imageSize, vec3 eye, vec3 forward, vec3 right, vec3 up, uint projection) {
    vec2 ndc = vec2(2.0 * pixel.x / imageSize.x - 1.0, 1.0 - 2.0 * pixel.y / imageSize.y);
    Ray ray;
    if (projection == kProjectionOrthographic) {
        ray.origin = eye + ndc.x * right + ndc.y * up;
        ray.dir = forward;
        return ray;
    }
    ray.origin = eye;
    ray.dir = normalize(forward + ndc.x * right + ndc.y * up);
    return ray;
}

// The pinhole (or orthographic) ray `pinhole` through a thin lens of radius
// apertureRadius centred on its origin, focused at focusDistance along the
// view axis (pbrt-v4 PerspectiveCamera / OrthographicCamera::GenerateRay):
// the point where the pinhole ray meets the plane of focus stays sharp, and
// the ray leaves from the lens point u (the unit square mapped to the disc
// concentrically, sampling.glsl) towards it. right and up are the camera's
// scaled frame vectors; the lens lies in their plane.
Ray thinLensRay(Ray pinhole, vec3 right, vec3 up, float apertureRadius, float focusDistance, vec2 u) {
    vec3 unitRight = normalize(right), unitUp = normalize(up);
    vec3 axis = cross(unitUp, unitRight);  // the unit view direction (right = forward x up)
    vec3 focus = pinhole.origin + pinhole.dir * (focusDistance / dot(pinhole.dir, axis));
    vec2 lens = apertureRadius * sampleDiskConcentric(u);
    Ray ray;
    ray.origin = pinhole.origin + lens.x * unitRight + lens.y * unitUp;
    ray.dir = normalize(focus - ray.origin);
    return ray;
}

#endif
