// A device's failures that no retry mends: VK_ERROR_DEVICE_LOST at a queue
// submission or a wait, and running out of device or host memory at an
// allocation. Each becomes a DeviceFailure that names the device, the
// submission or allocation, and what the device was doing (the activity
// set by whoever drives it); the command line adds the scene and exits 1,
// the Python module raises whitted.DeviceError and drops the device.
//
// Test builds (WHITTED_TEST_HOOKS) can make the Nth submission or
// allocation fail: WHITTED_INJECT_FAULT=submit:N or allocate:N, optionally
// followed by :lost, :device-memory or :host-memory (by default a
// submission is lost and an allocation runs out of device memory).
#pragma once

#include <vulkan/vulkan.hpp>

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

namespace whitted {

class DeviceFailure : public std::runtime_error {
public:
    DeviceFailure(vk::Result result, const std::string& message) : std::runtime_error(message), result_(result) {}
    vk::Result result() const { return result_; }
    bool lost() const { return result_ == vk::Result::eErrorDeviceLost; }
    // The same failure with `context` in front of its message ("scene.xml: ").
    DeviceFailure within(const std::string& context) const { return {result_, context + what()}; }

private:
    vk::Result result_;
};

// A fault to inject (test builds): the Nth submission or allocation fails.
struct InjectedFault {
    enum class At { Submit, Allocate } at = At::Submit;
    uint32_t nth = 0;
    vk::Result result = vk::Result::eErrorDeviceLost;
};

// WHITTED_INJECT_FAULT parsed; nothing when unset or in a product build.
// A malformed value throws std::invalid_argument.
std::optional<InjectedFault> injectedFaultFromEnvironment();

// Counts one device's submissions and allocations, knows what it is doing,
// and turns failures into DeviceFailure.
class DeviceEvents {
public:
    explicit DeviceEvents(std::string deviceName = {}, std::optional<InjectedFault> fault = std::nullopt)
        : deviceName_(std::move(deviceName)), fault_(fault) {}

    // Before each queue submission and each vkAllocateMemory: counts it,
    // and throws the injected fault when it is the one.
    void submission();
    void allocation(uint64_t bytes, const char* use);
    // Throws a DeviceFailure for `result` at the current submission (or
    // allocation, with its size and use).
    [[noreturn]] void failSubmission(vk::Result result) const;
    [[noreturn]] void failAllocation(vk::Result result, uint64_t bytes, const char* use) const;

    uint32_t submissions() const { return submissions_; }
    uint32_t allocations() const { return allocations_; }
    const std::string& activity() const { return activity_; }

private:
    friend class DeviceActivity;
    std::string describe(vk::Result result) const;

    std::string deviceName_;
    std::optional<InjectedFault> fault_;
    std::string activity_;
    uint32_t submissions_ = 0, allocations_ = 0;
};

// What the device does while this lives ("rendering band 2 of 5"), named by
// any failure meanwhile; the activity before it comes back after it.
class DeviceActivity {
public:
    DeviceActivity(DeviceEvents& events, std::string activity)
        : events_(events), before_(std::exchange(events.activity_, std::move(activity))) {}
    ~DeviceActivity() { events_.activity_ = std::move(before_); }
    DeviceActivity(const DeviceActivity&) = delete;
    DeviceActivity& operator=(const DeviceActivity&) = delete;

private:
    DeviceEvents& events_;
    std::string before_;
};

}  // namespace whitted
