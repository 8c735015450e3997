#include "vk/context.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <string_view>
#include <utility>
#include <stdexcept>

namespace whitted {

bool validationFromEnvironment() {
    const char* v = std::getenv("WHITTED_VALIDATION");
    return v && *v && std::string(v) != "0";
}

bool discreteMemoryFromEnvironment() {
#ifdef WHITTED_TEST_HOOKS
    const char* v = std::getenv("WHITTED_DISCRETE_MEMORY");
    return v && *v && std::string(v) != "0";
#else
    return false;
#endif
}
namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

std::string deviceTypeName(vk::PhysicalDeviceType type) {
    switch (type) {
        case vk::PhysicalDeviceType::eDiscreteGpu: return "discrete";
        case vk::PhysicalDeviceType::eIntegratedGpu: return "integrated";
        case vk::PhysicalDeviceType::eVirtualGpu: return "virtual";
        case vk::PhysicalDeviceType::eCpu: return "cpu";
        default: return "other";
    }
}

// Preference when no device is named: a real GPU first, lavapipe last.
int deviceTypeRank(vk::PhysicalDeviceType type) {
    switch (type) {
        case vk::PhysicalDeviceType::eDiscreteGpu: return 4;
        case vk::PhysicalDeviceType::eIntegratedGpu: return 3;
        case vk::PhysicalDeviceType::eVirtualGpu: return 2;
        case vk::PhysicalDeviceType::eCpu: return 1;
        default: return 0;
    }
}

// A queue family that computes: one that does not also draw where the
// device has it (a GPU's asynchronous compute queue, where acceleration
// structures are best built and dispatches never wait behind drawing).
std::optional<uint32_t> findComputeQueueFamily(const vk::raii::PhysicalDevice& device) {
    auto families = device.getQueueFamilyProperties();
    std::optional<uint32_t> universal;
    for (uint32_t i = 0; i < families.size(); ++i) {
        if (!(families[i].queueFlags & vk::QueueFlagBits::eCompute)) continue;
        if (!(families[i].queueFlags & vk::QueueFlagBits::eGraphics)) return i;
        if (!universal) universal = i;
    }
    return universal;
}

// The extensions tracing through ray queries needs (VK_KHR_acceleration_structure
// requires VK_KHR_deferred_host_operations; its other dependencies and
// VK_KHR_ray_query's are core in Vulkan 1.2).
constexpr const char* kRayQueryExtensions[] = {VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME,
                                               VK_KHR_RAY_QUERY_EXTENSION_NAME,
                                               VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME};

bool hasExtension(const std::vector<vk::ExtensionProperties>& extensions, std::string_view name) {
    return std::any_of(extensions.begin(), extensions.end(), [&](const vk::ExtensionProperties& e) {
        return std::string_view(e.extensionName.data()) == name;
    });
}

// A device that works in host memory (lavapipe, an integrated GPU): a
// memory type both device-local and host-visible holds what the shader
// and the host share, with no staging copy.
bool hasUnifiedMemory(const vk::raii::PhysicalDevice& device) {
    vk::PhysicalDeviceType type = device.getProperties().deviceType;
    if (type != vk::PhysicalDeviceType::eCpu && type != vk::PhysicalDeviceType::eIntegratedGpu) return false;
    auto shared = vk::MemoryPropertyFlagBits::eDeviceLocal | vk::MemoryPropertyFlagBits::eHostVisible |
                  vk::MemoryPropertyFlagBits::eHostCoherent;
    auto memory = device.getMemoryProperties();
    for (uint32_t i = 0; i < memory.memoryTypeCount; ++i)
        if ((memory.memoryTypes[i].propertyFlags & shared) == shared) return true;
    return false;
}

bool hasRayQuery(const vk::raii::PhysicalDevice& device) {
    auto extensions = device.enumerateDeviceExtensionProperties();
    for (const char* wanted : kRayQueryExtensions)
        if (!hasExtension(extensions, wanted)) return false;
    auto features = device.getFeatures2<vk::PhysicalDeviceFeatures2, vk::PhysicalDeviceAccelerationStructureFeaturesKHR,
                                        vk::PhysicalDeviceRayQueryFeaturesKHR>();
    return features.get<vk::PhysicalDeviceAccelerationStructureFeaturesKHR>().accelerationStructure &&
           features.get<vk::PhysicalDeviceRayQueryFeaturesKHR>().rayQuery;
}

DeviceInfo describe(const vk::raii::PhysicalDevice& device, uint32_t index) {
    auto props = device.getProperties2<vk::PhysicalDeviceProperties2, vk::PhysicalDeviceDriverProperties,
                                       vk::PhysicalDeviceSubgroupProperties>();
    const auto& p = props.get<vk::PhysicalDeviceProperties2>().properties;
    const auto& d = props.get<vk::PhysicalDeviceDriverProperties>();
    const auto& subgroup = props.get<vk::PhysicalDeviceSubgroupProperties>();
    DeviceInfo info;
    info.index = index;
    info.name = p.deviceName.data();
    info.type = deviceTypeName(p.deviceType);
    info.driver = std::string(d.driverName.data()) + " " + d.driverInfo.data();
    info.apiVersion = p.apiVersion;
    // The shader reads the scene through buffer device addresses (core in
    // Vulkan 1.2, optional there but on every Vulkan 1.2 desktop driver and lavapipe).
    if (p.apiVersion < VK_API_VERSION_1_2)
        info.unsuitable = "needs Vulkan 1.2";
    else if (!findComputeQueueFamily(device))
        info.unsuitable = "has no compute queue";
    else if (!device.getFeatures2<vk::PhysicalDeviceFeatures2, vk::PhysicalDeviceVulkan12Features>()
                  .get<vk::PhysicalDeviceVulkan12Features>()
                  .bufferDeviceAddress)
        info.unsuitable = "lacks bufferDeviceAddress (Vulkan 1.2 feature)";
    // The ray counters are summed across a subgroup before one atomic add
    // (shaders/whitted.comp): optional in Vulkan, on every desktop GPU and lavapipe.
    else if (!(subgroup.supportedStages & vk::ShaderStageFlagBits::eCompute) ||
             !(subgroup.supportedOperations & vk::SubgroupFeatureFlagBits::eArithmetic))
        info.unsuitable = "lacks subgroup arithmetic in compute shaders";
    info.suitable = info.unsuitable.empty();
    info.rayQuery = info.suitable && hasRayQuery(device);
    return info;
}

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

VKAPI_ATTR VkBool32 VKAPI_CALL debugCallback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                             VkDebugUtilsMessageTypeFlagsEXT,
                                             const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
    auto* counter = static_cast<std::atomic<uint32_t>*>(user);
    counter->fetch_add(1);
    const char* level = severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT ? "error" : "warning";
    std::fprintf(stderr, "whitted: validation %s: %s\n", level, data->pMessage);
    return VK_FALSE;
}

