#include "io/mtl_file.h"

#include "io/texture.h"
#include "io/texture_file.h"

#include <glm/gtc/packing.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace whitted {
namespace {

std::string trim(const std::string& s) {
    size_t a = s.find_first_not_of(" \t\r\n");
    if (a == std::string::npos) return "";
    size_t b = s.find_last_not_of(" \t\r\n");
    return s.substr(a, b - a + 1);
}

class MtlReader {
public:
    explicit MtlReader(std::filesystem::path path) : path_(std::move(path)), file_(path_.string()) {}

    MtlFile read() {
        std::ifstream in(path_);
        if (!in) throw MtlFileError(file_, 0, "cannot read file: it does not exist or is not readable");
        std::string text;
        int line = 0;
        MtlMaterial* m = nullptr;
        while (std::getline(in, text)) {
            ++line;
            line_ = line;
            std::string content = trim(text.substr(0, text.find('#')));
            if (content.empty()) continue;
            std::istringstream words(content);
            std::string key;
            words >> key;
            std::string rest = trim(content.substr(key.size()));
            if (key == "newmtl") {
                out_.materials.push_back({});
                m = &out_.materials.back();
                m->name = rest;
                m->line = line;
                continue;
            }
            if (!m) {
                fail("\"" + key + "\" before any newmtl");
            }
            if (key == "Ka" || key == "Kd" || key == "Ks" || key == "Ke" || key == "Tf") {
                // Reflectances and filters are fractions; only emission is open-ended.
                glm::dvec3 c = colour(key, rest, key == "Ke" ? 1e6 : 1.0);
                (key == "Ka" ? m->Ka : key == "Kd" ? m->Kd : key == "Ks" ? m->Ks : key == "Ke" ? m->Ke : m->Tf) = c;
            } else if (key == "Ns") {
                m->Ns = number(key, rest, 0, 1e5);
            } else if (key == "Ni") {
                m->Ni = number(key, rest, 1e-3, 10);
            } else if (key == "d") {
                m->d = number(key, rest, 0, 1);
            } else if (key == "Tr") {
                m->d = 1.0 - number(key, rest, 0, 1);
            } else if (key == "illum") {
                double v = number(key, rest, 0, 10);
                if (v != std::floor(v)) fail("illum must be an integer from 0 to 10, got " + rest);
                m->illum = int(v);
                m->illumLine = line;
            } else if (key == "map_Kd") {
                double bm = 1;
                std::string name = textureName(rest, bm);
                m->diffuseTexture = texture(name, TextureEncoding::Colour);
                m->diffuseTextureFile = mtlPath(path_.parent_path(), name);
            } else if (key == "norm") {
                double bm = 1;
                std::string name = textureName(rest, bm);
                m->normalMap = texture(name, TextureEncoding::Data);
                m->normalMapFile = mtlPath(path_.parent_path(), name);
            } else if (key == "bump" || key == "map_bump" || key == "map_Bump") {
                double bm = 1;
                std::string name = textureName(rest, bm);
                auto heights = texture(name, TextureEncoding::Data);
                m->normalMap = normalMapFromHeights(*heights, bm);
                m->normalMapFile.clear();
            }
            // Other keys (map_Ka, map_Ks, refl, sharpness, ...) are not used.
        }
        return std::move(out_);
    }

private:
    [[noreturn]] void fail(const std::string& message) const {
        throw MtlFileError(file_, line_, message);
    }
    double parse(const std::string& key, const std::string& word) const {
        try {
            size_t used = 0;
            double v = std::stod(word, &used);
            if (used == word.size() && std::isfinite(v)) return v;
        } catch (const std::exception&) {
        }
        fail(key + " expects numbers, got \"" + word + "\"");
    }
    double number(const std::string& key, const std::string& rest, double lo, double hi) const {
        std::istringstream in(rest);
        std::string word;
        in >> word;
        if (word.empty()) fail(key + " expects a number");
        double v = parse(key, word);
        if (v < lo || v > hi) {
            std::ostringstream range;
            range << "; it must be in [" << lo << ", " << hi << "]";
            fail(key + " is " + word + range.str());
        }
        return v;
    }
    glm::dvec3 colour(const std::string& key, const std::string& rest, double hi) const {
        std::istringstream in(rest);
        std::vector<std::string> words;
        for (std::string w; in >> w;) words.push_back(w);
        if (!words.empty() && (words[0] == "spectral" || words[0] == "xyz"))
            fail(key + " " + words[0] + " colours are not supported; give r g b");
        if (words.empty() || words.size() > 3) fail(key + " expects r g b (or one value for all three)");
        glm::dvec3 c;
        for (int i = 0; i < 3; ++i) c[i] = parse(key, words[std::min<size_t>(size_t(i), words.size() - 1)]);
        for (int i = 0; i < 3; ++i)
            if (!(c[i] >= 0 && c[i] <= hi)) {
                std::ostringstream message;
                message << key << " must have components in [0, " << hi << "], got " << c[i];
                fail(message.str());
            }
        return c;
    }
    // The file name after the options (-bm STRENGTH read, others skipped
    // with their arguments): the rest of the line, spaces kept.
    std::string textureName(const std::string& rest, double& bm) const {
        static const std::vector<std::pair<std::string, int>> options = {
            {"-bm", 1}, {"-blendu", 1}, {"-blendv", 1}, {"-boost", 1}, {"-cc", 1}, {"-clamp", 1}, {"-imfchan", 1},
            {"-mm", 2}, {"-o", 3}, {"-s", 3}, {"-t", 3}, {"-texres", 1}, {"-type", 1}};
        std::string s = rest;
        for (;;) {
            s = trim(s);
            if (s.empty() || s[0] != '-') break;
            std::istringstream in(s);
            std::string option;
            in >> option;
            auto it = std::find_if(options.begin(), options.end(), [&](auto& o) { return o.first == option; });
            if (it == options.end()) break;  // a file name starting with '-'
            std::vector<std::string> args;
            for (int k = 0; k < it->second; ++k) {
                std::string a;
                std::streampos before = in.tellg();
                if (!(in >> a)) fail(option + " expects " + std::to_string(it->second) + " value(s)");
                // -o, -s, -t take 1 to 3 numbers: stop at the first non-number.
                if (k > 0 && it->second == 3) {
                    char* end = nullptr;
                    std::strtod(a.c_str(), &end);
                    if (*end != '\0') {
                        in.clear();
                        in.seekg(before);
                        break;
                    }
                }
                args.push_back(a);
            }
            if (option == "-bm") bm = parse(option, args[0]);
            std::string left;
            std::getline(in, left, '\0');
            s = left;
        }
        if (s.empty()) fail("a texture statement without a file name");
        return s;
    }
    std::shared_ptr<const TextureData> texture(const std::string& written, TextureEncoding encoding) const {
        std::filesystem::path file = mtlPath(path_.parent_path(), written);
        std::error_code ec;
        if (!std::filesystem::is_regular_file(file, ec))
            fail("texture \"" + written + "\" does not exist (looked for " + file.string() + ")");
        try {
            return std::make_shared<const TextureData>(readTextureFile(file, encoding));
        } catch (const TextureFileError& e) {
            fail("texture \"" + written + "\" " + e.what());
        }
    }

