#include "vk/device_events.h"

#include <cstdlib>
#include <string_view>

namespace whitted {

std::optional<InjectedFault> injectedFaultFromEnvironment() {
#ifdef WHITTED_TEST_HOOKS
    const char* value = std::getenv("WHITTED_INJECT_FAULT");
    if (!value || !*value) return std::nullopt;
    std::string text = value;
    auto bad = [&] {
        return std::invalid_argument("WHITTED_INJECT_FAULT=" + text +
                                     ": expected submit:N or allocate:N, optionally :lost, :device-memory or "
                                     ":host-memory");
    };
    InjectedFault fault;
    size_t colon = text.find(':');
    if (colon == std::string::npos) throw bad();
    std::string_view at = std::string_view(text).substr(0, colon);
    if (at == "submit") {
        fault.at = InjectedFault::At::Submit;
        fault.result = vk::Result::eErrorDeviceLost;
    } else if (at == "allocate") {
        fault.at = InjectedFault::At::Allocate;
        fault.result = vk::Result::eErrorOutOfDeviceMemory;
    } else {
        throw bad();
    }
    size_t end = 0;
    try {
        fault.nth = uint32_t(std::stoul(text.substr(colon + 1), &end));
    } catch (const std::logic_error&) {
        throw bad();
    }
    std::string rest = text.substr(colon + 1 + end);
    if (rest == ":lost")
        fault.result = vk::Result::eErrorDeviceLost;
    else if (rest == ":device-memory")
        fault.result = vk::Result::eErrorOutOfDeviceMemory;
    else if (rest == ":host-memory")
        fault.result = vk::Result::eErrorOutOfHostMemory;
    else if (!rest.empty() || fault.nth == 0)
        throw bad();
    return fault;
#else
    return std::nullopt;
#endif
}

void DeviceEvents::submission() {
    ++submissions_;
    if (fault_ && fault_->at == InjectedFault::At::Submit && fault_->nth == submissions_)
        failSubmission(fault_->result);
}

void DeviceEvents::allocation(uint64_t bytes, const char* use) {
    ++allocations_;
    if (fault_ && fault_->at == InjectedFault::At::Allocate && fault_->nth == allocations_)
        failAllocation(fault_->result, bytes, use);
}

std::string DeviceEvents::describe(vk::Result result) const {
    std::string device = "device '" + deviceName_ + "'";
    switch (result) {
        case vk::Result::eErrorDeviceLost: return device + " was lost (VK_ERROR_DEVICE_LOST)";
        case vk::Result::eErrorOutOfDeviceMemory:
            return device + " is out of device memory (VK_ERROR_OUT_OF_DEVICE_MEMORY)";
        case vk::Result::eErrorOutOfHostMemory: return device + " is out of host memory (VK_ERROR_OUT_OF_HOST_MEMORY)";
        default: return device + " failed (" + vk::to_string(result) + ")";
    }
}

void DeviceEvents::failSubmission(vk::Result result) const {
    std::string message = describe(result) + " at queue submission " + std::to_string(submissions_);
    if (!activity_.empty()) message += ", " + activity_;
    throw DeviceFailure(result, message);
}

void DeviceEvents::failAllocation(vk::Result result, uint64_t bytes, const char* use) const {
    std::string message = describe(result) + " at memory allocation " + std::to_string(allocations_) + " (" +
                          std::to_string(bytes) + " bytes, " + std::to_string(bytes >> 20) + " MiB, of " + use +
                          " memory)";
    if (!activity_.empty()) message += ", " + activity_;
    throw DeviceFailure(result, message);
}

}  // namespace whitted