vk::raii::Instance createInstance(const vk::raii::Context& context, bool validation,
                                  const std::vector<std::string>& extraExtensions = {}) {
    vk::ApplicationInfo app{.pApplicationName = "whitted",
                            .applicationVersion = VK_MAKE_VERSION(0, 1, 0),
                            .pEngineName = "whitted",
                            .apiVersion = VK_API_VERSION_1_2};
    std::vector<const char*> layers;
    std::vector<const char*> extensions;
    for (const std::string& e : extraExtensions) extensions.push_back(e.c_str());
    if (validation) {
        auto available = context.enumerateInstanceLayerProperties();
        bool found = std::any_of(available.begin(), available.end(), [](const vk::LayerProperties& l) {
            return std::string_view(l.layerName.data()) == kValidationLayer;
        });
        if (!found)
            throw std::runtime_error(std::string("validation was requested but ") + kValidationLayer +
                                     " is not installed (Debian package vulkan-validationlayers)");
        layers.push_back(kValidationLayer);
        extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    }
    return vk::raii::Instance(context, vk::InstanceCreateInfo{
                                           .pApplicationInfo = &app,
                                           .enabledLayerCount = uint32_t(layers.size()),
                                           .ppEnabledLayerNames = layers.data(),
                                           .enabledExtensionCount = uint32_t(extensions.size()),
                                           .ppEnabledExtensionNames = extensions.data()});
}

// Which memory extensions the device was made with (vk/memory.h).
struct MemoryExtensions {
    bool priorities = false, pageable = false;
};

