// A double-precision CPU reference for ray/triangle hits, shared by tests.
#pragma once

#include "scene/scene.h"

#include <glm/glm.hpp>

#include <optional>
#include <utility>

namespace whitted::test {

// Ray/triangle in double precision, watertight: "Watertight Ray/Triangle
// Intersection", Woop, Benthin and Wald, JCGT 2(1), 2013, the algorithm of
// shaders/shapes/triangle.glsl carried out in doubles (edges inside, either
// side). The distance along `dir` as given (t > 0) and the barycentric
// weights of v0, v1, v2 at the hit; nullopt for a miss. The CPU reference of
// the watertight and ray-tree tests.
struct ExactTriangleHit {
    double t;
    glm::dvec3 barycentric;
};

inline std::optional<ExactTriangleHit> watertightTriangle(glm::dvec3 origin, glm::dvec3 dir, const Triangle& tri) {
    // The dominant axis of dir becomes z (x, y swapped to keep the winding
    // where dir[z] < 0), then the shear that turns the ray into +z.
    glm::dvec3 ad = glm::abs(dir);
    int kz = ad.x > ad.y ? (ad.x > ad.z ? 0 : 2) : (ad.y > ad.z ? 1 : 2);
    int kx = kz == 2 ? 0 : kz + 1, ky = kx == 2 ? 0 : kx + 1;
    if (dir[kz] < 0) std::swap(kx, ky);
    double sx = dir[kx] / dir[kz], sy = dir[ky] / dir[kz], sz = 1.0 / dir[kz];
    glm::dvec3 a = tri.v0 - origin, b = tri.v1 - origin, c = tri.v2 - origin;
    double ax = a[kx] - sx * a[kz], ay = a[ky] - sy * a[kz];
    double bx = b[kx] - sx * b[kz], by = b[ky] - sy * b[kz];
    double cx = c[kx] - sx * c[kz], cy = c[ky] - sy * c[kz];
    double u = cx * by - cy * bx, v = ax * cy - ay * cx, w = bx * ay - by * ax;
    if ((u < 0 || v < 0 || w < 0) && (u > 0 || v > 0 || w > 0)) return std::nullopt;
    double det = u + v + w;
    if (det == 0) return std::nullopt;
    double t = (u * sz * a[kz] + v * sz * b[kz] + w * sz * c[kz]) / det;
    if (!(t > 0)) return std::nullopt;
    return ExactTriangleHit{t, glm::dvec3(u, v, w) / det};
}

}  // namespace whitted::test
