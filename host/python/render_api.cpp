// whitted.Renderer, RenderResult, devices() and render(): a renderer keeps
// its Vulkan context, pipeline and uploaded scene between renders and
// re-uploads only what the scene's edit counters say changed (a camera edit
// rewrites the uniform block; a material edit the materials, no BVH).
// Rendering releases the GIL; after every submission to the device it takes
// it back to call progress and PyErr_CheckSignals, so Ctrl+C stops a render
// cleanly.
#include "io/atomic_file.h"
#include "io/image_io.h"
#include "output/aov_output.h"
#include "output/ray_tree_json.h"
#include "output/render_record.h"
#include "python/arguments.h"
#include "python/python_api.h"
#include "render/ray_cast.h"
#include "render/ray_tree.h"
#include "render/renderer.h"
#include "vk/context.h"

#include <nlohmann/json.hpp>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <mutex>
#include <optional>
#include <unistd.h>

namespace whitted::python {
namespace {

// A render's layers as one block, [layer][row][column][rgba], the whole
// region: the form of one band (BandView) covering the image, so that the
// output writers take it as they take the CLI's bands.
struct Pixels {
    ImageLayout layout;
    std::vector<float> layers;
    std::vector<float> sampleCounts;
    BandView whole() const {
        return {.index = 0, .y0 = layout.region.y0, .rows = layout.region.height(), .width = layout.region.width(),
                .layers = layers, .sampleCounts = sampleCounts};
    }
};

// Copies each band into its place in Pixels (the one copy a render makes,
// as the CLI's sink copies each band into its files).
class PixelSink final : public BandSink {
public:
    explicit PixelSink(Pixels& p) : p_(p) {
        size_t n = size_t(p.layout.region.width()) * p.layout.region.height();
        p_.layers.assign(n * 4 * p.layout.layerCount, 0.0f);
        p_.sampleCounts.assign(n, 0.0f);
    }
    void writeBand(const BandView& band) override {
        size_t w = size_t(band.width), n = w * p_.layout.region.height();
        size_t row = size_t(band.y0 - p_.layout.region.y0);
        for (uint32_t l = 0; l < p_.layout.layerCount; ++l) {
            std::span<const float> src = band.layer(l);
            std::copy(src.begin(), src.end(), p_.layers.begin() + l * n * 4 + row * w * 4);
        }
        std::copy(band.sampleCounts.begin(), band.sampleCounts.end(), p_.sampleCounts.begin() + row * w);
    }

private:
    Pixels& p_;
};

// A numpy array that owns `values` (moved into a capsule): no copy.
template <typename T>
py::array_t<T> ownedArray(std::vector<T>&& values, std::vector<py::ssize_t> shape) {
    auto* held = new std::vector<T>(std::move(values));
    py::capsule owner(held, [](void* p) { delete static_cast<std::vector<T>*>(p); });
    return py::array_t<T>(shape, held->data(), owner);
}

// cast_rays' origins or directions: an (N, 3) array of numbers as float64,
// or ValueError naming the argument.
using Rows = py::array_t<double, py::array::c_style | py::array::forcecast>;
Rows rowsArg(const py::object& x, const char* name) {
    Rows a;
    try {
        a = x.cast<Rows>();
    } catch (const py::cast_error&) {
        throw py::value_error(std::string(name) + ": must be an (N, 3) array of numbers");
    } catch (const py::error_already_set&) {  // numpy could not make numbers of it
        throw py::value_error(std::string(name) + ": must be an (N, 3) array of numbers");
    }
    if (a.ndim() != 2 || a.shape(1) != 3) {
        std::string got;
        for (py::ssize_t i = 0; i < a.ndim(); ++i) got += (i ? ", " : "") + std::to_string(a.shape(i));
        throw py::value_error(std::string(name) + ": must be an (N, 3) array, got shape (" + got + ")");
    }
    return a;
}

// What whitted.devices() and Renderer.device give for a device.
py::dict deviceDict(const DeviceInfo& d) {
    py::dict info;
    info["index"] = d.index;
    info["name"] = d.name;
    info["type"] = d.type;
    info["driver"] = d.driver;
    info["ray_query"] = d.rayQuery;
    return info;
}

struct Result {
    Pixels pixels;
    RenderResult stats;
    RenderSettings settings;
    std::vector<std::string> aovs;
    std::filesystem::path scenePath;
    std::shared_ptr<const Scene> masksScene;  // with object_id/material_id: the record's legend
    std::vector<uint64_t> objectIds;          // with the masks: the handle's object ids (stableObjectIds)
    DeviceInfo device;
    nlohmann::json uploads;
    double loadSeconds = 0;
    std::vector<std::string> warnings, warningDetails;  // the scene's, as the CLI's record has them
    py::object image, aovArrays, record;  // made on first use

