#include "view/progressive.h"

#include <algorithm>

namespace whitted {
namespace {

constexpr uint32_t kRowStep = gpu::kWorkgroupSize;  // rows of one work group
constexpr uint64_t kMinBudget = 1024;
constexpr uint64_t kInitialBudget = 1u << 12;
constexpr uint32_t kMaxPassSamples = 8;

}  // namespace

Progressive::Progressive(int width, int height, uint32_t targetSamples, double targetFrameSeconds)
    : width_(width),
      height_(height),
      target_(std::max(targetSamples, 1u)),
      targetSeconds_(targetFrameSeconds),
      budget_(kInitialBudget) {}

void Progressive::restart() {
    pass_ = 0;
    nextRow_ = 0;
    clear_ = true;
}

uint64_t Progressive::record(const Renderer& renderer, const vk::raii::CommandBuffer& cmd) {
    if (clear_) {
        renderer.recordClear(cmd);
        clear_ = false;
    }
    uint64_t recorded = 0;
    while (!done() && recorded < budget_) {
        // Pass sizes 1, 1, 2, 4, 8, 8, ... samples: the first passes give a
        // whole picture soon; later ones trace several samples per
        // invocation, which saves re-reading and re-writing the nine output
        // layers once per sample (the window's throughput then nears
        // render's).
        // Chosen at the start of a pass and kept for all its rows; never
        // so many that one band of rows would overrun the budget.
        if (nextRow_ == 0) {
            uint64_t affordable = std::max<uint64_t>(budget_ / (uint64_t(width_) * kRowStep), 1);
            passSamples_ =
                uint32_t(std::min<uint64_t>({std::max(pass_, 1u), kMaxPassSamples, target_ - pass_, affordable}));
        }
        uint32_t samples = passSamples_;
        // A band of whole rows, as many as the budget pays for (whole
        // work groups of rows, at least one): lavapipe pays several
        // milliseconds per dispatch, so few wide dispatches beat many tiles.
        uint64_t rowsPaid = (budget_ - recorded) / (uint64_t(width_) * samples);
        uint32_t rows = uint32_t(std::max<uint64_t>(rowsPaid / kRowStep * kRowStep, kRowStep));
        rows = std::min(rows, uint32_t(height_) - nextRow_);
        renderer.recordTile(
            cmd, {.tileOrigin = glm::uvec2(0, nextRow_),
                  .tileSize = glm::uvec2(width_, rows),
                  .firstSample = pass_,
                  .sampleCount = samples});
        recorded += uint64_t(width_) * rows * samples;
        nextRow_ += rows;
        if (nextRow_ == uint32_t(height_)) {
            nextRow_ = 0;
            pass_ += samples;
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