// The logical device: one queue of `family`, buffer device addresses, the
// texture array's non-uniform indexing where offered, ray queries when
// `rayQuery`, memory priorities where offered (`enabled` says).
vk::raii::Device createDevice(const vk::raii::PhysicalDevice& physical, uint32_t family,
                              std::vector<const char*> deviceExtensions, bool rayQuery, MemoryExtensions& enabled) {
    float priority = 1.0f;
    vk::DeviceQueueCreateInfo queueInfo{.queueFamilyIndex = family, .queueCount = 1, .pQueuePriorities = &priority};
    vk::PhysicalDeviceVulkan12Features features12{.bufferDeviceAddress = VK_TRUE};  // scene arrays (shaders/scene.glsl)
    // The texture array is indexed by a material's slot, which varies across
    // an invocation group (shaders/texture.glsl, nonuniformEXT).
    features12.shaderSampledImageArrayNonUniformIndexing =
        physical.getFeatures2<vk::PhysicalDeviceFeatures2, vk::PhysicalDeviceVulkan12Features>()
            .get<vk::PhysicalDeviceVulkan12Features>()
            .shaderSampledImageArrayNonUniformIndexing;
    void* chain = &features12;
    vk::PhysicalDeviceRayQueryFeaturesKHR rayQueryFeatures{.rayQuery = VK_TRUE};
    vk::PhysicalDeviceAccelerationStructureFeaturesKHR accelerationFeatures{.accelerationStructure = VK_TRUE};
    if (rayQuery) {
        deviceExtensions.insert(deviceExtensions.end(), std::begin(kRayQueryExtensions), std::end(kRayQueryExtensions));
        rayQueryFeatures.pNext = std::exchange(chain, &rayQueryFeatures);
        accelerationFeatures.pNext = std::exchange(chain, &accelerationFeatures);
    }
    // Memory priorities where offered (vk/memory.h gives each block one),
    // and pageable device-local memory with them: the driver may then move
    // low-priority memory out of the device when it runs short.
    auto extensions = physical.enumerateDeviceExtensionProperties();
    auto offered = physical.getFeatures2<vk::PhysicalDeviceFeatures2, vk::PhysicalDeviceMemoryPriorityFeaturesEXT,
                                         vk::PhysicalDevicePageableDeviceLocalMemoryFeaturesEXT>();
    vk::PhysicalDeviceMemoryPriorityFeaturesEXT priorityFeatures{.memoryPriority = VK_TRUE};
    vk::PhysicalDevicePageableDeviceLocalMemoryFeaturesEXT pageableFeatures{.pageableDeviceLocalMemory = VK_TRUE};
    enabled.priorities = hasExtension(extensions, VK_EXT_MEMORY_PRIORITY_EXTENSION_NAME) &&
                         offered.get<vk::PhysicalDeviceMemoryPriorityFeaturesEXT>().memoryPriority;
    enabled.pageable = enabled.priorities &&
                       hasExtension(extensions, VK_EXT_PAGEABLE_DEVICE_LOCAL_MEMORY_EXTENSION_NAME) &&
                       offered.get<vk::PhysicalDevicePageableDeviceLocalMemoryFeaturesEXT>().pageableDeviceLocalMemory;
    if (enabled.priorities) {
        deviceExtensions.push_back(VK_EXT_MEMORY_PRIORITY_EXTENSION_NAME);
        priorityFeatures.pNext = std::exchange(chain, &priorityFeatures);
        if (enabled.pageable) {
            deviceExtensions.push_back(VK_EXT_PAGEABLE_DEVICE_LOCAL_MEMORY_EXTENSION_NAME);
            pageableFeatures.pNext = std::exchange(chain, &pageableFeatures);
        }
    }
    return vk::raii::Device(physical, vk::DeviceCreateInfo{.pNext = chain,
                                                           .queueCreateInfoCount = 1,
                                                           .pQueueCreateInfos = &queueInfo,
                                                           .enabledExtensionCount = uint32_t(deviceExtensions.size()),
                                                           .ppEnabledExtensionNames = deviceExtensions.data()});
}

}  // namespace

std::vector<DeviceInfo> VulkanContext::listDevices() {
    vk::raii::Context context;
    vk::raii::Instance instance = createInstance(context, false);
    vk::raii::PhysicalDevices devices(instance);
    std::vector<DeviceInfo> infos;
    for (uint32_t i = 0; i < devices.size(); ++i) infos.push_back(describe(devices[i], i));
    return infos;
}

