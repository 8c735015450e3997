// A compute pipeline with one descriptor set and a push-constant block.
#pragma once

#include "vk/context.h"

#include <span>

namespace whitted {

struct ComputePipeline {
    vk::raii::DescriptorSetLayout setLayout{nullptr};
    vk::raii::PipelineLayout layout{nullptr};
    vk::raii::Pipeline pipeline{nullptr};
};

struct DescriptorBinding {
    uint32_t binding;
    vk::DescriptorType type;
    uint32_t count = 1;  // an array of descriptors when > 1
};

// `bindings` lists the set's bindings (numbers need not be contiguous);
// `specialization` (optional) sets the shader's specialization constants.
ComputePipeline createComputePipeline(const VulkanContext& ctx, std::span<const uint32_t> spirv,
                                      std::span<const DescriptorBinding> bindings, uint32_t pushConstantSize,
                                      const vk::SpecializationInfo* specialization = nullptr);

// The same with the descriptor type of each binding number 0..n-1.
ComputePipeline createComputePipeline(const VulkanContext& ctx, std::span<const uint32_t> spirv,
                                      std::span<const vk::DescriptorType> bindings, uint32_t pushConstantSize,
                                      const vk::SpecializationInfo* specialization = nullptr);

}  // namespace whitted
