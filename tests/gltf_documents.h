// glTF and GLB documents made by the tests (tests/gltf_hardening_test.cpp,
// tests/bad_input_test.cpp): one square with its bytes, a chain of nodes,
// the .glb container around a document.
#pragma once

#include "test_support.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

namespace whitted::test {

using Json = nlohmann::json;

// One square (two triangles, positions then uint16 indices) in a buffer of
// its own bytes, and a glTF document using it.
inline std::vector<unsigned char> squareBytes() {
    std::vector<float> positions = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    std::vector<uint16_t> indices = {0, 1, 2, 0, 2, 3};
    std::vector<unsigned char> bytes(positions.size() * 4 + indices.size() * 2);
    std::memcpy(bytes.data(), positions.data(), positions.size() * 4);
    std::memcpy(bytes.data() + positions.size() * 4, indices.data(), indices.size() * 2);
    return bytes;
}

inline Json squareDocument(bool embedded = true, const std::vector<unsigned char>& bytes = squareBytes()) {
    Json j;
    j["asset"] = {{"version", "2.0"}};
    Json buffer = {{"byteLength", bytes.size()}};
    if (embedded) buffer["uri"] = "data:application/octet-stream;base64," + base64(bytes);
    j["buffers"] = Json::array({buffer});
    j["bufferViews"] = Json::array({{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 48}},
                                    {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 12}}});
    j["accessors"] = Json::array({{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}},
                                  {{"bufferView", 1}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}});
    j["meshes"] = Json::array({{{"primitives", Json::array({{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}})}}});
    j["nodes"] = Json::array({{{"mesh", 0}}});
    return j;
}

// The square in three nodes: "node 0" flattened onto the x axis, the
// second whole, "flat" flattened onto the y axis; each flattened one has
// two degenerate triangles.
inline Json flattenedNodesDocument() {
    Json j = squareDocument();
    j["nodes"] = Json::array({{{"mesh", 0}, {"scale", {1, 1e-200, 1}}},
                              {{"mesh", 0}, {"scale", {1, 1, 1}}},
                              {{"mesh", 0}, {"name", "flat"}, {"scale", {1e-200, 1, 1}}}});
    j["scenes"] = Json::array({{{"nodes", {0, 1, 2}}}});
    return j;
}

// A chain of `depth` nodes, each the only child of the one before, the
// last holding the square, each moving it by 0.001 along x.
inline Json chain(size_t depth) {
    Json j = squareDocument();
    Json nodes = Json::array();
    for (size_t i = 0; i < depth; ++i) {
        Json n = {{"translation", {0.001, 0, 0}}};
        if (i + 1 < depth) n["children"] = Json::array({i + 1});
        else n["mesh"] = 0;
        nodes.push_back(std::move(n));
    }
    j["nodes"] = std::move(nodes);
    return j;
}

// A .glb of `json` and `bin` (glTF 2.0 §4.4: 12-byte header, chunks padded
// to 4 bytes, JSON with spaces, BIN with zeros).
inline std::vector<unsigned char> glbBytes(const Json& json, std::vector<unsigned char> bin) {
    std::string text = json.dump();
    while (text.size() % 4) text += ' ';
    while (bin.size() % 4) bin.push_back(0);
    std::vector<unsigned char> out = {'g', 'l', 'T', 'F'};
    auto word = [&](uint32_t w) {
        for (int k = 0; k < 4; ++k) out.push_back((unsigned char)(w >> (8 * k)));
    };
    const uint32_t total = uint32_t(12 + 8 + text.size() + 8 + bin.size());
    word(2);
    word(total);
    word(uint32_t(text.size()));
    word(0x4E4F534Au);
    out.insert(out.end(), text.begin(), text.end());
    word(uint32_t(bin.size()));
    word(0x004E4942u);
    out.insert(out.end(), bin.begin(), bin.end());
    return out;
}

// The byte offsets at which a .glb of glbBytes() can be cut: after the
// header, inside and after each chunk's header, inside the JSON, at and
// inside the BIN chunk, and four bytes short of the end.
inline std::vector<size_t> glbCuts(const std::vector<unsigned char>& glb) {
    uint32_t jsonLength = 0;
    std::memcpy(&jsonLength, glb.data() + 12, 4);
    const size_t binStart = 20 + jsonLength;
    return {size_t(12), size_t(16), size_t(20), size_t(20 + jsonLength / 2), binStart, binStart + 4, binStart + 8,
            glb.size() - 4};
}

// `glb` cut at `cut`, its header's length made the cut file's (so that only
// the chunks are wrong).
inline std::vector<unsigned char> glbCutAt(const std::vector<unsigned char>& glb, size_t cut) {
    std::vector<unsigned char> part(glb.begin(), glb.begin() + long(cut));
    const uint32_t length = uint32_t(cut);
    std::memcpy(part.data() + 8, &length, 4);
    return part;
}

inline std::filesystem::path writeJson(const std::filesystem::path& path, const Json& j) {
    std::ofstream(path) << j.dump();
    return path;
}

inline std::filesystem::path writeBytes(const std::filesystem::path& path, const std::vector<unsigned char>& bytes) {
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), long(bytes.size()));
    return path;
}

}  // namespace whitted::test
