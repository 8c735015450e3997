// Progressive accumulation for the live window: the sample budget of a
// render is split across frames. A pass adds the next samples (1, 1, 2, 4,
// then 8 at a time) to every pixel, in bands of whole rows; a frame records
// as many rows as its budget of camera samples allows (a pass may span
// frames, a frame may finish several passes), and the budget follows the
// measured tracing time so that a frame stays near its target (well under
// 100 ms) on any device. Sample indices are global, so after S samples the
// sums hold the samples `whitted render --spp S` traces; only the grouping
// of the float additions differs.
#pragma once

#include <cstdint>

#include "render/renderer.h"

namespace whitted {

class Progressive {
public:
    Progressive(int width, int height, uint32_t targetSamples, double targetFrameSeconds);

    // Starts over (camera or scene changed): the next frame clears the sums.
    void restart();
    // Records this frame's clear and tile dispatches; returns the camera
    // samples recorded (0 once every pixel has the target count).
    uint64_t record(const Renderer& renderer, const vk::raii::CommandBuffer& cmd);
    // Feeds back how long the last frame's tracing took (submit to fence).
    void frameDone(double seconds, uint64_t recorded);
    // The time tracing may take per frame: the frame target less what the
    // rest of the frame (display, overlay, present) costs.
    void setTargetSeconds(double seconds) { targetSeconds_ = seconds; }

    uint32_t completedSamples() const { return pass_; }  // every pixel has at least this many
    uint32_t targetSamples() const { return target_; }
    bool done() const { return pass_ >= target_; }
    uint64_t budget() const { return budget_; }
    bool needsClear() const { return clear_; }

private:
    int width_, height_;
    uint32_t target_;
    double targetSeconds_;
    uint64_t budget_;           // camera samples per frame
    uint32_t pass_ = 0;         // first sample index of the pass in progress
    uint32_t passSamples_ = 1;  // samples the pass in progress adds
    uint32_t nextRow_ = 0;      // first row of the pass not yet dispatched
    bool clear_ = true;
};

}  // namespace whitted