    std::string recordJson(const std::vector<std::filesystem::path>& files, const std::string& tonemap) const {
        nlohmann::json j = nlohmann::json::parse(renderRecordJson({.scenePath = scenePath, .settings = settings,
                                                                   .tonemap = tonemap, .device = device, .sharedWith = {},
                                                                   .result = &stats, .files = files,
                                                                   .loadSeconds = loadSeconds, .warnings = warnings,
                                                                   .warningDetails = warningDetails,
                                                                   .masks = masksScene.get(), .exposure = 0,
                                                                   .camera = {}}));
        if (masksScene) {  // the legend numbers objects as the mask does (stableObjectIds)
            for (auto& o : j["masks"]["objects"]) o["id"] = objectIds[o["id"].get<size_t>()];
            for (auto& mt : j["masks"]["materials"]) mt["object"] = objectIds[mt["object"].get<size_t>()];
        }
        j["uploads"] = uploads;
        return j.dump(2) + "\n";
    }
    py::array values(const std::string& name) const {
        int channels = 0;
        std::vector<float> v = floatImageValues(pixels.whole(), name, settings.aovBounces, settings.samplesPerPixel,
                                                channels, pixels.layout.environment);
        if (name == "image" && settings.transparentBackground) {
            addCoverage(pixels.whole(), true, v);
            channels = 4;
        }
        std::vector<py::ssize_t> shape = {pixels.layout.region.height(), pixels.layout.region.width()};
        if (channels > 1) shape.push_back(channels);
        py::array_t<float> array = ownedArray(std::move(v), shape);
        // The masks hold the ids' bits (the EXR's UINT channel): the same
        // memory seen as uint32, no copy.
        if (name == "object_id" || name == "material_id") return array.view("uint32");
        return array;
    }
    // The files of `whitted render -o path`, through the same writers.
    std::vector<std::filesystem::path> save(const std::filesystem::path& path, Tonemap tonemap) const {
        std::filesystem::path parent = path.parent_path().empty() ? "." : path.parent_path();
        if (!std::filesystem::is_directory(parent)) throw py::value_error("output folder " + parent.string() + " does not exist");
        if (!isWritableFormat(path))
            throw py::value_error("cannot write images of type '" + path.extension().string() +
                                  "' (use .png, .exr, .jpg or .tif)");
        ImageFileSink sink(path, aovs, tonemap, pixels.layout, settings.samplesPerPixel, 0.0,
                           settings.transparentBackground);
        sink.writeBand(pixels.whole());
        std::vector<std::filesystem::path> files = sink.finish();
        std::filesystem::path recordPath = path;
        recordPath.replace_extension(".json");
        writeTextFile(recordPath, recordJson(files, tonemap == Tonemap::Seed ? "seed" : "clamp"));
        return files;
    }
};
using ResultRef = std::shared_ptr<Result>;

// ---- Stable object ids in the object_id mask (scene_api.cpp's handles) ----
// The renderer numbers objects by their index; the result numbers them by
// the scene handle's ids (python_api.h), which survive the removal of other
// objects and are never reused within the scene's life. Until an object is
// removed they are the indices, so the mask is the CLI's.
void stableObjectIds(Result& r) {
    const std::vector<uint64_t>& ids = r.objectIds;
    bool indices = true;
    for (size_t k = 0; k < ids.size(); ++k) indices = indices && ids[k] == k;
    if (indices) return;
    const ImageLayout& layout = r.pixels.layout;
    size_t n = size_t(layout.region.width()) * size_t(layout.region.height());
    float* objectChannel = r.pixels.layers.data() + size_t(layout.idLayer()) * n * 4;  // rgba: r is the object
    for (size_t p = 0; p < n; ++p) {
        uint32_t bits;
        std::memcpy(&bits, objectChannel + 4 * p, sizeof bits);
        if (bits >= ids.size()) continue;  // the background
        uint32_t id = uint32_t(ids[bits]);
        std::memcpy(objectChannel + 4 * p, &id, sizeof id);
    }
}

// result.masks: object id -> its name, shape and material (the record's legend).
py::dict masksDict(const Result& r) {
    py::dict d;
    if (!r.masksScene) return d;
    nlohmann::ordered_json legend = maskLegend(*r.masksScene);
    for (size_t k = 0; k < r.masksScene->objects.size(); ++k) {
        py::dict entry;
        entry["name"] = legend["objects"][k]["name"].get<std::string>();
        entry["type"] = legend["objects"][k]["shape"].get<std::string>();
        entry["material"] = legend["materials"][k]["name"].get<std::string>();
        entry["material_id"] = k;
        d[py::int_(r.objectIds[k])] = entry;
    }
    return d;
}

// What the uploaded scene was: which scene, at which edits, with which settings.
struct Uploaded {
    uint64_t sceneId = 0;
    Versions versions;
    RenderSettings settings;
};

// Renderer(device=...): None (the best device), a name substring, or an
// index as whitted.devices() lists them (ValueError naming the devices for
// one that is not there), as the context takes it (vk/context.h).
std::optional<std::string> deviceArg(const py::object& device) {
    if (device.is_none()) return std::nullopt;
    if (py::isinstance<py::str>(device)) return device.cast<std::string>();
    if (!py::isinstance<py::int_>(device) || py::isinstance<py::bool_>(device))
        throw py::type_error("device: expected an index, a name substring or None, got " + typeName(device));
    long long index = PyLong_AsLongLong(device.ptr());
    if (index == -1 && PyErr_Occurred()) PyErr_Clear();  // too large: not there either
    std::vector<DeviceInfo> devices = VulkanContext::listDevices();
    if (index < 0 || size_t(index) >= devices.size()) {
        std::string listed;
        for (const DeviceInfo& d : devices) listed += (listed.empty() ? "" : ", ") + std::to_string(d.index) + ": " + d.name;
        throw py::value_error("device: no device " + py::str(device).cast<std::string>() + "; the devices are " + listed);
    }
    return std::to_string(index);
}

// The cameras of a batch render: a non-empty list of Camera of one image
// size, unless width and height are given.
std::vector<Camera> batchCameras(const py::object& camerasArg, std::optional<int> width, std::optional<int> height) {
    auto bad = [](const std::string& what) { throw py::value_error(what); };
    std::vector<Camera> cameras;
    if (py::isinstance<py::str>(camerasArg) || !py::isinstance<py::iterable>(camerasArg))
        bad("cameras: must be a list of Camera (e.g. scene.camera.copy())");
    for (py::handle h : camerasArg) {
        if (!py::isinstance<CameraView>(h))
            bad("cameras: must be a list of Camera (e.g. scene.camera.copy()), got a " +
                py::str(py::type::of(h).attr("__name__")).cast<std::string>());
        cameras.push_back(h.cast<const CameraView&>().c());
    }
    if (cameras.empty()) bad("cameras: the list is empty");
    for (const Camera& c : cameras)
        if ((!width && c.width != cameras[0].width) || (!height && c.height != cameras[0].height))
            bad("cameras: of different image sizes (" + std::to_string(cameras[0].width) + "x" +
                std::to_string(cameras[0].height) + " and " + std::to_string(c.width) + "x" +
                std::to_string(c.height) + "); give width= and height=");
    return cameras;
}

// The render's settings from render()'s arguments, each checked (ValueError
// naming the argument); `aovs` gets the auxiliary images asked for.
RenderSettings renderSettings(const Camera& camera, std::optional<int> width, std::optional<int> height, int spp,
                              const std::string& aa, std::optional<double> aaThreshold, int maxDepth,
                              const py::object& aovsArg, int aovBounces, const std::optional<std::vector<int>>& region,
                              const std::string& trace, const py::object& seedArg, bool alpha,
                              std::vector<std::string>& aovs) {
    auto bad = [](const std::string& what) { throw py::value_error(what); };
    auto side = [&](const char* name, std::optional<int> v, int fallback) {
        int x = v.value_or(fallback);
        if (x < 1 || x > int(gpu::kMaxImageSide))
            bad(std::string(name) + ": must be in 1.." + std::to_string(gpu::kMaxImageSide) + ", got " + std::to_string(x));
        return x;
    };
    RenderSettings s;
    s.width = side("width", width, camera.width);
    s.height = side("height", height, camera.height);
    if (spp < 1 || spp > int(gpu::kMaxSamplesPerPixel))
        bad("spp: must be in 1.." + std::to_string(gpu::kMaxSamplesPerPixel) + ", got " + std::to_string(spp));
    s.samplesPerPixel = spp;
    if (aa != "adaptive" && aa != "uniform") bad("aa: must be 'adaptive' or 'uniform', got '" + aa + "'");
    s.antiAliasing = aa == "uniform" ? AntiAliasing::Uniform : AntiAliasing::Adaptive;
    if (aaThreshold) {
        if (!std::isfinite(*aaThreshold) || *aaThreshold < 0 || *aaThreshold > 1)
            bad("aa_threshold: must be in [0, 1], got " + py::str(py::float_(*aaThreshold)).cast<std::string>());
        s.aaThreshold = float(*aaThreshold);
    }
    if (maxDepth < 0 || maxDepth > int(gpu::kMaxDepthLimit))
        bad("max_depth: must be in 0.." + std::to_string(gpu::kMaxDepthLimit) + ", got " + std::to_string(maxDepth));
    s.maxDepth = maxDepth;
    if (aovBounces < 0 || aovBounces > int(gpu::kAovBouncesMax))
        bad("aov_bounces: must be in 0.." + std::to_string(gpu::kAovBouncesMax) + ", got " + std::to_string(aovBounces));
    std::string list;
    if (py::isinstance<py::str>(aovsArg)) {
        list = aovsArg.cast<std::string>();
    } else {
        for (py::handle h : aovsArg) list += (list.empty() ? "" : ",") + py::str(h).cast<std::string>();
        if (list.empty()) list = "none";
    }
    try {
        aovs = parseAovList(list, aovBounces);
    } catch (const std::invalid_argument& e) {
        bad(std::string("aovs: ") + e.what());
    }
    s.auxiliary = !aovs.empty() || alpha;  // the alpha is the hit mask's
    s.transparentBackground = alpha;
    s.aovBounces = hasSplitAov(aovs) ? aovBounces : 0;
    s.ids = hasIdAov(aovs);
    if (region) {
        const std::vector<int>& r = *region;
        if (r.size() != 4) bad("region: must be (x0, y0, x1, y1), got " + std::to_string(r.size()) + " numbers");
        if (r[0] < 0 || r[1] < 0 || r[2] > s.width || r[3] > s.height || r[0] >= r[2] || r[1] >= r[3])
            bad("region: " + std::to_string(r[0]) + "," + std::to_string(r[1]) + "," + std::to_string(r[2]) + "," +
                std::to_string(r[3]) + " is empty or outside the " + std::to_string(s.width) + "x" +
                std::to_string(s.height) + " image");
        s.region = PixelRegion{r[0], r[1], r[2], r[3]};
    }
    if (trace != "auto" && trace != "bvh" && trace != "rayquery")
        bad("trace: must be 'auto', 'bvh' or 'rayquery', got '" + trace + "'");
    s.trace = trace == "rayquery" ? TracePath::RayQuery : trace == "bvh" ? TracePath::Bvh : TracePath::Auto;
    // seed: FrameParams.seed, xor-ed into each pixel's pattern hash
    // (whitted.comp): a function of the pixel and the seed only.
    if (!py::isinstance<py::int_>(seedArg) || py::isinstance<py::bool_>(seedArg))
        bad("seed: must be an integer in 0..4294967295");
    {
        py::int_ seedValue = seedArg.cast<py::int_>();
        if (seedValue < py::int_(0) || seedValue > py::int_(0xFFFFFFFFu))
            bad("seed: must be in 0..4294967295, got " + py::str(seedValue).cast<std::string>());
        s.seed = seedValue.cast<uint32_t>();
    }
    return s;
}

class PyRenderer {
public:
    explicit PyRenderer(const std::optional<std::string>& device) : deviceName_(device.value_or("")) {
        py::gil_scoped_release release;
        openDevice();
    }

