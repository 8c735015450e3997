#include "io/image_library.h"

#include <dlfcn.h>

#include <filesystem>
#include <string>
#include <vector>
#include <stdexcept>

namespace whitted {
namespace {

struct Loaded {
    const ImageLibrary* library = nullptr;
    std::string error;  // the places tried and why each failed
};

#ifdef WHITTED_IMAGE_LIBRARY_STATIC
// Linked in (the fuzzer): nothing to load.
Loaded load() { return {whittedImageLibrary(kImageLibraryAbi), ""}; }
#else
// The module beside the executable, then where the build wrote it.
Loaded load() {
    std::vector<std::filesystem::path> candidates;
    std::error_code ec;
    std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) candidates.push_back(self.parent_path() / "whitted_image_io.so");
    candidates.push_back(WHITTED_IMAGE_LIBRARY_PATH);
    Loaded result;
    for (const std::filesystem::path& candidate : candidates) {
        void* handle = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            const char* why = dlerror();
            result.error += "\n  " + std::string(why ? why : candidate.string() + ": not loaded");
            continue;
        }
        auto entry = reinterpret_cast<const ImageLibrary* (*)(uint32_t)>(dlsym(handle, "whittedImageLibrary"));
        if (entry) result.library = entry(kImageLibraryAbi);
        if (result.library) return result;
        result.error += "\n  " + candidate.string() + ": not this build's image module";
        dlclose(handle);
    }
    return result;
}
#endif

// The load, once per process (the dynamic loader's state is per process).
const Loaded& loaded() {
    static const Loaded result = load();
    return result;
}

}  // namespace

const ImageLibrary& imageLibrary() {
    const Loaded& result = loaded();
    if (!result.library)
        throw std::runtime_error("cannot load the image file module (OpenImageIO):" + result.error);
    return *result.library;
}

}  // namespace whitted
