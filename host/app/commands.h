// The command-line verbs. Each sets up its own options on the CLI11 app
// beside its code (render_command.cpp, view_command.cpp, devices_command.cpp,
// trace_command.cpp, convert_command.cpp); main.cpp only registers them, parses
// and calls the one given.
#pragma once

#include <functional>

namespace CLI {
class App;
}

namespace whitted {

// Exit statuses shared by every command.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;     // device or I/O failure
inline constexpr int kExitBadInput = 2;    // bad scene file or arguments
inline constexpr int kExitValidation = 3;  // the Vulkan validation layer reported a problem
inline constexpr int kExitInterrupted = 130;  // Ctrl+C (128 + SIGINT, as shells report it); nothing written

// A verb registered on the command line: its subcommand, and what runs
// (after parsing) when it is the one given. `run` returns the exit status.
struct Command {
    CLI::App* subcommand = nullptr;
    std::function<int()> run;
};

Command addRenderCommand(CLI::App& app);
Command addDevicesCommand(CLI::App& app);
Command addViewCommand(CLI::App& app);
Command addTraceCommand(CLI::App& app);
Command addConvertCommand(CLI::App& app);

}  // namespace whitted
