// The images the live window can show: the main image, then every
// auxiliary image in the order of `--aov all`, drawn as
// output/aov_output.cpp writes them (the L key cycles through them, a
// script's `layer NAME` picks one).
#pragma once

#include <string>
#include <vector>

#include "display_types.h"

namespace whitted {

struct LayerView {
    std::string name;
    gpu::DisplayParams params;
};

// With --aov-bounces B, the split images reflection.1..B and
// transmission.1..B follow "transmission".
std::vector<LayerView> layerViews(int width, int height, int aovBounces);

}  // namespace whitted