    // One render (cameras None: the scene's camera) or a batch, one render
    // per camera of `cameras` (a list of Camera, e.g. scene.camera.copy()):
    // the scene goes to the device once, each camera rewrites only the
    // uniform block. Returns a RenderResult or a list of them. Every option
    // is checked before anything reaches the device.
    py::object render(const SceneRef& handle, std::optional<int> width, std::optional<int> height, int spp,
                      const std::string& aa, std::optional<double> aaThreshold, int maxDepth, py::object aovsArg,
                      int aovBounces, std::optional<std::vector<int>> region, const std::string& trace,
                      py::object progress, py::object camerasArg, py::object seedArg, bool alpha,
                      const std::string& environmentSampling) {
        if (!progress.is_none() && !PyCallable_Check(progress.ptr()))
            throw py::type_error("progress: must be callable (progress(fraction)) or None, got a " +
                                 py::str(py::type::of(progress).attr("__name__")).cast<std::string>());
        const Scene& scene = *handle->scene;
        bool batch = !camerasArg.is_none();
        std::vector<Camera> cameras = batch ? batchCameras(camerasArg, width, height) : std::vector{scene.camera};
        std::vector<std::string> aovs;
        RenderSettings s = renderSettings(cameras[0], width, height, spp, aa, aaThreshold, maxDepth, aovsArg,
                                          aovBounces, region, trace, seedArg, alpha, aovs);
        if (environmentSampling != "importance" && environmentSampling != "uniform")
            throw py::value_error("environment_sampling: must be 'importance' or 'uniform', got '" +
                                  environmentSampling + "'");
        s.uniformEnvironmentSampling = environmentSampling == "uniform";
        std::vector<ResultRef> results = renderEach(handle, s, aovs, cameras, batch, progress);
        if (s.ids)
            for (ResultRef& r : results) stableObjectIds(*r);
        if (!batch) return py::cast(results[0]);
        py::list out;
        for (ResultRef& r : results) out.append(py::cast(r));
        return out;
    }

