#include "view/view_script.h"

#include "view/layer_views.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace whitted {
namespace {

// A whole word as a number of type T (std::from_chars: no '+', no spaces;
// "inf" and "nan" read as doubles).
template <typename T>
std::optional<T> number(const std::string& word) {
    T value{};
    auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
    if (error != std::errc() || end != word.data() + word.size()) return std::nullopt;
    return value;
}

// A distance or a duration: a finite double.
std::optional<double> finiteNumber(const std::string& word) {
    std::optional<double> value = number<double>(word);
    if (value && !std::isfinite(*value)) return std::nullopt;
    return value;
}

int keyByName(const std::string& name) {
    static const std::map<std::string, int> named = {
        {"ESCAPE", GLFW_KEY_ESCAPE}, {"F1", GLFW_KEY_F1}, {"TAB", GLFW_KEY_TAB}, {"SPACE", GLFW_KEY_SPACE}};
    if (auto it = named.find(name); it != named.end()) return it->second;
    if (name.size() == 1 && name[0] >= 'A' && name[0] <= 'Z') return GLFW_KEY_A + (name[0] - 'A');
    if (name.size() == 1 && name[0] >= '0' && name[0] <= '9') return GLFW_KEY_0 + (name[0] - '0');
    return GLFW_KEY_UNKNOWN;
}

// One command's arguments, typed; throws std::invalid_argument with what
// is wrong (loadScript puts FILE:LINE before it).
ScriptAction parseAction(const std::string& name, const std::vector<std::string>& args, const ScriptLimits& limits) {
    auto refuse = [](const std::string& what) { return std::invalid_argument(what); };
    if (name == "frames") {
        auto n = number<long>(args[0]);
        if (!n || *n < 0) throw refuse("frames needs a count");
        return script::Frames{*n};
    }
    if (name == "spp") {
        auto n = number<long>(args[0]);
        if (!n || *n < 1) throw refuse("spp needs a count >= 1");
        if (*n > long(limits.sampleBudget)) throw refuse("spp " + args[0] + " is above the --spp budget");
        return script::Spp{uint32_t(*n)};
    }
    if (name == "reload") return script::Reload{};
    if (name == "key") {
        int key = keyByName(args[0]);
        if (key == GLFW_KEY_UNKNOWN) throw refuse("unknown key '" + args[0] + "'");
        return script::Key{key};
    }
    if (name == "hold") {
        int key = keyByName(args[0]);
        auto seconds = finiteNumber(args[1]);
        if (key == GLFW_KEY_UNKNOWN || !seconds || *seconds < 0) throw refuse("hold KEY SECONDS");
        return script::Hold{key, *seconds};
    }
    if (name == "drag") {
        static const std::map<std::string, int> buttons = {{"left", GLFW_MOUSE_BUTTON_LEFT},
                                                           {"right", GLFW_MOUSE_BUTTON_RIGHT},
                                                           {"middle", GLFW_MOUSE_BUTTON_MIDDLE}};
        auto b = buttons.find(args[0]);
        auto dx = finiteNumber(args[1]), dy = finiteNumber(args[2]);
        if (b == buttons.end() || !dx || !dy) throw refuse("drag left|right|middle DX DY");
        return script::Drag{b->second, *dx, *dy};
    }
    if (name == "scroll") {
        auto steps = finiteNumber(args[0]);
        if (!steps) throw refuse("scroll STEPS");
        return script::Scroll{*steps};
    }
    if (name == "copy") return script::Copy{args[0], args[1]};
    if (name == "replace") return script::Replace{args[0], args[1], args[2]};
    if (name == "edit") {
        auto object = number<int>(args[0]);
        auto value = number<double>(args[2]);  // not finite: refused below, as the panel refuses it
        if (!object || *object < 0 || !value) throw refuse("edit OBJECT FIELD VALUE");
        std::optional<ObjectField> field = objectFieldNamed(args[1]);
        if (!field) throw refuse("edit: " + unknownObjectField(args[1]));
        if (auto error = objectFieldValueError(*field, *value)) throw refuse("edit: " + *error);
        return script::Edit{*object, *field, *value};
    }
    if (name == "select") {
        auto index = number<int>(args[1]);
        if ((args[0] != "light" && args[0] != "object") || !index || *index < 0)
            throw refuse("select light|object N");
        return script::Select{args[0] == "light", *index};
    }
    if (name == "layer") {
        std::vector<LayerView> layers = layerViews(1, 1, limits.aovBounces);
        for (size_t i = 0; i < layers.size(); ++i)
            if (layers[i].name == args[0]) return script::Layer{i};
        throw refuse("unknown layer '" + args[0] + "'");
    }
    if (name == "pick") {
        auto x = number<int>(args[0]), y = number<int>(args[1]);
        if (!x || !y || *x < 0 || *y < 0) throw refuse("pick X Y (an image pixel)");
        return script::Pick{*x, *y};
    }
    if (name == "screenshot" || name == "window_screenshot")
        return script::Screenshot{args[0], name == "window_screenshot"};
    if (name == "save_images") return script::SaveImages{};
    if (name == "save_scene") return script::SaveScene{};
    return script::Quit{};
}

}  // namespace

