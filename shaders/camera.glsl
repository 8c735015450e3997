#ifndef WHITTED_CAMERA_GLSL
#define WHITTED_CAMERA_GLSL
#include "ray.glsl"

// Pinhole camera ray through the point `pixel` (pixel units, origin at the
// top-left corner of the image). right/up are pre-scaled by the half extents
// of the image window at unit distance, so the window spans [-1, 1]^2.
Ray generateCameraRay(vec2 pixel, vec2 imageSize, vec3 eye, vec3 forward, vec3 right, vec3 up) {
    vec2 ndc = vec2(2.0 * pixel.x / imageSize.x - 1.0, 1.0 - 2.0 * pixel.y / imageSize.y);
    Ray ray;
    ray.origin = eye;
    ray.dir = normalize(forward + ndc.x * right + ndc.y * up);
    return ray;
}

#endif
