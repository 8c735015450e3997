// `whitted convert INPUT -o OUT.xml`: any input the other commands take (a
// scene file, a model file through its quick look) written as a whitted
// scene file by the scene writer the window's Save uses, so that it can be
// edited and renders as the input does.
#include "app/commands.h"
#include "app/quick_look.h"
#include "io/atomic_file.h"
#include "io/image_io.h"
#include "io/texture.h"
#include "scene/scene_error.h"
#include "scene/scene_writer.h"

#include <CLI/CLI.hpp>
#include <glm/gtc/packing.hpp>

#include <filesystem>
#include <functional>
#include <map>
#include <iostream>
#include <memory>

namespace whitted {
namespace {

struct ConvertOptions {
    std::filesystem::path input;
    std::filesystem::path output;
};

// Textures a file carries inside it (a .glb's images, base64 in a .gltf)
// have no path the scene file could name: each is written beside the output
// as OUT.textureK.png (or .jpg), the very bytes the file held, so that the
// converted scene decodes the same texels. A texture made on the host (an
// MTL height map turned into a normal map) is written as OUT.textureK.exr,
// its full-resolution level as the half floats it holds; its coarser levels,
// built again from those, can then differ in the last bits.
void writeEmbeddedTextures(Scene& scene, const std::filesystem::path& output) {
    std::map<const TextureData*, std::string> written;  // one file per texture, however many use it
    auto extract = [&](TextureRef& ref) {
        if (!ref || !ref.written.empty() || ref.data->levels.empty()) return;
        if (auto it = written.find(ref.data.get()); it != written.end()) {
            ref.written = it->second;
            return;
        }
        const TextureData& data = *ref.data;
        std::string stem = output.stem().string() + ".texture" + std::to_string(written.size());
        std::filesystem::path file;
        if (!data.encoded.empty()) {
            file = stem + "." + data.encodedFormat;
            std::string bytes(data.encoded.begin(), data.encoded.end());
            writeTextFile(output.parent_path() / file, bytes);  // atomic; the bytes as they are
        } else {
            const TextureLevel& level = data.levels[0];
            std::vector<float> texels(level.rgba.size());
            for (size_t i = 0; i < texels.size(); ++i) texels[i] = glm::unpackHalf1x16(level.rgba[i]);
            file = stem + ".exr";
            writeImage(output.parent_path() / file, level.width, level.height, 4, texels, PixelEncoding::Float);
        }
        // Absolute: the writer makes texture paths relative to the file it writes.
        ref.written = written[ref.data.get()] = std::filesystem::absolute(output.parent_path() / file).string();
    };
    auto material = [&](Material& m) {
        for (TextureRef* t : m.textures()) extract(*t);
    };
    std::function<void(Csg&)> children = [&](Csg& csg) {
        for (CsgChild& child : csg.children) {
            material(child.material);
            if (Csg* inner = std::get_if<Csg>(&child.shape)) children(*inner);
        }
    };
    for (Object& object : scene.objects) {
        material(object.material);
        if (Csg* csg = std::get_if<Csg>(&object.shape)) children(*csg);
    }
}

int runConvert(const ConvertOptions& options) {
    Scene scene;
    try {
        scene = loadSceneOrModel(options.input);
    } catch (const SceneError& e) {
        std::cerr << e.what() << "\n";
        return kExitBadInput;
    }
    for (const std::string& warning : scene.warnings) std::cerr << "warning: " << warning << "\n";
    std::filesystem::path folder = options.output.parent_path().empty() ? "." : options.output.parent_path();
    if (!std::filesystem::is_directory(folder)) {
        std::cerr << "whitted: " << options.output.string() << ": the folder " << folder.string()
                  << " does not exist\n";
        return kExitBadInput;
    }
    writeEmbeddedTextures(scene, options.output);
    writeSceneFile(scene, options.output);  // atomic: a temporary file renamed when complete
    return kExitOk;
}

}  // namespace

Command addConvertCommand(CLI::App& app) {
    auto options = std::make_shared<ConvertOptions>();
    auto* cmd = app.add_subcommand("convert", "write a scene or model file as a whitted XML scene");
    cmd->add_option("input", options->input, "scene file (.xml) or model file (.obj, .glb, .ply, ...)")->required();
    cmd->add_option("-o,--output", options->output, "the XML scene file to write")->required();
    return {cmd, [options] { return runConvert(*options); }};
}

}  // namespace whitted
