#include "app/interrupt.h"

#include <atomic>
#include <csignal>

namespace whitted {
namespace {

std::atomic<bool> interrupted{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the handler may only touch a lock-free atomic");

using Handler = void (*)(int);
Handler previousInt = SIG_DFL;
Handler previousTerm = SIG_DFL;

extern "C" void onSignal(int signal) {
    interrupted.store(true);
    std::signal(signal, SIG_DFL);  // the second one ends the process
}

}  // namespace

InterruptScope::InterruptScope() {
    interrupted.store(false);
    previousInt = std::signal(SIGINT, onSignal);
    previousTerm = std::signal(SIGTERM, onSignal);
}

InterruptScope::~InterruptScope() {
    std::signal(SIGINT, previousInt);
    std::signal(SIGTERM, previousTerm);
}

void throwIfInterrupted() {
    if (interrupted.load()) throw Interrupted{};
}

}  // namespace whitted
