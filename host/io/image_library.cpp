#include "io/image_library.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <future>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <thread>

namespace whitted {
namespace {

struct Loaded {
    const ImageLibrary* library = nullptr;
    std::string error;  // the places tried and why each failed
};

#ifdef WHITTED_IMAGE_LIBRARY_STATIC
// Linked in (the fuzzer, the sanitizer build): nothing to load.
Loaded load() { return {whittedImageLibrary(kImageLibraryAbi), ""}; }
#else
// The module beside the executable, beside the shared object holding this
// code (the Python module, installed with it), then where the build wrote it.
Loaded load() {
    std::vector<std::filesystem::path> candidates;
    std::error_code ec;
    std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) candidates.push_back(self.parent_path() / "whitted_image_io.so");
    Dl_info info{};
    if (dladdr(reinterpret_cast<void*>(&load), &info) && info.dli_fname)
        candidates.push_back(std::filesystem::path(info.dli_fname).parent_path() / "whitted_image_io.so");
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

// Debian's OpenImageIO pulls in OpenBLAS (through OpenCV), whose thread
// pool starts with the library, a thread a core, and spins (sched_yield)
// for a while before it sleeps: loaded beside the pipeline build, those
// threads took a core from the render that followed (measured: see
// tools/benchmark_results/README.md). whitted never calls BLAS, so the
// pool gets one thread, set before main() while the process has one thread
// (setenv is not safe beside threads reading the environment); a user's
// own setting is kept.
[[maybe_unused]] const bool kOpenBlasSingleThreaded = [] { return setenv("OPENBLAS_NUM_THREADS", "1", 0) == 0; }();

// The load, once per process: started ahead by preloadImageLibrary, or run
// by the first imageLibrary() (deferred).
struct Pending {
    std::mutex mutex;
    std::shared_future<Loaded> loaded;
};

Pending& pending() {
    static Pending p;
    return p;
}

// The load, started unless it was: on another thread (async) or by the
// first get() (deferred).
std::shared_future<Loaded> start(std::launch policy) {
    Pending& p = pending();
    std::lock_guard lock(p.mutex);
    if (!p.loaded.valid()) p.loaded = std::async(policy, load).share();
    return p.loaded;
}

// Threads running or ready to run on the machine now, this one included
// (Linux: /proc/stat's procs_running); a large number when unknown.
unsigned runnableThreads() {
    std::ifstream in("/proc/stat");
    std::string key;
    unsigned count = 0;
    while (in >> key) {
        if (key == "procs_running" && in >> count) return count;
        in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
    }
    return std::numeric_limits<unsigned>::max();
}

}  // namespace

const ImageLibrary& imageLibrary() {
    const Loaded& loaded = start(std::launch::deferred).get();
    if (!loaded.library)
        throw std::runtime_error("cannot load the image file module (OpenImageIO):" + loaded.error);
    return *loaded.library;
}

void preloadImageLibrary() {
    if (runnableThreads() < std::thread::hardware_concurrency()) start(std::launch::async);
}

}  // namespace whitted
