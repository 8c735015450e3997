// libFuzzer target for the XML scene loader (tools/run_fuzzer.sh builds and
// runs it). Whatever the bytes, loadSceneFromString must either refuse them
// with a SceneError or return a scene that keeps the loader's promises
// (scenes/README.md "Scene files"). Anything else is a finding: another exception
// (std::terminate aborts), a crash, an AddressSanitizer or
// UndefinedBehaviorSanitizer report, a scene with a non-finite or
// out-of-range value (__builtin_trap), a hang or runaway memory.
#include "scene/scene_loader.h"

#include "device_types.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <type_traits>
#include <variant>

namespace {

using namespace whitted;

constexpr double kMaxMagnitude = 1e6;  // every number the loader accepts is within ±1e6

void check(bool ok) {
    if (!ok) __builtin_trap();
}

void checkValue(double v) { check(std::isfinite(v) && std::abs(v) <= 4 * kMaxMagnitude); }
void checkVector(const glm::dvec3& v) {
    for (int i = 0; i < 3; ++i) checkValue(v[i]);
}
void checkUnit(const glm::dvec3& v) {
    checkVector(v);
    check(std::abs(glm::length(v) - 1.0) < 1e-9);
}
void checkInUnitInterval(double v) { check(v >= 0 && v <= 1); }
void checkTriangle(const Triangle& t) {
    checkVector(t.v0);
    checkVector(t.v1);
    checkVector(t.v2);
    check(glm::length(glm::cross(t.v1 - t.v0, t.v2 - t.v0)) > 0);  // degenerate ones are refused or skipped
}

void checkScene(const Scene& scene) {
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
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::string_view xml(reinterpret_cast<const char*>(data), size);
    try {
        checkScene(loadSceneFromString(xml, "fuzz.xml"));
    } catch (const SceneError& e) {
        // The refusal must name the file and say something.
        check(e.file() == "fuzz.xml" && !e.message().empty() && e.line() >= 0);
    }
    return 0;
}
