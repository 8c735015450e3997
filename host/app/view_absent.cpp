// `whitted view` in a build without the live window (-DWHITTED_BUILD_VIEW=OFF,
// the headless GPU kit of tools/gpu_kit.sh): the command exists, takes any
// arguments and says that this build has no window.
#include <iostream>

#include "app/commands.h"

#include <CLI/CLI.hpp>

namespace whitted {

Command addViewCommand(CLI::App& app) {
    auto* cmd = app.add_subcommand("view", "the live window (not in this build: WHITTED_BUILD_VIEW=OFF)");
    cmd->allow_extras();
    return {cmd, [] {
                std::cerr << "whitted: this build has no live window (configured with -DWHITTED_BUILD_VIEW=OFF); "
                             "use `whitted render`\n";
                return kExitFailure;
            }};
}

}  // namespace whitted