    std::filesystem::path path_;
    std::string file_;
    int line_ = 0;
    MtlFile out_;
};

}  // namespace

std::filesystem::path mtlPath(const std::filesystem::path& folder, std::string written) {
    std::replace(written.begin(), written.end(), '\\', '/');
    std::filesystem::path p(written);
    return p.is_absolute() ? p : folder / p;
}

std::shared_ptr<const TextureData> normalMapFromHeights(const TextureData& heights, double bm) {
    const TextureLevel& level = heights.levels.at(0);
    int w = level.width, h = level.height;
    auto height = [&](int x, int y) {
        x = (x % w + w) % w;  // wraps, as the texture repeats
        y = (y % h + h) % h;
        return double(glm::unpackHalf1x16(level.rgba[(size_t(y) * size_t(w) + size_t(x)) * 4]));
    };
    std::vector<float> rgba(size_t(w) * size_t(h) * 4);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double dx = (height(x + 1, y) - height(x - 1, y)) / 2.0;
            double dy = (height(x, y - 1) - height(x, y + 1)) / 2.0;  // rows from the top: up is y - 1
            glm::dvec3 n = glm::normalize(glm::dvec3(-bm * dx, -bm * dy, 1.0));
            float* t = &rgba[(size_t(y) * size_t(w) + size_t(x)) * 4];
            for (int c = 0; c < 3; ++c) t[c] = float(n[c] * 0.5 + 0.5);
            t[3] = 1.0f;
        }
    return std::make_shared<const TextureData>(textureFromPixels(w, h, rgba, heights.name + " (as a normal map)"));
}

MtlFile readMtlFile(const std::filesystem::path& path) { return MtlReader(path).read(); }

}  // namespace whitted
