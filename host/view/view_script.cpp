#include "view/view_script.h"

#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

namespace whitted {

std::vector<ScriptCommand> loadScript(const std::filesystem::path& path) {
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
                                                         {"quit", 0}};
    std::ifstream in(path);
    if (!in) throw std::invalid_argument(path.string() + ": cannot read the script");
    std::vector<ScriptCommand> commands;
    std::string text;
    for (int line = 1; std::getline(in, text); ++line) {
        if (size_t hash = text.find('#'); hash != std::string::npos) text.resize(hash);
        std::istringstream words(text);
        ScriptCommand c;
        c.line = line;
        if (!(words >> c.name)) continue;
        for (std::string w; words >> w;) c.args.push_back(w);
        auto known = kArity.find(c.name);
        auto where = path.string() + ":" + std::to_string(line) + ": ";
        if (known == kArity.end()) throw std::invalid_argument(where + "unknown command '" + c.name + "'");
        if (c.args.size() != known->second)
            throw std::invalid_argument(where + "'" + c.name + "' takes " + std::to_string(known->second) +
                                        " argument(s), got " + std::to_string(c.args.size()));
        commands.push_back(std::move(c));
    }
    return commands;
}

}  // namespace whitted
