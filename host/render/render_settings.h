#pragma once

#include <cstdint>

namespace whitted {

// How to render a scene; zero width/height means the scene camera's size.
struct RenderSettings {
    int width = 0;
    int height = 0;
    int samplesPerPixel = 1;
    int maxDepth = 6;         // secondary bounces; 0 = local shading only
    bool auxiliary = true;    // also produce the auxiliary (AOV) layers
    bool useBvh = true;       // false: test every primitive (reference for tests)
    uint32_t seed = 0;        // decorrelates sample patterns between renders
    // Upper bound on camera samples per dispatch: keeps each submit short
    // (GPU watchdogs, progress updates) while amortising submit overhead.
    uint64_t samplesPerDispatch = 1u << 18;
};

}  // namespace whitted
