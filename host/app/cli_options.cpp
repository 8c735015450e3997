#include "app/cli_options.h"

#include <charconv>
#include <iostream>
#include <stdexcept>

namespace whitted {

PixelRegion parsePixelRegion(const std::string& text) {
    auto refused = [&] {
        return std::invalid_argument("expected X0,Y0,X1,Y1 (four integers), got '" + text + "'");
    };
    int v[4] = {};
    const char* at = text.data();
    const char* end = text.data() + text.size();
    for (int i = 0; i < 4; ++i) {
        if (i > 0) {
            if (at == end || *at != ',') throw refused();
            ++at;
        }
        auto [next, error] = std::from_chars(at, end, v[i]);
        if (error != std::errc()) throw refused();
        at = next;
    }
    if (at != end) throw refused();
    return {v[0], v[1], v[2], v[3]};
}

void printSceneWarnings(const Scene& scene, bool verbose) {
    for (const std::string& warning : scene.warnings) std::cerr << "warning: " << warning << "\n";
    if (verbose)
        for (const std::string& detail : scene.warningDetails) std::cerr << "  " << detail << "\n";
}

}  // namespace whitted
