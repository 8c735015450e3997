// whitted: the command line. Each command sets up its own options beside
// its code in host/app/ (app/commands.h); here they are registered, the
// arguments parsed, the command given run, and a failure caught once.
#include "app/commands.h"
#include "app/interrupt.h"

#include <CLI/CLI.hpp>

#include <iostream>

int main(int argc, char** argv) {
    using namespace whitted;
    CLI::App app{"whitted: a Whitted-style ray tracer on Vulkan compute"};
    app.set_version_flag("--version", std::string("whitted ") + WHITTED_VERSION);
    app.require_subcommand(1);
    const Command commands[] = {addRenderCommand(app), addDevicesCommand(app), addViewCommand(app),
                                addTraceCommand(app), addConvertCommand(app)};

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        int status = app.exit(e);
        return status == 0 ? kExitOk : kExitBadInput;
    }

    try {
        for (const Command& command : commands)
            if (command.subcommand->parsed()) return command.run();
        return kExitBadInput;  // not reached: parsing requires one command
    } catch (const Interrupted&) {
        std::cerr << "whitted: interrupted; nothing written\n";
        return kExitInterrupted;
    } catch (const std::exception& e) {
        std::cerr << "whitted: " << e.what() << "\n";
        return kExitFailure;
    }
}
