#include "app/progress_bar.h"

#include <cstdio>
#include <unistd.h>

namespace whitted {

ProgressBar::ProgressBar(std::string label, bool enabled)
    : label_(std::move(label)), enabled_(enabled && ::isatty(STDERR_FILENO)) {}

void ProgressBar::update(double fraction) {
    if (!enabled_) return;
    auto now = std::chrono::steady_clock::now();
    if (fraction < 1.0 && now - lastDraw_ < std::chrono::milliseconds(100)) return;
    lastDraw_ = now;
    double elapsed = std::chrono::duration<double>(now - start_).count();
    double eta = fraction > 0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
    constexpr int kWidth = 30;
    int filled = int(fraction * kWidth + 0.5);
    std::string bar(filled, '#');
    bar.append(kWidth - filled, '.');
    std::fprintf(stderr, "\r%s [%s] %3d%%  %.1fs elapsed, ETA %.1fs ", label_.c_str(), bar.c_str(),
                 int(fraction * 100.0), elapsed, eta);
    std::fflush(stderr);
    drawn_ = true;
}

void ProgressBar::finish() {
    if (drawn_) std::fprintf(stderr, "\r\033[K");
    drawn_ = false;
}

}  // namespace whitted