    // Renders with the GIL released, one result per camera; the scene is
    // uploaded (what changed of it) before the first.
    std::vector<ResultRef> renderEach(const SceneRef& handle, const RenderSettings& s,
                                      const std::vector<std::string>& aovs, const std::vector<Camera>& cameras,
                                      bool batch, const py::object& progress) {
        const Scene& scene = *handle->scene;
        // The renderer reads its own copy: the script may edit the scene
        // (or render it elsewhere) while this render runs.
        Scene copy = scene;
        copy.camera = cameras[0];
        std::shared_ptr<const Scene> masksScene;
        if (s.ids) masksScene = std::make_shared<const Scene>(scene);
        const std::vector<uint64_t> objectIds = handle->objectIds;
        Versions versions = handle->versions;
        uint64_t id = handle->id;
        bool hasProgress = !progress.is_none();
        // Called after every submission to the queue: Ctrl+C (a signal,
        // or one raised by progress itself) stops the render there.
        ProgressCallback between = [&](double fraction) {
            py::gil_scoped_acquire gil;
            if (PyErr_CheckSignals() != 0) throw py::error_already_set();
            if (hasProgress) progress(fraction);
            if (PyErr_CheckSignals() != 0) throw py::error_already_set();
        };
        std::vector<ResultRef> results;
        {
            py::gil_scoped_release release;
            std::lock_guard lock(mutex_);
            try {
                openDevice();
                for (size_t i = 0; i < cameras.size(); ++i) {
                    auto result = std::make_shared<Result>();
                    result->settings = s;
                    result->aovs = aovs;
                    result->scenePath = scene.sourcePath;
                    result->warnings = scene.warnings;
                    result->warningDetails = scene.warningDetails;
                    result->device = ctx_->deviceInfo();
                    result->masksScene = masksScene;
                    if (s.ids) result->objectIds = objectIds;
                    uint32_t messagesBefore = ctx_->validationMessageCount();
                    if (i == 0) {
                        result->uploads = upload(copy, versions, id, s);
                    } else {
                        result->uploads = {{"renderer", false}, {"geometry", false}, {"bvh", false},
                                           {"materials", false}, {"lights", false}, {"camera", false},
                                           {"textures", false}};
                    }
                    if (batch) {
                        // The scene's camera version says nothing of a batch's
                        // cameras: each is sent, and the next render sends the
                        // scene's camera again.
                        renderer_->setCamera(cameras[i]);
                        result->uploads["camera"] = true;
                        uploaded_.versions.camera = kBatchCamera;
                    }
                    result->pixels.layout = renderer_->layout();
                    PixelSink sink(result->pixels);
                    result->stats = renderer_->renderTo(sink, between);
                    result->stats.layout = renderer_->layout();
                    throwIfValidationReported(messagesBefore, "this render");
                    results.push_back(std::move(result));
                }
            } catch (const DeviceFailure& e) {
                deviceFailed(e, scene);
            }
        }
        return results;
    }

