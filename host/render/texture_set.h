// The scene's image textures on the device: one sampled image with its mip
// chain per texture (RGBA16F, linear values: colour textures were decoded
// from sRGB on the host, io/texture_file.h), one trilinear repeating
// sampler, and the kMaxTextures descriptors of the kBindingTextures array
// (unused ones name a 1x1 dummy image, so the whole array is always valid).
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "io/texture.h"
#include "vk/context.h"
#include "vk/memory.h"

namespace whitted {

class TextureSet {
public:
    TextureSet() = default;
    TextureSet(VulkanContext& ctx, std::span<const std::shared_ptr<const TextureData>> textures);

    // gpu::kMaxTextures entries, slot order.
    std::vector<vk::DescriptorImageInfo> descriptorInfos() const;
    vk::DeviceSize bytes() const { return bytes_; }

private:
    struct Image {  // destroyed view, image, then memory
        Allocation memory;
        vk::raii::Image image{nullptr};
        vk::raii::ImageView view{nullptr};
    };
    Image upload(VulkanContext& ctx, const TextureData& texture);

    std::vector<Image> images_;  // images_[0] is the dummy, slot i is images_[i + 1]
    vk::raii::Sampler sampler_{nullptr};
    vk::DeviceSize bytes_ = 0;
};

}  // namespace whitted
