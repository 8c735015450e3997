// `whitted devices`: the Vulkan devices, and whether each can render.
#include "app/commands.h"
#include "vk/context.h"

#include <CLI/CLI.hpp>

#include <cstdio>

namespace whitted {

Command addDevicesCommand(CLI::App& app) {
    auto* cmd = app.add_subcommand("devices", "list the Vulkan devices");
    return {cmd, [] {
                for (const DeviceInfo& d : VulkanContext::listDevices())
                    std::printf("%u: %s (%s, %s, Vulkan %u.%u)%s\n", d.index, d.name.c_str(), d.type.c_str(),
                                d.driver.c_str(), VK_API_VERSION_MAJOR(d.apiVersion),
                                VK_API_VERSION_MINOR(d.apiVersion),
                                d.suitable ? "" : (" [unsuitable: " + d.unsuitable + "]").c_str());
                return kExitOk;
            }};
}

}  // namespace whitted
