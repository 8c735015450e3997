// Ctrl+C during a command: the signal handler only records the signal; the
// work stops at its next check (a render checks after every submission to
// the device), unwinding removes what it was writing (temporary files, a
// history folder), and main() exits with kExitInterrupted. A second Ctrl+C
// ends the process at once, as without the handler.
#pragma once

#include <stdexcept>

namespace whitted {

// Thrown by throwIfInterrupted(); main() reports it and exits 130.
struct Interrupted : std::runtime_error {
    Interrupted() : std::runtime_error("interrupted") {}
};

// Catches SIGINT and SIGTERM while it lives, then restores the handlers it
// replaced. One at a time.
class InterruptScope {
public:
    InterruptScope();
    ~InterruptScope();
    InterruptScope(const InterruptScope&) = delete;
    InterruptScope& operator=(const InterruptScope&) = delete;
};

// Throws Interrupted once a signal arrived within an InterruptScope.
void throwIfInterrupted();

}  // namespace whitted