    // What each ray hits first, found on the device by the tracer's own
    // closest-hit query (render/ray_cast.h) in the scene this renderer
    // holds: the uploaded one, brought up to the scene's edits, or a new
    // upload when it holds another scene. Every argument is checked first.
    py::dict castRays(const SceneRef& handle, const py::object& originsArg, const py::object& directionsArg,
                      const py::object& tMaxArg) {
        Rows origins = rowsArg(originsArg, "origins"), directions = rowsArg(directionsArg, "directions");
        if (directions.shape(0) != origins.shape(0))
            throw py::value_error("directions: " + std::to_string(directions.shape(0)) + " rows, but origins has " +
                                  std::to_string(origins.shape(0)));
        py::array_t<double, py::array::c_style | py::array::forcecast> tMax;
        try {
            tMax = tMaxArg.cast<py::array_t<double, py::array::c_style | py::array::forcecast>>();
        } catch (const std::exception&) {
            throw py::value_error("t_max: must be a number or an (N,) array of numbers");
        }
        if (tMax.ndim() > 1) throw py::value_error("t_max: must be a number or an (N,) array of numbers");
        size_t n = size_t(origins.shape(0));
        CastRays rays{.origins = std::span(origins.data(), 3 * n), .directions = std::span(directions.data(), 3 * n),
                      .tMax = std::span(tMax.data(), size_t(tMax.size()))};
        try {
            checkCastRays(rays);
        } catch (const std::invalid_argument& e) {
            throw py::value_error(e.what());
        }
        Scene copy = *handle->scene;
        const std::vector<uint64_t> objectIds = handle->objectIds;
        Versions versions = handle->versions;
        uint64_t id = handle->id;
        CastResult hits;
        {
            py::gil_scoped_release release;
            std::lock_guard lock(mutex_);
            try {
                openDevice();
                // The settings the scene is held with, or the smallest renderer
                // (a 1x1 image without auxiliary layers) for a scene it lacks.
                RenderSettings s = uploaded_.settings;
                if (!renderer_ || id != uploaded_.sceneId) s = {.width = 1, .height = 1, .auxiliary = false};
                upload(copy, versions, id, s);
                if (!caster_) caster_ = std::make_unique<RayCaster>(*ctx_);
                uint32_t messagesBefore = ctx_->validationMessageCount();
                hits = caster_->cast(*renderer_, rays);
                throwIfValidationReported(messagesBefore, "cast_rays");
            } catch (const DeviceFailure& e) {
                deviceFailed(e, copy);
            }
        }
        // Object indices to the scene's stable ids, as the object_id mask's (stableObjectIds).
        for (uint32_t& o : hits.object)
            if (o != gpu::kNoObject) o = uint32_t(objectIds[o]);
        py::ssize_t rows = py::ssize_t(n);
        py::dict out;
        out["t"] = ownedArray(std::move(hits.t), {rows});
        out["object_id"] = ownedArray(std::move(hits.object), {rows});
        out["primitive_id"] = ownedArray(std::move(hits.primitive), {rows});
        out["normal"] = ownedArray(std::move(hits.normal), {rows, 3});
        out["uv"] = ownedArray(std::move(hits.uv), {rows, 2});
        return out;
    }

