// Scripted input for the live window (`whitted view --script FILE`), so that
// tests can drive it under Xvfb. One command per line, run in order; '#'
// starts a comment. Waiting commands hold the script until their condition
// holds (at most kScriptWaitSeconds, then the run fails):
//   frames N              wait N frames
//   spp N                 wait until every pixel has N samples (at most --spp)
//   reload                wait until the scene file has been reloaded (or refused)
//   key NAME              press and release a key (A..Z, 0..9, ESCAPE, F1, TAB, SPACE)
//   hold NAME SECONDS     hold a key down (flying with W/A/S/D/Q/E)
//   drag BUTTON DX DY     drag with left, right or middle by DX, DY pixels
//   scroll STEPS          the mouse wheel
//   copy FROM TO          copy a file (an edit of the watched scene)
//   replace FILE OLD NEW  replace the first OLD by NEW in FILE, written in place
//   edit OBJECT FIELD V   what the editor panel does: object index, field
//                         (view/editor_panel.h: ior | kt | kr | ks | kd | ka | x | y | z |
//                         checker_size | checker_r|g|b | absorption_r|g|b | operation |
//                         texture_scale | normal_strength), value
//   select light|object N select an entry in the editor panel (shows its fields)
//   pick X Y              what T then a click on image pixel X,Y does: show its
//                         ray tree (view/ray_tree_overlay.h)
//   layer NAME            show an auxiliary image (color = the main image; view/layer_views.h)
//   screenshot FILE       write the image shown (without overlay) as PNG
//   window_screenshot FILE  write the whole window, overlay included
//   save_images           what the P key does: the images into the history
//   save_scene            what the panel's Save does
//   quit
// Paths are relative to the working directory. Every argument is checked
// when the script is loaded, before the window opens; view/script_runner.h
// carries the commands out.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <variant>
#include <vector>

#include "scene/scene.h"
#include "view/editor_panel.h"

namespace whitted {

inline constexpr double kScriptWaitSeconds = 120.0;

// One struct per command, its arguments typed (keys and buttons as GLFW
// codes, layers as indices into layerViews).
namespace script {
struct Frames { long count; };
struct Spp { uint32_t samples; };
struct Reload {};
struct Key { int key; };
struct Hold { int key; double seconds; };
struct Drag { int button; double dx, dy; };
struct Scroll { double steps; };
struct Copy { std::filesystem::path from, to; };
struct Replace { std::filesystem::path file; std::string text, replacement; };
struct Edit { int object; ObjectField field; double value; };
struct Select { bool light; int index; };
struct Layer { size_t index; };
struct Pick { int x, y; };
struct Screenshot { std::filesystem::path path; bool window; };
struct SaveImages {};
struct SaveScene {};
struct Quit {};
}  // namespace script

using ScriptAction = std::variant<script::Frames, script::Spp, script::Reload, script::Key, script::Hold, script::Drag,
                                  script::Scroll, script::Copy, script::Replace, script::Edit, script::Select,
                                  script::Layer, script::Screenshot, script::SaveImages, script::SaveScene,
                                  script::Quit, script::Pick>;

struct ScriptCommand {
    int line = 0;
    std::string name;  // as written, for messages
    ScriptAction action;
};

// What the arguments are checked against: the window's options.
struct ScriptLimits {
    uint32_t sampleBudget = 1;  // --spp
    int aovBounces = 0;         // --aov-bounces (the reflection.K layers)
};

// Reads and checks a script; throws std::invalid_argument "FILE:LINE: ..."
// for an unknown command, a wrong number of arguments or an argument that
// is not what the command takes.
std::vector<ScriptCommand> loadScript(const std::filesystem::path& path, const ScriptLimits& limits);

// The checks that need the scene: each `edit` before the script's first
// file change (copy, replace) is tried on a copy of the scene, in order, so
// that an object index out of range or a field the object lacks is refused
// before the window opens. Throws std::invalid_argument "FILE:LINE: edit: ...".
void checkScriptOnScene(const std::filesystem::path& path, const std::vector<ScriptCommand>& commands,
                        const Scene& scene);

}  // namespace whitted
