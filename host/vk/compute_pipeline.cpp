#include "vk/compute_pipeline.h"

#include <vector>

namespace whitted {

ComputePipeline createComputePipeline(const VulkanContext& ctx, std::span<const uint32_t> spirv,
                                      std::span<const vk::DescriptorType> bindings, uint32_t pushConstantSize,
                                      const vk::SpecializationInfo* specialization) {
    std::vector<DescriptorBinding> numbered;
    for (uint32_t i = 0; i < bindings.size(); ++i) numbered.push_back({i, bindings[i]});
    return createComputePipeline(ctx, spirv, numbered, pushConstantSize, specialization);
}

ComputePipeline createComputePipeline(const VulkanContext& ctx, std::span<const uint32_t> spirv,
                                      std::span<const DescriptorBinding> bindings, uint32_t pushConstantSize,
                                      const vk::SpecializationInfo* specialization) {
    ComputePipeline p;
    std::vector<vk::DescriptorSetLayoutBinding> layoutBindings;
    for (const DescriptorBinding& b : bindings)
        layoutBindings.push_back({.binding = b.binding, .descriptorType = b.type, .descriptorCount = b.count,
                                  .stageFlags = vk::ShaderStageFlagBits::eCompute});
    p.setLayout = vk::raii::DescriptorSetLayout(
        ctx.device, vk::DescriptorSetLayoutCreateInfo{.bindingCount = uint32_t(layoutBindings.size()),
                                                      .pBindings = layoutBindings.data()});

    vk::PushConstantRange range{.stageFlags = vk::ShaderStageFlagBits::eCompute, .offset = 0, .size = pushConstantSize};
    vk::DescriptorSetLayout setLayout = *p.setLayout;
    p.layout = vk::raii::PipelineLayout(ctx.device, vk::PipelineLayoutCreateInfo{.setLayoutCount = 1,
                                                                                 .pSetLayouts = &setLayout,
                                                                                 .pushConstantRangeCount = 1,
                                                                                 .pPushConstantRanges = &range});

    vk::raii::ShaderModule module(ctx.device, vk::ShaderModuleCreateInfo{.codeSize = spirv.size_bytes(),
                                                                         .pCode = spirv.data()});
    // Through the context's pipeline cache, saved at once: a later run (or
    // window) skips the driver's compilation when nothing changed.
    p.pipeline = vk::raii::Pipeline(ctx.device, ctx.pipelineCache->cache(),
                                    vk::ComputePipelineCreateInfo{.stage = {.stage = vk::ShaderStageFlagBits::eCompute,
                                                                            .module = *module,
                                                                            .pName = "main",
                                                                            .pSpecializationInfo = specialization},
                                                                  .layout = *p.layout});
    ctx.pipelineCache->save();
    return p;
}

}  // namespace whitted
