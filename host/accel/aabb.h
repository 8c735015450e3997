// Axis-aligned bounding box.
#pragma once

#include <glm/glm.hpp>

#include <limits>

namespace whitted {

struct Aabb {
    glm::vec3 min{std::numeric_limits<float>::infinity()};
    glm::vec3 max{-std::numeric_limits<float>::infinity()};

    void extend(const glm::vec3& p) {
        min = glm::min(min, p);
        max = glm::max(max, p);
    }
    void extend(const Aabb& b) {
        min = glm::min(min, b.min);
        max = glm::max(max, b.max);
    }
    bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
    bool finite() const { return glm::all(glm::lessThan(glm::abs(min), glm::vec3(1e30f))) &&
                                 glm::all(glm::lessThan(glm::abs(max), glm::vec3(1e30f))); }
    glm::vec3 center() const { return 0.5f * (min + max); }
    float surfaceArea() const {
        if (empty()) return 0.0f;
        glm::vec3 d = max - min;
        return 2.0f * (d.x * d.y + d.y * d.z + d.z * d.x);
    }
    static Aabb unbounded() {
        Aabb b;
        b.min = glm::vec3(-std::numeric_limits<float>::infinity());
        b.max = glm::vec3(std::numeric_limits<float>::infinity());
        return b;
    }
};

}  // namespace whitted