    // The ray tree of pixel (x, y): the dict `whitted trace --json` prints,
    // with its settings (one centre sample, uniform). Checked before the
    // device is touched.
    py::object tracePixel(const SceneRef& handle, int x, int y, std::optional<int> width, std::optional<int> height,
                          int maxDepth) {
        const Scene& scene = *handle->scene;
        auto bad = [](const std::string& what) { throw py::value_error(what); };
        auto side = [&](const char* name, std::optional<int> v, int fallback) {
            int n = v.value_or(fallback);
            if (n < 1 || n > int(gpu::kMaxImageSide))
                bad(std::string(name) + ": must be in 1.." + std::to_string(gpu::kMaxImageSide) + ", got " + std::to_string(n));
            return n;
        };
        RenderSettings s;
        s.width = side("width", width, scene.camera.width);
        s.height = side("height", height, scene.camera.height);
        if (maxDepth < 0 || maxDepth > int(gpu::kMaxDepthLimit))
            bad("max_depth: must be in 0.." + std::to_string(gpu::kMaxDepthLimit) + ", got " + std::to_string(maxDepth));
        std::string image = " is outside the " + std::to_string(s.width) + "x" + std::to_string(s.height) + " image";
        if (x < 0 || x >= s.width) bad("x: " + std::to_string(x) + image);
        if (y < 0 || y >= s.height) bad("y: " + std::to_string(y) + image);
        s = rayTreeSettings(s.width, s.height, maxDepth);
        Scene copy = scene;
        Versions versions = handle->versions;
        uint64_t id = handle->id;
        const std::vector<uint64_t> objectIds = handle->objectIds;
        std::string text;
        {
            py::gil_scoped_release release;
            std::lock_guard lock(mutex_);
            try {
                openDevice();
                uint32_t messagesBefore = ctx_->validationMessageCount();
                upload(copy, versions, id, s);
                if (!recorder_) recorder_ = std::make_unique<RayTreeRecorder>(*ctx_);
                text = rayTreeJson(recorder_->trace(*renderer_, x, y), copy, objectIds);
                throwIfValidationReported(messagesBefore, "this trace");
            } catch (const DeviceFailure& e) {
                deviceFailed(e, copy);
            }
        }
        return py::module_::import("json").attr("loads")(text);
    }

    // The device's queue submissions and memory allocations so far (tests:
    // which of them WHITTED_INJECT_FAULT can fail).
    py::dict deviceEvents() {
        std::lock_guard lock(mutex_);
        openDevice();
        py::dict d;
        d["submissions"] = ctx_->events->submissions();
        d["allocations"] = ctx_->events->allocations();
        return d;
    }

    py::dict device() {
        {
            py::gil_scoped_release release;
            std::lock_guard lock(mutex_);
            openDevice();
        }
        return deviceDict(ctx_->deviceInfo());
    }

private:
    // The device, opened again after one was lost.
    // Validation-layer messages since `before` fail the call (as `whitted render --validate` fails).
    void throwIfValidationReported(uint32_t before, const char* during) const {
        uint32_t now = ctx_->validationMessageCount();
        if (now != before)
            throw std::runtime_error("the Vulkan validation layer reported " + std::to_string(now - before) +
                                     " message(s) during " + during);
    }

    void openDevice() {
        if (!ctx_)
            ctx_ = std::make_unique<VulkanContext>(
                ContextOptions{.validation = validationFromEnvironment(), .deviceName = deviceName_});
    }

    // A lost device or exhausted memory: what was on the device goes (the
    // next call uploads the scene again; after a loss, on a device opened
    // again), and whitted.DeviceError names the scene.
    [[noreturn]] void deviceFailed(const DeviceFailure& e, const Scene& scene) {
        caster_.reset();
        recorder_.reset();
        renderer_.reset();
        uploaded_ = {};
        if (e.lost()) ctx_.reset();
        std::string name = scene.sourcePath.empty() ? std::string("the scene") : scene.sourcePath.string();
        throw e.within(name + ": ");
    }

