// What every loaded scene keeps, whichever reader made it (scenes/README.md
// "Scene files"): the checks the fuzz targets under tools/fuzz/ apply to a
// scene a reader accepted. A broken promise is __builtin_trap, which
// libFuzzer records as a finding.
#pragma once

#include "scene/scene.h"

#include "device_types.h"

#include <cmath>
#include <type_traits>
#include <variant>

namespace whitted::fuzz {

constexpr double kMaxMagnitude = 1e6;  // every number the loader accepts is within ±1e6

inline void check(bool ok) {
    if (!ok) __builtin_trap();
}

inline void checkValue(double v) { check(std::isfinite(v) && std::abs(v) <= 4 * kMaxMagnitude); }
inline void checkVector(const glm::dvec3& v) {
    for (int i = 0; i < 3; ++i) checkValue(v[i]);
}
inline void checkUnit(const glm::dvec3& v) {
    checkVector(v);
    check(std::abs(glm::length(v) - 1.0) < 1e-9);
}
inline void checkInUnitInterval(double v) { check(v >= 0 && v <= 1); }
inline void checkTriangle(const Triangle& t) {
    checkVector(t.v0);
    checkVector(t.v1);
    checkVector(t.v2);
    check(glm::length(glm::cross(t.v1 - t.v0, t.v2 - t.v0)) > 0);  // degenerate ones are refused or skipped
}

inline void checkScene(const Scene& scene) {
    const Camera& c = scene.camera;
    checkVector(c.eye);
    checkVector(c.windowCenter);
    checkUnit(c.up);
    check(glm::length(c.windowCenter - c.eye) > 0);
    check(c.verticalFovDegrees > 0 && c.verticalFovDegrees < 180);
    constexpr int maxSide = int(gpu::kMaxImageSide);
    check(c.width >= 1 && c.width <= maxSide && c.height >= 1 && c.height <= maxSide);
    checkVector(scene.ambientLight);
    for (const Light& l : scene.lights) {
        checkVector(l.position);
        checkVector(l.color);
        for (int i = 0; i < 3; ++i) check(l.color[i] >= 0);
    }
    if (const std::optional<Environment>& e = scene.environment) {
        for (const glm::dvec3& c : {e->color, e->zenith, e->horizon, e->ground}) {
            checkVector(c);
            for (int i = 0; i < 3; ++i) check(c[i] >= 0);
        }
        check(std::isfinite(e->intensity) && e->intensity >= 0);
        check(std::abs(e->rotationDegrees) <= 360);
        check(e->shadowSamples >= 0 && e->shadowSamples <= 256);
        check((e->kind == Environment::Kind::Image) == (e->image != nullptr));
    }
    for (const Object& o : scene.objects) {
        const Material& m = o.material;
        for (int i = 0; i < 3; ++i) {
            checkInUnitInterval(m.diffuseColor[i]);
            checkInUnitInterval(m.specularColor[i]);
        }
        for (double k : {m.ambient, m.diffuse, m.specular, m.reflection, m.transmission}) checkInUnitInterval(k);
        check(m.shininess > 0 && m.shininess <= 1e5);
        check(m.ior >= 0.1 && m.ior <= 10);
        std::visit(
            [](const auto& s) {
                using T = std::decay_t<decltype(s)>;
                if constexpr (std::is_same_v<T, Sphere>) {
                    checkVector(s.center);
                    check(s.radius > 0);
                } else if constexpr (std::is_same_v<T, Cylinder>) {
                    checkVector(s.base);
                    checkUnit(s.axis);
                    check(s.radius > 0 && s.height > 0);
                } else if constexpr (std::is_same_v<T, Plane>) {
                    checkVector(s.point);
                    checkUnit(s.normal);
                } else if constexpr (std::is_same_v<T, Triangle>) {
                    checkTriangle(s);
                } else if constexpr (std::is_same_v<T, Box>) {
                    checkVector(s.min);
                    checkVector(s.max);
                    for (int i = 0; i < 3; ++i) check(s.min[i] < s.max[i]);
                } else if constexpr (std::is_same_v<T, Mesh>) {
                    check(!s.triangles.empty());
                    for (const Triangle& t : s.triangles) checkTriangle(t);
                    check(s.normals.empty() || s.normals.size() == s.triangles.size());
                    for (const auto& n : s.normals)
                        for (const glm::dvec3& v : n) checkUnit(v);
                } else if constexpr (std::is_same_v<T, Csg>) {
                    check(s.children.size() >= 2);
                }
            },
            o.shape);
    }
    // Instances (scenes/README.md "Instances"): prototypes of meshes and
    // triangles only, none empty; each instance names one, its transform
    // finite and invertible.
    for (const Prototype& p : scene.prototypes) {
        check(!p.objects.empty());
        for (const Object& o : p.objects)
            check(std::holds_alternative<Mesh>(o.shape) || std::holds_alternative<Triangle>(o.shape));
    }
    for (const Instance& instance : scene.instances) {
        check(instance.prototype < scene.prototypes.size());
        for (int col = 0; col < 4; ++col) checkVector(glm::dvec3(instance.worldFromObject[col]));
        check(glm::determinant(glm::dmat3(instance.worldFromObject)) != 0);
    }
}

}  // namespace whitted::fuzz
