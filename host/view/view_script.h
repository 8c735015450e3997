// Scripted input for the live window (`whitted view --script FILE`), so that
// tests can drive it under Xvfb. One command per line, run in order; '#'
// starts a comment. Waiting commands hold the script until their condition
// holds (at most kScriptWaitSeconds, then the run fails):
//   frames N              wait N frames
//   spp N                 wait until every pixel has N samples
//   reload                wait until the scene file has been reloaded (or refused)
//   key NAME              press and release a key (W, R, L, C, P, ESCAPE, ...)
//   hold NAME SECONDS     hold a key down (flying with W/A/S/D/Q/E)
//   drag BUTTON DX DY     drag with left, right or middle by DX, DY pixels
//   scroll STEPS          the mouse wheel
//   copy FROM TO          copy a file (an edit of the watched scene)
//   replace FILE OLD NEW  replace the first OLD by NEW in FILE, written in place
//   edit OBJECT FIELD V   what the editor panel does: object index, field
//                         ior | kt | kr | ks | kd | ka | x | y | z | checker_size |
//                         checker_r|g|b | absorption_r|g|b | operation (csg: 0 union,
//                         1 intersection, 2 difference), value
//   select light|object N select an entry in the editor panel (shows its fields)
//   layer NAME            show an auxiliary image (color = the main image)
//   screenshot FILE       write the image shown (without overlay) as PNG
//   window_screenshot FILE  write the whole window, overlay included
//   save_images           what the P key does: the images into the history
//   save_scene            what the panel's Save does
//   quit
// Paths are relative to the working directory.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace whitted {

inline constexpr double kScriptWaitSeconds = 120.0;

struct ScriptCommand {
    int line = 0;
    std::string name;
    std::vector<std::string> args;
};

// Reads and checks a script; throws std::invalid_argument "FILE:LINE: ..."
// for an unknown command or a wrong number of arguments.
std::vector<ScriptCommand> loadScript(const std::filesystem::path& path);

}  // namespace whitted
