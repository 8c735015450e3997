// One render shared among several devices (`whitted render --device all`):
// each renderer, on its own device and thread, takes every N-th band of the
// same band layout, and the bands reach the sink in order, top to bottom.
// Every pixel's samples depend on its place in the image alone, so the image
// is the one a single device renders (bit for bit on identical devices).
#pragma once

#include "render/renderer.h"

#include <span>

namespace whitted {

RenderResult renderOnDevices(std::span<Renderer* const> renderers, BandSink& sink,
                             const ProgressCallback& progress = {});

}  // namespace whitted
