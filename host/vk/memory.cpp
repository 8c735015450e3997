#include "vk/memory.h"

#include "vk/device_events.h"

#include <algorithm>
#include <iterator>
#include <stdexcept>

namespace whitted {

// One vkAllocateMemory allocation and its free ranges (offset -> size).
struct MemoryBlock {
    vk::raii::DeviceMemory memory{nullptr};
    vk::DeviceSize size = 0;
    vk::DeviceSize used = 0;
    void* mapped = nullptr;
    bool dedicated = false;  // one request's own block, freed with it
    std::map<vk::DeviceSize, vk::DeviceSize> free;
};

namespace {

using Property = vk::MemoryPropertyFlagBits;

// The blocks' priorities (VK_EXT_memory_priority, 0 to 1): what shaders
// read and write at every sample stays resident first; staging least.
float priorityOf(MemoryUse use) {
    switch (use) {
        case MemoryUse::Device:
        case MemoryUse::Shared: return 1.0f;
        case MemoryUse::Readback: return 0.5f;
        case MemoryUse::Upload: break;
    }
    return 0.25f;
}

bool mappedUse(MemoryUse use) { return use != MemoryUse::Device; }

vk::DeviceSize alignUp(vk::DeviceSize value, vk::DeviceSize alignment) {
    return (value + alignment - 1) / alignment * alignment;
}

}  // namespace

const char* memoryUseName(MemoryUse use) {
    switch (use) {
        case MemoryUse::Device: return "device-local";
        case MemoryUse::Shared: return "shared device-local";
        case MemoryUse::Upload: return "upload";
        case MemoryUse::Readback: return "read-back";
    }
    return "?";
}

Allocation& Allocation::operator=(Allocation&& other) noexcept {
    if (this != &other) {
        release();
        owner_ = std::exchange(other.owner_, nullptr);
        block_ = std::exchange(other.block_, nullptr);
        offset_ = other.offset_;
        size_ = other.size_;
    }
    return *this;
}

vk::DeviceMemory Allocation::memory() const { return block_ ? *block_->memory : vk::DeviceMemory{}; }

void* Allocation::mapped() const {
    return block_ && block_->mapped ? static_cast<char*>(block_->mapped) + offset_ : nullptr;
}

void Allocation::release() {
    if (owner_ && block_) owner_->free(block_, offset_, size_);
    owner_ = nullptr;
    block_ = nullptr;
}

MemoryAllocator::MemoryAllocator(const vk::raii::PhysicalDevice& physical, const vk::raii::Device& device,
                                 MemoryOptions options, DeviceEvents* events)
    : device_(device), properties_(physical.getMemoryProperties()), options_(options), events_(events) {}

MemoryAllocator::~MemoryAllocator() = default;

// A type allowed by `typeBits` for `use`. Required: device-local for the
// device's uses, host-visible and coherent for the host's, both for Shared.
// Preferred: device memory that the host cannot see (on a discrete GPU the
// host-visible part of its memory is small), and host memory outside the
// device (read-back also cached).
uint32_t MemoryAllocator::memoryType(uint32_t typeBits, MemoryUse use) const {
    vk::MemoryPropertyFlags host = Property::eHostVisible | Property::eHostCoherent;
    vk::MemoryPropertyFlags required, unwanted, wanted;
    switch (use) {
        case MemoryUse::Device:
            required = Property::eDeviceLocal;
            unwanted = Property::eHostVisible;
            break;
        case MemoryUse::Shared: required = host | Property::eDeviceLocal; break;
        case MemoryUse::Upload:
            required = host;
            unwanted = Property::eDeviceLocal;
            break;
        case MemoryUse::Readback:
            required = host;
            wanted = Property::eHostCached;
            unwanted = Property::eDeviceLocal;
            break;
    }
    if (use == MemoryUse::Shared && !options_.unified)
        throw std::logic_error("shared device-local memory asked for on a device without unified memory");
    std::optional<uint32_t> best;
    int bestScore = -1;
    for (uint32_t i = 0; i < properties_.memoryTypeCount; ++i) {
        vk::MemoryPropertyFlags flags = properties_.memoryTypes[i].propertyFlags;
        if (!(typeBits & (1u << i)) || (flags & required) != required) continue;
        int score = ((flags & wanted) == wanted ? 2 : 0) + (!(flags & unwanted) ? 1 : 0);
        if (score > bestScore) bestScore = score, best = i;
    }
    if (!best)
        throw std::runtime_error(std::string("no Vulkan memory type fits ") + memoryUseName(use) + " memory (" +
                                 vk::to_string(required) + ")");
    return *best;
}

MemoryBlock& MemoryAllocator::newBlock(const Key& key, vk::DeviceSize size, bool dedicated) {
    auto block = std::make_unique<MemoryBlock>();
    block->size = size;
    block->dedicated = dedicated;
    block->free[0] = size;
    vk::MemoryPriorityAllocateInfoEXT priority{.priority = priorityOf(key.use)};
    vk::MemoryAllocateFlagsInfo addressed{.pNext = options_.priorities ? &priority : nullptr,
                                          .flags = vk::MemoryAllocateFlagBits::eDeviceAddress};
    // Buffers in any block may be read by device address (images never are).
    const void* next = key.image ? (options_.priorities ? static_cast<const void*>(&priority) : nullptr)
                                 : static_cast<const void*>(&addressed);
    try {
        block->memory = vk::raii::DeviceMemory(device_, vk::MemoryAllocateInfo{.pNext = next,
                                                                               .allocationSize = size,
                                                                               .memoryTypeIndex = key.type});
        ++stats_.allocationCalls;
        // With pageable device-local memory the priority is the block's
        // current one, set (and changeable) through vkSetDeviceMemoryPriorityEXT.
        if (options_.pageable) block->memory.setPriorityEXT(priorityOf(key.use));
        if (mappedUse(key.use)) {
            block->mapped = block->memory.mapMemory(0, VK_WHOLE_SIZE);
            // lavapipe (Mesa 25.0) reports success and maps to MAP_FAILED
            // when its mmap of the allocation fails (seen under ulimit -v).
            if (!block->mapped || block->mapped == reinterpret_cast<void*>(intptr_t(-1)))
                throw vk::OutOfHostMemoryError("vkMapMemory returned no mapping");
        }
    } catch (const vk::OutOfDeviceMemoryError&) {
        if (events_) events_->failAllocation(vk::Result::eErrorOutOfDeviceMemory, size, memoryUseName(key.use));
        throw;
    } catch (const vk::OutOfHostMemoryError&) {
        if (events_) events_->failAllocation(vk::Result::eErrorOutOfHostMemory, size, memoryUseName(key.use));
        throw;
    }
    stats_.bytes[size_t(key.use)] += size;
    ++stats_.blocks;
    auto& list = blocks_[key];
    list.push_back(std::move(block));
    return *list.back();
}

Allocation MemoryAllocator::allocate(const vk::MemoryRequirements& requirements, MemoryUse use, bool image) {
    std::lock_guard lock(mutex_);
    Key key{memoryType(requirements.memoryTypeBits, use), use, image};
    vk::DeviceSize alignment = std::max<vk::DeviceSize>(requirements.alignment, 1);
    vk::DeviceSize size = std::max<vk::DeviceSize>(requirements.size, 1);
    if (events_) events_->allocation(size, memoryUseName(use));
    stats_.requested[size_t(use)] += size;

    auto place = [&](MemoryBlock& block) -> std::optional<vk::DeviceSize> {
        for (auto it = block.free.begin(); it != block.free.end(); ++it) {
            vk::DeviceSize start = alignUp(it->first, alignment);
            vk::DeviceSize end = it->first + it->second;
            if (start + size > end) continue;
            vk::DeviceSize before = start - it->first, after = end - (start + size);
            vk::DeviceSize rangeStart = it->first;
            block.free.erase(it);
            if (before > 0) block.free[rangeStart] = before;
            if (after > 0) block.free[start + size] = after;
            block.used += size;
            return start;
        }
        return std::nullopt;
    };
    Allocation a;
    a.owner_ = this;
    a.size_ = size;
    auto& list = blocks_[key];
    for (auto& block : list)
        if (!block->dedicated)
            if (auto offset = place(*block)) {
                a.block_ = block.get();
                a.offset_ = *offset;
                return a;
            }
    // A new block: one of its own for a request of half the preferred size
    // or more; else 1/8 of the preferred size for the first of its kind,
    // doubling with each further one.
    vk::DeviceSize preferred = options_.preferredBlockSize;
    bool dedicated = size >= preferred / 2;
    vk::DeviceSize blockSize = size;
    if (!dedicated) {
        size_t shared = size_t(std::count_if(list.begin(), list.end(), [](const auto& b) { return !b->dedicated; }));
        blockSize = std::min(preferred, (preferred / 8) << std::min<size_t>(shared, 3));
        blockSize = std::max(blockSize, size);
    }
    MemoryBlock& block = newBlock(key, blockSize, dedicated);
    a.block_ = &block;
    a.offset_ = *place(block);
    return a;
}

void MemoryAllocator::free(MemoryBlock* block, vk::DeviceSize offset, vk::DeviceSize size) {
    std::lock_guard lock(mutex_);
    // The range back into the free list, joined with its neighbours.
    auto next = block->free.emplace(offset, size).first;
    if (next != block->free.begin()) {
        auto previous = std::prev(next);
        if (previous->first + previous->second == next->first) {
            previous->second += next->second;
            block->free.erase(next);
            next = previous;
        }
    }
    auto after = std::next(next);
    if (after != block->free.end() && next->first + next->second == after->first) {
        next->second += after->second;
        block->free.erase(after);
    }
    block->used -= size;
    if (block->used > 0) return;
    // An empty block goes, unless it is the only empty one of its kind: the
    // next scene or staging copy reuses it.
    for (auto& [key, list] : blocks_) {
        auto it = std::find_if(list.begin(), list.end(), [&](const auto& b) { return b.get() == block; });
        if (it == list.end()) continue;
        bool anotherEmpty = std::any_of(list.begin(), list.end(), [&](const auto& b) {
            return b.get() != block && b->used == 0 && !b->dedicated;
        });
        if (!block->dedicated && !anotherEmpty) return;
        stats_.bytes[size_t(key.use)] -= block->size;
        --stats_.blocks;
        list.erase(it);
        return;
    }
}

MemoryStats MemoryAllocator::stats() const {
    std::lock_guard lock(mutex_);
    return stats_;
}

}  // namespace whitted
