// libFuzzer target for the XML scene loader (tools/run_fuzzer.sh builds and
// runs it). Whatever the bytes, loadSceneFromString must either refuse them
// with a SceneError or return a scene that keeps the loader's promises
// (scenes/README.md "Scene files"). Anything else is a finding: another exception
// (std::terminate aborts), a crash, an AddressSanitizer or
// UndefinedBehaviorSanitizer report, a scene with a non-finite or
// out-of-range value (__builtin_trap), a hang or runaway memory.
#include "scene/scene_loader.h"

#include "scene_checks.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

using namespace whitted;
using whitted::fuzz::check;
using whitted::fuzz::checkScene;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::string_view xml(reinterpret_cast<const char*>(data), size);
    try {
        checkScene(loadSceneFromString(xml, "fuzz.xml"));
    } catch (const SceneError& e) {
        // The refusal must name the file and say something.
        check(e.file() == "fuzz.xml" && !e.message().empty() && e.line() >= 0);
    }
    return 0;
}
