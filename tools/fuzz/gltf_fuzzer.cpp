// libFuzzer target for the glTF 2.0 reader and its mapping into a scene
// (io/gltf_file.cpp, scene/authored_scene.cpp; tools/run_fuzzer.sh builds
// and runs it, seeded from tests/fuzz_corpus/gltf). The bytes are a .gltf or
// a .glb (the reader tells them by their first four bytes), data: URIs and
// base64 included. Whatever they are, loadGltfScene must refuse them with a
// SceneError naming the file or return a scene that keeps the loader's
// promises (scene_checks.h). Anything else is a finding: another exception,
// a crash, a sanitizer report, a hang or runaway memory.
#include "scene/authored_scene.h"
#include "scene/scene_error.h"

#include "model_file.h"
#include "scene_checks.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

using namespace whitted;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::filesystem::path file =
        fuzz::writeScratch("fuzz.gltf", std::string_view(reinterpret_cast<const char*>(data), size));
    try {
        fuzz::checkScene(loadGltfScene(file).scene);
    } catch (const SceneError& e) {
        fuzz::check(e.file() == file.string() && !e.message().empty() && e.line() == 0);
    }
    return 0;
}
