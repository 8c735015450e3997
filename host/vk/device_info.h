// What a Vulkan device is, in plain values: the device list, the render
// record and the Python module read it without including Vulkan.
#pragma once

#include <cstdint>
#include <string>

namespace whitted {

struct DeviceInfo {
    uint32_t index = 0;
    std::string name;
    std::string type;  // "discrete", "integrated", "virtual", "cpu", "other"
    std::string driver;
    uint32_t apiVersion = 0;
    bool suitable = false;  // Vulkan 1.2, a compute queue and buffer device addresses
    std::string unsuitable;  // why not, when not suitable
    // VK_KHR_ray_query and VK_KHR_acceleration_structure with their features
    // (enabled on the device when present: README "Ray queries").
    bool rayQuery = false;
};

}  // namespace whitted
