#include "view/progressive.h"

#include <algorithm>

namespace whitted {
namespace {

constexpr uint32_t kTile = 32;
constexpr uint64_t kMinBudget = kTile * kTile;
constexpr uint64_t kInitialBudget = 1u << 14;

}  // namespace

Progressive::Progressive(int width, int height, uint32_t targetSamples, double targetFrameSeconds)
    : width_(width), height_(height), tilesX_((uint32_t(width) + kTile - 1) / kTile),
      tilesY_((uint32_t(height) + kTile - 1) / kTile), target_(std::max(targetSamples, 1u)),
      targetSeconds_(targetFrameSeconds), budget_(kInitialBudget) {}

void Progressive::restart() {
    pass_ = 0;
    nextTile_ = 0;
    clear_ = true;
}

uint64_t Progressive::record(const Renderer& renderer, const vk::raii::CommandBuffer& cmd) {
    if (clear_) {
        renderer.recordClear(cmd);
        clear_ = false;
    }
    uint64_t pixels = uint64_t(width_) * height_;
    uint64_t recorded = 0;
    while (!done() && recorded < budget_) {
        // A whole pass fits: one dispatch over the image. Otherwise tiles in
        // scanline order until the budget is spent.
        if (nextTile_ == 0 && budget_ - recorded >= pixels) {
            renderer.recordTile(cmd, {.tile = glm::uvec4(0, 0, width_, height_), .samples = glm::uvec4(pass_, 1, 0, 0)});
            recorded += pixels;
            ++pass_;
            continue;
        }
        uint32_t tx = nextTile_ % tilesX_, ty = nextTile_ / tilesX_;
        uint32_t x = tx * kTile, y = ty * kTile;
        uint32_t w = std::min(kTile, uint32_t(width_) - x), h = std::min(kTile, uint32_t(height_) - y);
        renderer.recordTile(cmd, {.tile = glm::uvec4(x, y, w, h), .samples = glm::uvec4(pass_, 1, 0, 0)});
        recorded += uint64_t(w) * h;
        if (++nextTile_ == tilesX_ * tilesY_) {
            nextTile_ = 0;
            ++pass_;
        }
    }
    return recorded;
}

// Multiplicative step towards the target time, at most x2 or /2 per frame so
// that one odd frame (a reload, the window being moved) does not throw it.
void Progressive::frameDone(double seconds, uint64_t recorded) {
    if (recorded < budget_ || seconds <= 0) return;  // the budget was not the limit
    double factor = std::clamp(targetSeconds_ / seconds, 0.5, 2.0);
    budget_ = std::clamp<uint64_t>(uint64_t(double(budget_) * factor), kMinBudget, uint64_t(1) << 26);
}

}  // namespace whitted
