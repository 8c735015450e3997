#pragma once

#include <cstdint>
#include <optional>

namespace whitted {

// How the samples of a pixel are chosen.
enum class AntiAliasing {
    Uniform,   // every pixel takes exactly samplesPerPixel stratified samples
    Adaptive,  // one sample per pixel, more where the image varies, up to samplesPerPixel
};

// How rays find the scene's bounded primitives (README "Ray queries").
enum class TracePath {
    Auto,      // ray queries on a GPU that offers them, our BVH elsewhere
    Bvh,       // our BVH walked in the shader (any device)
    RayQuery,  // the device's acceleration structures through VK_KHR_ray_query
};

// How the tracer reads the scene's BVH nodes, primitives, materials and
// lights (render/device_policy.h); every choice gives the same image.
enum class SceneReads {
    Auto,        // through storage buffers on lavapipe before Mesa 25, else through their device addresses
    Address,     // through their device addresses
    Descriptor,  // through storage buffer descriptors, where every array fits one storage buffer range
};

// Pixels x0 <= x < x1, y0 <= y < y1 of the full image.
struct PixelRegion {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    int width() const { return x1 - x0; }
    int height() const { return y1 - y0; }
    bool operator==(const PixelRegion&) const = default;
};

// Default refinement threshold of adaptive anti-aliasing: a difference of
// the displayed (clamped, sRGB-encoded) colour in [0, 1] (README "Adaptive
// anti-aliasing" says how it was chosen).
inline constexpr float kDefaultAaThreshold = 2.0f / 255.0f;

// How to render a scene; zero width/height means the scene camera's size.
struct RenderSettings {
    int width = 0;
    int height = 0;
    int samplesPerPixel = 1;  // uniform: exactly; adaptive: at most
    int maxDepth = 6;         // secondary bounces; 0 = local shading only
    bool auxiliary = true;    // also produce the auxiliary (AOV) layers
    // With auxiliary: reflection and transmission split by ray depth into
    // this many layers each (0..gpu::kAovBouncesMax; README "Auxiliary images").
    int aovBounces = 0;
    // With auxiliary: the object and material masks' layer (the id of what
    // the pixel-centre ray hits; README "Auxiliary images").
    bool ids = false;
    // --background transparent: camera rays do not see the environment (its light, reflections and
    // refractions stay), and the auxiliary layers are made, whose hit mask is the image's alpha.
    bool transparentBackground = false;
    bool useBvh = true;       // false: test every primitive (reference for tests)
    TracePath trace = TracePath::Auto;
    uint32_t seed = 0;        // decorrelates sample patterns between renders
    AntiAliasing antiAliasing = AntiAliasing::Uniform;
    float aaThreshold = kDefaultAaThreshold;
    // Render only these pixels of the full image (none: all of it). They get
    // exactly the samples a full render gives them.
    std::optional<PixelRegion> region{};
    // Upper bound on camera samples per dispatch: keeps each submit short
    // (GPU watchdogs, progress updates) while amortising submit overhead.
    uint64_t samplesPerDispatch = 1u << 18;
    // Device memory for the output layers of one band of rows; the image is
    // rendered band by band and each band handed on when done, so memory
    // does not grow with the image. 0: the whole image at once (the window).
    uint64_t bandBytes = uint64_t(32) << 20;
    // Sample every texture at its full-resolution level instead of the
    // ray-cone level (tests of the filtering, shaders/texture.glsl).
    bool textureLodZero = false;
    // Draw an image environment's light directions uniformly over the sphere instead of by its luminance
    // (render/gpu_environment.h): what importance sampling gains is measured against this.
    bool uniformEnvironmentSampling = false;
    // Auto: as suits the device. Tests force each way and compare the images.
    SceneReads sceneReads = SceneReads::Auto;
    // A build of the tracer without the code the scene does not use (csg
    // objects, textures: host/render/device_policy.h); false: the full one.
    // Tests compare the two.
    bool fittedShader = true;

    // A renderer built for one RenderSettings is reused only for equal ones
    // (the Python module compares them as a whole: a field left out of the
    // comparison once reused a renderer without its mask layer).
    bool operator==(const RenderSettings&) const = default;
};

}  // namespace whitted
