#include "view/layer_views.h"

namespace whitted {

std::vector<LayerView> layerViews(int width, int height, int bounces) {
    auto make = [&](const char* name, uint32_t kind, uint32_t layer, uint32_t channel, float scale) {
        return LayerView{name,
                         {.kind = kind,
                          .layer = layer,
                          .channel = channel,
                          .width = uint32_t(width),
                          .height = uint32_t(height),
                          .scalarScale = scale,
                          .depthMedian = 1}};
    };
    std::vector<LayerView> views = {make("color", gpu::kDisplayColor, gpu::kAovColor, 0, 1),
            make("ambient", gpu::kDisplayColor, gpu::kAovAmbient, 0, 1),
            make("diffuse", gpu::kDisplayColor, gpu::kAovDiffuse, 0, 1),
            make("specular", gpu::kDisplayColor, gpu::kAovSpecular, 0, 1),
            make("reflection", gpu::kDisplayColor, gpu::kAovReflection, 0, 1),
            make("transmission", gpu::kDisplayColor, gpu::kAovTransmission, 0, 1),
            make("ambient_coef", gpu::kDisplayScalar, gpu::kAovCoefs0, 0, 1),
            make("diffuse_coef", gpu::kDisplayScalar, gpu::kAovCoefs0, 1, 1),
            make("specular_coef", gpu::kDisplayScalar, gpu::kAovCoefs0, 2, 1),
            make("reflection_coef", gpu::kDisplayScalar, gpu::kAovCoefs1, 0, 1),
            make("transmission_coef", gpu::kDisplayScalar, gpu::kAovCoefs1, 1, 1),
            make("ior", gpu::kDisplayScalar, gpu::kAovCoefs1, 2, 1.0f / 3.0f),
            make("depth", gpu::kDisplayDepth, gpu::kAovCoefs0, 3, 1),
            make("normal", gpu::kDisplayNormal, gpu::kAovNormal, 0, 1),
            // The id layer follows the split ones (device_types.h).
            make("object_id", gpu::kDisplayId, gpu::kAovCount + 2 * uint32_t(bounces), 0, 1),
            make("material_id", gpu::kDisplayId, gpu::kAovCount + 2 * uint32_t(bounces), 1, 1)};
    // --aov-bounces: the split images after "transmission", as --aov all orders them.
    std::vector<LayerView> split;
    for (int part = 0; part < 2; ++part)
        for (int k = 1; k <= bounces; ++k)
            split.push_back(make((std::string(part == 0 ? "reflection." : "transmission.") + std::to_string(k)).c_str(),
                                 gpu::kDisplayColor, gpu::kAovCount + uint32_t(part * bounces + k - 1), 0, 1));
    views.insert(views.begin() + 6, split.begin(), split.end());
    return views;
}

}  // namespace whitted
