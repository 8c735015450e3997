// A progress bar with an ETA on stderr, redrawn in place on a terminal and
// silent elsewhere (logs and CI get the summary line only).
#pragma once

#include <chrono>
#include <string>

namespace whitted {

class ProgressBar {
public:
    ProgressBar(std::string label, bool enabled);
    void update(double fraction);
    void finish();

private:
    std::string label_;
    bool enabled_;
    bool drawn_ = false;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
    std::chrono::steady_clock::time_point lastDraw_{};
};

}  // namespace whitted