    // Brings the device's scene to `scene`: a new renderer when the settings
    // (or the scene) changed, else only the parts whose counters moved.
    nlohmann::json upload(const Scene& scene, const Versions& versions, uint64_t id, const RenderSettings& s) {
        nlohmann::json u = {{"renderer", false}, {"geometry", false}, {"bvh", false},
                            {"materials", false}, {"lights", false}, {"camera", false}, {"textures", false}};
        if (!renderer_ || id != uploaded_.sceneId || s != uploaded_.settings) {
            renderer_.reset();  // its device memory goes first
            renderer_ = std::make_unique<Renderer>(*ctx_, scene, s);
            for (auto& [key, value] : u.items()) value = true;
        } else {
            const Versions& was = uploaded_.versions;
            if (versions.geometry != was.geometry) {
                renderer_->setScene(scene);
                u["geometry"] = u["bvh"] = u["materials"] = u["lights"] = u["camera"] = true;
                u["textures"] = renderer_->texturesUploaded();
            } else {
                if (versions.materials != was.materials) {
                    if (!renderer_->setMaterials(scene)) {
                        renderer_->setScene(scene);
                        u["geometry"] = u["bvh"] = u["lights"] = u["camera"] = true;
                        u["textures"] = renderer_->texturesUploaded();
                    }
                    u["materials"] = true;
                }
                if (versions.lights != was.lights && !u["lights"].get<bool>()) {
                    renderer_->setLights(scene);
                    u["lights"] = true;
                }
                if (versions.camera != was.camera && !u["camera"].get<bool>()) {
                    renderer_->setCamera(scene.camera);
                    u["camera"] = true;
                }
            }
        }
        uploaded_ = {id, versions, s};
        return u;
    }

    // uploaded_.versions.camera after a batch: no scene's counter (they
    // count up from 0), so the scene's camera is sent again.
    static constexpr uint64_t kBatchCamera = ~uint64_t(0);