VulkanContext::VulkanContext(const ContextOptions& options) {
    instance = createInstance(context, options.validation, options.instanceExtensions);
    if (options.validation) {
        using Severity = vk::DebugUtilsMessageSeverityFlagBitsEXT;
        using Type = vk::DebugUtilsMessageTypeFlagBitsEXT;
        messenger = vk::raii::DebugUtilsMessengerEXT(
            instance, vk::DebugUtilsMessengerCreateInfoEXT{
                          .messageSeverity = Severity::eWarning | Severity::eError,
                          .messageType = Type::eGeneral | Type::eValidation | Type::ePerformance,
                          .pfnUserCallback = debugCallback,
                          .pUserData = validationMessages_.get()});
    }

    // Device choice: the one named, else the best-ranked suitable one.
    vk::raii::PhysicalDevices devices(instance);
    std::optional<uint32_t> chosen;
    if (!options.deviceName.empty()) {
        bool isIndex = std::all_of(options.deviceName.begin(), options.deviceName.end(),
                                   [](unsigned char c) { return std::isdigit(c); });
        for (uint32_t i = 0; i < devices.size() && !chosen; ++i) {
            DeviceInfo d = describe(devices[i], i);
            bool match = isIndex ? std::to_string(i) == options.deviceName
                                 : lower(d.name).find(lower(options.deviceName)) != std::string::npos;
            if (match) {
                if (!d.suitable) throw std::runtime_error("device '" + d.name + "' is unsuitable: it " + d.unsuitable);
                chosen = i;
            }
        }
        if (!chosen)
            throw std::runtime_error("no Vulkan device matches '" + options.deviceName +
                                     "' (run `whitted devices` to list them)");
    } else {
        int bestRank = -1;
        for (uint32_t i = 0; i < devices.size(); ++i) {
            DeviceInfo d = describe(devices[i], i);
            int rank = deviceTypeRank(devices[i].getProperties().deviceType);
            if (d.suitable && rank > bestRank) {
                bestRank = rank;
                chosen = i;
            }
        }
        if (!chosen)
            throw std::runtime_error(
                "no Vulkan 1.2 device with a compute queue and bufferDeviceAddress was found (install "
                "mesa-vulkan-drivers for lavapipe)");
    }
    physicalDevice = std::move(devices[*chosen]);
    info_ = describe(physicalDevice, *chosen);

    queueFamily = *findComputeQueueFamily(physicalDevice);
    std::vector<const char*> deviceExtensions;
    if (options.canPresent) {
        // One queue for tracing, blits and presentation.
        auto families = physicalDevice.getQueueFamilyProperties();
        auto wanted = vk::QueueFlagBits::eCompute | vk::QueueFlagBits::eGraphics;
        std::optional<uint32_t> presenting;
        for (uint32_t i = 0; i < families.size() && !presenting; ++i)
            if ((families[i].queueFlags & wanted) == wanted &&
                options.canPresent(*instance, *physicalDevice, i))
                presenting = i;
        if (!presenting)
            throw std::runtime_error("device '" + info_.name + "' has no queue that computes, draws and presents to the window");
        queueFamily = *presenting;
        deviceExtensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
    }
    MemoryExtensions memoryExtensions;
    device = createDevice(physicalDevice, queueFamily, deviceExtensions, info_.rayQuery, memoryExtensions);
    queue = vk::raii::Queue(device, queueFamily, 0);
    // One-time command buffers (submitAndWait), freed after their
    // submission; whoever reuses one has a pool of its own and resets that.
    commandPool = vk::raii::CommandPool(device, vk::CommandPoolCreateInfo{
                                                    .flags = vk::CommandPoolCreateFlagBits::eTransient,
                                                    .queueFamilyIndex = queueFamily});
    pipelineCache = std::make_unique<PipelineCache>(
        device, physicalDevice.getProperties(),
        options.pipelineCacheFolder ? *options.pipelineCacheFolder : pipelineCacheFolderFromEnvironment());
    events = std::make_unique<DeviceEvents>(info_.name, injectedFaultFromEnvironment());
    bool discrete = options.discreteMemory.value_or(discreteMemoryFromEnvironment());
    memory = std::make_unique<MemoryAllocator>(
        physicalDevice, device,
        MemoryOptions{.unified = !discrete && hasUnifiedMemory(physicalDevice),
                      .priorities = memoryExtensions.priorities,
                      .pageable = memoryExtensions.pageable},
        events.get());
}

void VulkanContext::submit(const vk::SubmitInfo& info, vk::Fence fence) const {
    events->submission();
    try {
        queue.submit(info, fence);
    } catch (const vk::SystemError& e) {
        events->failSubmission(vk::Result(e.code().value()));
    }
}

void VulkanContext::waitForFence(vk::Fence fence) const {
    // vk::raii turns VK_ERROR_DEVICE_LOST and friends into vk::SystemError.
    vk::Result result;
    try {
        result = device.waitForFences(fence, VK_TRUE, UINT64_MAX);
    } catch (const vk::SystemError& e) {
        events->failSubmission(vk::Result(e.code().value()));
    }
    if (result != vk::Result::eSuccess) throw std::runtime_error("vkWaitForFences: " + vk::to_string(result));
}

}  // namespace whitted