std::vector<ScriptCommand> loadScript(const std::filesystem::path& path, const ScriptLimits& limits) {
    static const std::map<std::string, size_t> kArity = {{"frames", 1},
                                                         {"spp", 1},
                                                         {"reload", 0},
                                                         {"key", 1},
                                                         {"hold", 2},
                                                         {"drag", 3},
                                                         {"scroll", 1},
                                                         {"copy", 2},
                                                         {"replace", 3},
                                                         {"edit", 3},
                                                         {"layer", 1},
                                                         {"screenshot", 1},
                                                         {"window_screenshot", 1},
                                                         {"save_images", 0},
                                                         {"save_scene", 0},
                                                         {"select", 2},
                                                         {"pick", 2},
                                                         {"quit", 0}};
    std::ifstream in(path);
    if (!in) throw std::invalid_argument(path.string() + ": cannot read the script");
    std::vector<ScriptCommand> commands;
    std::string text;
    for (int line = 1; std::getline(in, text); ++line) {
        if (size_t hash = text.find('#'); hash != std::string::npos) text.resize(hash);
        std::istringstream words(text);
        std::string name;
        if (!(words >> name)) continue;
        std::vector<std::string> args;
        for (std::string w; words >> w;) args.push_back(w);
        auto known = kArity.find(name);
        auto where = path.string() + ":" + std::to_string(line) + ": ";
        if (known == kArity.end()) throw std::invalid_argument(where + "unknown command '" + name + "'");
        if (args.size() != known->second)
            throw std::invalid_argument(where + "'" + name + "' takes " + std::to_string(known->second) +
                                        " argument(s), got " + std::to_string(args.size()));
        try {
            commands.push_back({line, name, parseAction(name, args, limits)});
        } catch (const std::invalid_argument& e) {
            throw std::invalid_argument(where + e.what());
        }
    }
    return commands;
}

void checkScriptOnScene(const std::filesystem::path& path, const std::vector<ScriptCommand>& commands,
                        const Scene& scene) {
    std::optional<Scene> edited;  // copied only when there is an edit to try
    for (const ScriptCommand& c : commands) {
        if (std::holds_alternative<script::Copy>(c.action) || std::holds_alternative<script::Replace>(c.action))
            return;  // the scene file changes: later edits apply to what it will hold
        const auto* edit = std::get_if<script::Edit>(&c.action);
        if (!edit) continue;
        if (!edited) edited = scene;
        if (auto error = setObjectField(*edited, edit->object, edit->field, edit->value))
            throw std::invalid_argument(path.string() + ":" + std::to_string(c.line) + ": edit: " + *error);
    }
}

}  // namespace whitted