    std::string deviceName_;  // as given: empty for the best
    std::unique_ptr<VulkanContext> ctx_;  // none after a lost device, until the next call
    std::unique_ptr<Renderer> renderer_;
    std::unique_ptr<RayCaster> caster_;  // made on the first cast_rays
    std::unique_ptr<RayTreeRecorder> recorder_;  // beside renderer_: trace_pixel
    Uploaded uploaded_;
    std::mutex mutex_;  // one render at a time per renderer
};

py::list listDevices() {
    py::list out;
    for (const DeviceInfo& d : VulkanContext::listDevices()) {
        py::dict info = deviceDict(d);
        info["suitable"] = d.suitable;
        if (!d.suitable) info["unsuitable"] = d.unsuitable;
        out.append(info);
    }
    return out;
}

Tonemap tonemapFrom(const std::string& t) {
    if (t == "clamp") return Tonemap::Clamp;
    if (t == "seed") return Tonemap::Seed;
    throw py::value_error("tonemap: must be 'clamp' or 'seed', got '" + t + "'");
}

}  // namespace

void addRenderApi(py::module_& m) {
    m.def("devices", &listDevices, "The Vulkan devices: dicts of index, name, type, driver, ray_query, suitable");
    // A lost device or exhausted device memory during a render, cast or
    // trace: the message names the device, the scene and what was being done.
    // The renderer stays usable: its next call uploads again.
    py::register_exception<DeviceFailure>(m, "DeviceError", PyExc_RuntimeError);

    py::class_<Result, ResultRef>(m, "RenderResult", "What a render gives: the image, its auxiliary images, its record")
        .def_property_readonly(
            "image",
            [](Result& r) {
                if (!r.image) r.image = r.values("image");
                return r.image;
            },
            "float32 (H, W, 3), linear: the values of the EXR `whitted render` writes; with render(alpha=True) "
            "(H, W, 4): the colour premultiplied by the alpha, the coverage")
        .def_property_readonly(
            "aovs",
            [](Result& r) {
                if (!r.aovArrays) {
                    py::dict d;
                    for (const std::string& name : r.aovs) d[py::str(name)] = r.values(name);
                    r.aovArrays = d;
                }
                return r.aovArrays;
            },
            "name -> array (H, W, 3) or (H, W), the values of the auxiliary EXR files: float32, but the masks "
            "object_id and material_id uint32 (the ids; 0xFFFFFFFF: no object)")
        .def_property_readonly(
            "record",
            [](Result& r) {
                if (!r.record) r.record = py::module_::import("json").attr("loads")(r.recordJson({}, "clamp"));
                return r.record;
            },
            "the render.json content, with 'uploads': what this render sent to the device")
        .def_property_readonly("masks", &masksDict,
                               "with the object_id mask: object id -> {name, type, material, material_id}; the ids "
                               "are the scene's, stable across renders and add/remove")
        .def_property_readonly("width", [](const Result& r) { return r.pixels.layout.region.width(); })
        .def_property_readonly("height", [](const Result& r) { return r.pixels.layout.region.height(); })
        .def(
            "save",
            [](const Result& r, const std::filesystem::path& path, const std::string& tonemap) {
                Tonemap t = tonemapFrom(tonemap);
                py::gil_scoped_release release;
                return r.save(path, t);
            },
            py::arg("path"), py::arg("tonemap") = "clamp",
            "Writes the files `whitted render -o path` writes (auxiliary images beside it, the record as .json); "
            "returns the image paths")
        .def("_repr_png_", [](const Result& r) {
            // The PNG through the same writer, in a private temporary folder.
            std::string tmpl = (std::filesystem::temp_directory_path() / "whitted-XXXXXX").string();
            if (!::mkdtemp(tmpl.data())) throw std::runtime_error("cannot create a temporary folder");
            std::filesystem::path dir = tmpl, png = dir / "image.png";
            ImageFileSink sink(png, {}, Tonemap::Clamp, r.pixels.layout, r.settings.samplesPerPixel);
            sink.writeBand(r.pixels.whole());
            sink.finish();
            std::ifstream in(png, std::ios::binary);
            std::string bytes((std::istreambuf_iterator<char>(in)), {});
            std::filesystem::remove_all(dir);
            return py::bytes(bytes);
        });

    py::class_<PyRenderer>(m, "Renderer",
                           "Holds a Vulkan device, the pipeline and the uploaded scene between renders. "
                           "A renderer renders one scene at a time (calls from several threads wait in turn); "
                           "renderers on different threads render at the same time.")
        .def(py::init([](const py::object& device) { return std::make_unique<PyRenderer>(deviceArg(device)); }),
             py::arg("device") = py::none(),
             "device: an index (int) or a name substring as whitted.devices() and `whitted devices` list them "
             "(None: the best)")
        .def_property_readonly("device", &PyRenderer::device)
        .def_property_readonly("_device_events", &PyRenderer::deviceEvents,
                               "the device's queue submissions and memory allocations so far (for tests)")
        .def("cast_rays", &PyRenderer::castRays, py::arg("scene"), py::arg("origins"), py::arg("directions"),
             py::arg("t_max") = std::numeric_limits<double>::infinity(),
             "What each ray origins[i] + t * directions[i], 0 < t < t_max, hits first in the scene, found on the "
             "device by the renderer's own closest-hit query (host/python/README.md \"Ray casting\"). origins, "
             "directions: (N, 3) float32 or float64 (directions of any nonzero length); t_max: a number or (N,), "
             "in units of each direction. Returns a dict of numpy arrays: t (N,) float32 (inf: a miss; a hit whose t "
             "overflows float32 is one), object_id "
             "(N,) uint32 (the object_id mask's ids, 0xFFFFFFFF: a miss), primitive_id (N,) uint32 (a mesh's "
             "triangle index, a csg object's leaf, else 0), normal (N, 3) float32 (the unit geometric normal, "
             "outward), uv (N, 2) float32. Releases the GIL.")
        .def("trace_pixel", &PyRenderer::tracePixel, py::arg("scene"), py::arg("x"), py::arg("y"), py::kw_only(),
             py::arg("width") = py::none(), py::arg("height") = py::none(), py::arg("max_depth") = 6,
             "The ray tree behind pixel (x, y) (the options of `whitted trace`): the dict `whitted trace --json` "
             "prints, each object with its \"id\" as result.masks and the object_id mask number it. Bad values raise "
             "ValueError naming the argument before the device is touched")
        .def("render", &PyRenderer::render, py::arg("scene"), py::kw_only(), py::arg("width") = py::none(),
             py::arg("height") = py::none(), py::arg("spp") = 16, py::arg("aa") = "adaptive",
             py::arg("aa_threshold") = py::none(), py::arg("max_depth") = 6, py::arg("aovs") = py::tuple(),
             py::arg("aov_bounces") = 0, py::arg("region") = py::none(), py::arg("trace") = "auto",
             py::arg("progress") = py::none(), py::arg("cameras") = py::none(), py::arg("seed") = 0,
             py::arg("alpha") = false, py::arg("environment_sampling") = "importance",
             "Renders the scene (the options of `whitted render`); returns a RenderResult. Releases the GIL; "
             "progress(fraction) is called after every submission to the device, where Ctrl+C stops the render. "
             "cameras=[Camera, ...] "
             "(e.g. scene.camera.copy() after edits): one render per camera, the scene uploaded once, only the "
             "camera block between them; returns a list of RenderResult (width/height default to the cameras' "
             "size, which must then agree). seed (0..2^32-1, default 0: today's patterns): the sample positions within "
             "each pixel; the same seed gives the same pixels across calls, regions, threads and renderers. alpha=True: "
             "the background transparent (`--background transparent`): camera rays do not see the environment, and "
             "image gets the coverage as a fourth channel. environment_sampling='uniform': an image environment's "
             "light directions drawn uniformly over the sphere instead of by its luminance (for comparisons)");
}

}  // namespace whitted::python
