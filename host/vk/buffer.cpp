#include "vk/buffer.h"

#include <algorithm>
#include <cstring>

namespace whitted {

Buffer createBuffer(const VulkanContext& ctx, vk::DeviceSize size, vk::BufferUsageFlags usage, MemoryUse use) {
    Buffer b;
    b.size = std::max<vk::DeviceSize>(size, 16);  // zero-sized buffers are invalid
    b.buffer = vk::raii::Buffer(ctx.device, vk::BufferCreateInfo{.size = b.size, .usage = usage,
                                                                  .sharingMode = vk::SharingMode::eExclusive});
    b.allocation = ctx.memory->allocate(b.buffer.getMemoryRequirements(), use);
    b.buffer.bindMemory(b.allocation.memory(), b.allocation.offset());
    b.mapped = b.allocation.mapped();
    if (usage & vk::BufferUsageFlagBits::eShaderDeviceAddress)
        b.address = ctx.device.getBufferAddress({.buffer = *b.buffer});
    return b;
}

Buffer createDeviceBuffer(VulkanContext& ctx, const void* data, vk::DeviceSize size, vk::BufferUsageFlags usage) {
    // A device that works in host memory (lavapipe, an integrated GPU) is
    // written directly: a staging copy would hold the data twice (640 MB more
    // for a 10M-triangle mesh).
    if (data && size > 0 && ctx.memory->unified()) {
        Buffer direct = createBuffer(ctx, size, usage, MemoryUse::Shared);
        std::memcpy(direct.mapped, data, size);
        return direct;
    }
    Buffer device = createBuffer(ctx, size, usage | vk::BufferUsageFlagBits::eTransferDst, MemoryUse::Device);
    if (data && size > 0) {
        Buffer staging = createBuffer(ctx, size, vk::BufferUsageFlagBits::eTransferSrc, MemoryUse::Upload);
        std::memcpy(staging.mapped, data, size);
        ctx.submitAndWait([&](vk::raii::CommandBuffer& cmd) {
            cmd.copyBuffer(*staging.buffer, *device.buffer, vk::BufferCopy{0, 0, size});
        });
    } else {
        ctx.submitAndWait([&](vk::raii::CommandBuffer& cmd) { cmd.fillBuffer(*device.buffer, 0, VK_WHOLE_SIZE, 0); });
    }
    return device;
}

void readBuffer(VulkanContext& ctx, const Buffer& source, void* destination, vk::DeviceSize size) {
    Buffer staging = createBuffer(ctx, size, vk::BufferUsageFlagBits::eTransferDst, MemoryUse::Readback);
    ctx.submitAndWait([&](vk::raii::CommandBuffer& cmd) {
        // Earlier shader or transfer writes to the source come first.
        vk::MemoryBarrier fromWriters{.srcAccessMask = vk::AccessFlagBits::eShaderWrite | vk::AccessFlagBits::eTransferWrite,
                                      .dstAccessMask = vk::AccessFlagBits::eTransferRead};
        cmd.pipelineBarrier(vk::PipelineStageFlagBits::eComputeShader | vk::PipelineStageFlagBits::eTransfer,
                            vk::PipelineStageFlagBits::eTransfer, {}, fromWriters, nullptr, nullptr);
        cmd.copyBuffer(*source.buffer, *staging.buffer, vk::BufferCopy{0, 0, size});
        // Make the copy visible to host reads after the fence.
        vk::MemoryBarrier toHost{.srcAccessMask = vk::AccessFlagBits::eTransferWrite,
                                 .dstAccessMask = vk::AccessFlagBits::eHostRead};
        cmd.pipelineBarrier(vk::PipelineStageFlagBits::eTransfer, vk::PipelineStageFlagBits::eHost, {}, toHost,
                            nullptr, nullptr);
    });
    std::memcpy(destination, staging.mapped, size);
}

MirroredBuffer::MirroredBuffer(VulkanContext& ctx, vk::DeviceSize size, vk::BufferUsageFlags usage) {
    if (ctx.memory->unified()) {
        device_ = createBuffer(ctx, size, usage, MemoryUse::Shared);
        std::memset(device_.mapped, 0, device_.size);
        return;
    }
    using Usage = vk::BufferUsageFlagBits;
    device_ = createBuffer(ctx, size, usage | Usage::eTransferSrc | Usage::eTransferDst, MemoryUse::Device);
    // One twin for both directions: upload memory is host-coherent, and
    // the host reads these small buffers once a submission.
    host_ = createBuffer(ctx, size, Usage::eTransferSrc | Usage::eTransferDst, MemoryUse::Readback);
    std::memset(host_.mapped, 0, host_.size);
    ctx.submitAndWait([&](vk::raii::CommandBuffer& cmd) { cmd.fillBuffer(*device_.buffer, 0, VK_WHOLE_SIZE, 0); });
}

void MirroredBuffer::recordUpload(const vk::raii::CommandBuffer& cmd, vk::DeviceSize bytes) const {
    if (!staged() || bytes == 0) return;
    // The host's writes before the submission are visible to transfers; the
    // shader's earlier reads of the old contents come first.
    vk::MemoryBarrier before{.srcAccessMask = vk::AccessFlagBits::eShaderRead | vk::AccessFlagBits::eShaderWrite,
                             .dstAccessMask = vk::AccessFlagBits::eTransferWrite};
    cmd.pipelineBarrier(vk::PipelineStageFlagBits::eComputeShader, vk::PipelineStageFlagBits::eTransfer, {}, before,
                        nullptr, nullptr);
    cmd.copyBuffer(*host_.buffer, *device_.buffer, vk::BufferCopy{0, 0, std::min(bytes, size())});
    vk::MemoryBarrier after{.srcAccessMask = vk::AccessFlagBits::eTransferWrite,
                            .dstAccessMask = vk::AccessFlagBits::eShaderRead | vk::AccessFlagBits::eShaderWrite};
    cmd.pipelineBarrier(vk::PipelineStageFlagBits::eTransfer, vk::PipelineStageFlagBits::eComputeShader, {}, after,
                        nullptr, nullptr);
}

void MirroredBuffer::recordDownload(const vk::raii::CommandBuffer& cmd, vk::DeviceSize bytes) const {
    if (!staged() || bytes == 0) return;
    vk::MemoryBarrier after{.srcAccessMask = vk::AccessFlagBits::eShaderWrite | vk::AccessFlagBits::eTransferWrite,
                            .dstAccessMask = vk::AccessFlagBits::eTransferRead};
    cmd.pipelineBarrier(vk::PipelineStageFlagBits::eComputeShader | vk::PipelineStageFlagBits::eTransfer,
                        vk::PipelineStageFlagBits::eTransfer, {}, after, nullptr, nullptr);
    cmd.copyBuffer(*device_.buffer, *host_.buffer, vk::BufferCopy{0, 0, std::min(bytes, size())});
    vk::MemoryBarrier toHost{.srcAccessMask = vk::AccessFlagBits::eTransferWrite,
                             .dstAccessMask = vk::AccessFlagBits::eHostRead};
    cmd.pipelineBarrier(vk::PipelineStageFlagBits::eTransfer, vk::PipelineStageFlagBits::eHost, {}, toHost, nullptr,
                        nullptr);
}

void MirroredBuffer::recordZero(const vk::raii::CommandBuffer& cmd) const {
    std::memset(host(), 0, size());
    if (!staged()) return;
    vk::MemoryBarrier before{.srcAccessMask = vk::AccessFlagBits::eShaderRead | vk::AccessFlagBits::eShaderWrite,
                             .dstAccessMask = vk::AccessFlagBits::eTransferWrite};
    cmd.pipelineBarrier(vk::PipelineStageFlagBits::eComputeShader, vk::PipelineStageFlagBits::eTransfer, {}, before,
                        nullptr, nullptr);
    cmd.fillBuffer(*device_.buffer, 0, VK_WHOLE_SIZE, 0);
}

}  // namespace whitted
