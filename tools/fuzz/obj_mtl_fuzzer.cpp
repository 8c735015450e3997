// libFuzzer target for the OBJ reader (through Assimp, io/mesh_file.cpp),
// the MTL reader (io/mtl_file.cpp) and their mapping into a scene
// (scene/authored_scene.cpp); tools/run_fuzzer.sh builds and runs it, seeded
// from tests/fuzz_corpus/obj_mtl. The bytes are an OBJ file, then, after a
// line "#@mtl", the MTL library fuzz.mtl that `mtllib fuzz.mtl` names.
// loadObjMtlScene must refuse them with a SceneError naming one of the two
// files or return a scene that keeps the loader's promises (scene_checks.h).
#include "scene/authored_scene.h"
#include "scene/scene_error.h"

#include "model_file.h"
#include "scene_checks.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

using namespace whitted;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::string_view bytes(reinterpret_cast<const char*>(data), size);
    constexpr std::string_view kSplit = "\n#@mtl\n";
    const size_t split = bytes.find(kSplit);
    const std::string_view obj = bytes.substr(0, split);
    const std::string_view mtl = split == std::string_view::npos ? std::string_view() : bytes.substr(split + kSplit.size());
    const std::filesystem::path objFile = fuzz::writeScratch("fuzz.obj", obj);
    const std::filesystem::path mtlFile = fuzz::writeScratch("fuzz.mtl", mtl);
    try {
        fuzz::checkScene(loadObjMtlScene(objFile).scene);
    } catch (const SceneError& e) {
        fuzz::check((e.file() == objFile.string() || e.file() == mtlFile.string()) && !e.message().empty() &&
                    e.line() >= 0);
    }
    return 0;
}
