#include "render/texture_set.h"

#include <cstring>
#include <glm/gtc/packing.hpp>

#include "device_types.h"
#include "vk/buffer.h"

namespace whitted {

TextureSet::TextureSet(VulkanContext& ctx, std::span<const std::shared_ptr<const TextureData>> textures) {
    // Trilinear filtering with an explicit level (the ray-cone LOD,
    // shaders/texture.glsl); textures repeat.
    sampler_ = vk::raii::Sampler(ctx.device, vk::SamplerCreateInfo{.magFilter = vk::Filter::eLinear,
                                                                   .minFilter = vk::Filter::eLinear,
                                                                   .mipmapMode = vk::SamplerMipmapMode::eLinear,
                                                                   .addressModeU = vk::SamplerAddressMode::eRepeat,
                                                                   .addressModeV = vk::SamplerAddressMode::eRepeat,
                                                                   .addressModeW = vk::SamplerAddressMode::eRepeat,
                                                                   .maxLod = VK_LOD_CLAMP_NONE});
    TextureData dummy;
    dummy.name = "dummy";
    dummy.levels.push_back({1, 1, std::vector<uint16_t>(4, glm::packHalf1x16(1.0f))});
    images_.push_back(upload(ctx, dummy));
    for (const auto& texture : textures) images_.push_back(upload(ctx, *texture));
}

TextureSet::Image TextureSet::upload(VulkanContext& ctx, const TextureData& texture) {
    constexpr vk::Format kFormat = vk::Format::eR16G16B16A16Sfloat;
    Image img;
    uint32_t levels = uint32_t(texture.levels.size());
    img.image = vk::raii::Image(
        ctx.device,
        vk::ImageCreateInfo{.imageType = vk::ImageType::e2D,
                            .format = kFormat,
                            .extent = {uint32_t(texture.levels[0].width), uint32_t(texture.levels[0].height), 1},
                            .mipLevels = levels,
                            .arrayLayers = 1,
                            .samples = vk::SampleCountFlagBits::e1,
                            .tiling = vk::ImageTiling::eOptimal,
                            .usage = vk::ImageUsageFlagBits::eSampled | vk::ImageUsageFlagBits::eTransferDst,
                            .initialLayout = vk::ImageLayout::eUndefined});
    vk::MemoryRequirements req = img.image.getMemoryRequirements();
    DeviceActivity activity(*ctx.events, "uploading texture " + texture.name);
    img.memory = ctx.memory->allocate(req, MemoryUse::Device, true);
    img.image.bindMemory(img.memory.memory(), img.memory.offset());
    bytes_ += req.size;

    // Every level through one staging buffer, copied in one submission.
    vk::DeviceSize total = 0;
    for (const TextureLevel& level : texture.levels) total += level.rgba.size() * sizeof(uint16_t);
    Buffer staging = createBuffer(ctx, total, vk::BufferUsageFlagBits::eTransferSrc, MemoryUse::Upload);
    std::vector<vk::BufferImageCopy> copies;
    vk::DeviceSize offset = 0;
    for (uint32_t i = 0; i < levels; ++i) {
        const TextureLevel& level = texture.levels[i];
        std::memcpy(static_cast<char*>(staging.mapped) + offset, level.rgba.data(),
                    level.rgba.size() * sizeof(uint16_t));
        copies.push_back({.bufferOffset = offset,
                          .imageSubresource = {vk::ImageAspectFlagBits::eColor, i, 0, 1},
                          .imageExtent = {uint32_t(level.width), uint32_t(level.height), 1}});
        offset += level.rgba.size() * sizeof(uint16_t);
    }
    vk::ImageSubresourceRange all{vk::ImageAspectFlagBits::eColor, 0, levels, 0, 1};
    ctx.submitAndWait([&](vk::raii::CommandBuffer& cmd) {
        vk::ImageMemoryBarrier toTransfer{.srcAccessMask = {},
                                          .dstAccessMask = vk::AccessFlagBits::eTransferWrite,
                                          .oldLayout = vk::ImageLayout::eUndefined,
                                          .newLayout = vk::ImageLayout::eTransferDstOptimal,
                                          .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                          .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                          .image = *img.image,
                                          .subresourceRange = all};
        cmd.pipelineBarrier(vk::PipelineStageFlagBits::eTopOfPipe, vk::PipelineStageFlagBits::eTransfer, {}, nullptr,
                            nullptr, toTransfer);
        cmd.copyBufferToImage(*staging.buffer, *img.image, vk::ImageLayout::eTransferDstOptimal, copies);
        vk::ImageMemoryBarrier toShader{.srcAccessMask = vk::AccessFlagBits::eTransferWrite,
                                        .dstAccessMask = vk::AccessFlagBits::eShaderRead,
                                        .oldLayout = vk::ImageLayout::eTransferDstOptimal,
                                        .newLayout = vk::ImageLayout::eShaderReadOnlyOptimal,
                                        .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                        .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                        .image = *img.image,
                                        .subresourceRange = all};
        cmd.pipelineBarrier(vk::PipelineStageFlagBits::eTransfer, vk::PipelineStageFlagBits::eComputeShader, {},
                            nullptr, nullptr, toShader);
    });
    img.view = vk::raii::ImageView(
        ctx.device,
        vk::ImageViewCreateInfo{
            .image = *img.image, .viewType = vk::ImageViewType::e2D, .format = kFormat, .subresourceRange = all});
    return img;
}

std::vector<vk::DescriptorImageInfo> TextureSet::descriptorInfos() const {
    std::vector<vk::DescriptorImageInfo> infos;
    for (uint32_t slot = 0; slot < gpu::kMaxTextures; ++slot) {
        const Image& img = slot + 1 < images_.size() ? images_[slot + 1] : images_[0];
        infos.push_back({*sampler_, *img.view, vk::ImageLayout::eShaderReadOnlyOptimal});
    }
    return infos;
}

}  // namespace whitted
