#include "io/gltf_file.h"

#include "io/texture.h"
#include "io/texture_file.h"

#include <nlohmann/json.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <span>
#include <sstream>

namespace whitted {
namespace {

using Json = nlohmann::json;

// The scene format's limit on any coordinate (scenes/README.md "Scene files").
constexpr double kMaxMagnitude = 1e6;

std::vector<unsigned char> readBytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return {};
    return std::vector<unsigned char>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

std::optional<std::vector<unsigned char>> decodeBase64(std::string_view text) {
    std::vector<unsigned char> out;
    uint32_t bits = 0;
    int count = 0;
    for (char c : text) {
        int v = c >= 'A' && c <= 'Z' ? c - 'A'
                : c >= 'a' && c <= 'z' ? c - 'a' + 26
                : c >= '0' && c <= '9' ? c - '0' + 52
                : c == '+' || c == '-' ? 62
                : c == '/' || c == '_' ? 63
                                       : -1;
        if (c == '=') break;
        if (v < 0) return std::nullopt;
        bits = bits << 6 | uint32_t(v);
        if ((count += 6) >= 8) {
            count -= 8;
            out.push_back((unsigned char)(bits >> count & 0xffu));
        }
    }
    return out;
}

// Percent-decoding of a relative URI ("my%20file.bin" -> "my file.bin").
std::string uriToPath(const std::string& uri) {
    std::string out;
    for (size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit((unsigned char)uri[i + 1]) &&
            std::isxdigit((unsigned char)uri[i + 2])) {
            out += char(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

std::string show(double v) {
    std::ostringstream out;
    out << v;
    return out.str();
}

class Reader {
public:
    explicit Reader(std::filesystem::path path) : path_(std::move(path)), file_(path_.string()) {}

    GltfFile read() {
        parse();
        check(json_.is_object(), "", "the file's top level is not a JSON object");
        const Json* asset = member(json_, "asset");
        check(asset && asset->is_object(), "/asset", "is missing; a glTF 2.0 file has an \"asset\" with its version");
        std::string version = string(*asset, "version", "/asset/version", "");
        check(version.rfind("2.", 0) == 0, "/asset/version",
              "is \"" + version + "\"; whitted reads glTF 2.0 files");
        for (const Json& e : array(json_, "extensionsRequired", "/extensionsRequired")) {
            std::string name = e.is_string() ? e.get<std::string>() : "";
            static const std::vector<std::string> known = {
                "KHR_lights_punctual", "KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume",
                "KHR_materials_emissive_strength"};
            check(std::find(known.begin(), known.end(), name) != known.end(), "/extensionsRequired",
                  "requires extension \"" + name + "\", which whitted does not read");
        }
        readBuffers();
        readMaterials();
        readMeshes();
        readCameras();
        readLights();
        readNodes();
        return std::move(out_);
    }

private:
    [[noreturn]] void fail(const std::string& where, const std::string& message) const {
        throw GltfFileError(file_ + ": " + (where.empty() ? "" : where + ": ") + message);
    }
    void check(bool ok, const std::string& where, const std::string& message) const {
        if (!ok) fail(where, message);
    }
    void warn(const std::string& where, const std::string& message) {
        out_.warnings.push_back(file_ + ": " + where + ": " + message);
    }

    static const Json* member(const Json& o, const char* key) {
        if (!o.is_object()) return nullptr;
        auto it = o.find(key);
        return it == o.end() ? nullptr : &*it;
    }
    const Json& array(const Json& o, const char* key, const std::string& where) const {
        static const Json empty = Json::array();
        const Json* a = member(o, key);
        if (!a) return empty;
        check(a->is_array(), where, "must be an array");
        return *a;
    }
    double number(const Json& o, const char* key, const std::string& where, double fallback, double lo,
                  double hi) const {
        const Json* v = member(o, key);
        if (!v) return fallback;
        check(v->is_number(), where, "must be a number");
        double x = v->get<double>();
        // Messages are built only on failure: a file of a million nodes checks millions of values.
        if (!(std::isfinite(x) && x >= lo && x <= hi))
            fail(where, "is " + v->dump() + "; it must be in [" + show(lo) + ", " + show(hi) + "]");
        return x;
    }
    int index(const Json& o, const char* key, const std::string& where, size_t count) const {
        const Json* v = member(o, key);
        if (!v) return -1;
        if (!(v->is_number_integer() && v->get<int64_t>() >= 0 && size_t(v->get<int64_t>()) < count))
            fail(where, "is " + v->dump() + "; expected an index below " + std::to_string(count));
        return int(v->get<int64_t>());
    }
    std::string string(const Json& o, const char* key, const std::string& where, const std::string& fallback) const {
        const Json* v = member(o, key);
        if (!v) return fallback;
        check(v->is_string(), where, "must be a string");
        return v->get<std::string>();
    }
    template <int N>
    glm::vec<N, double> numbers(const Json& o, const char* key, const std::string& where, glm::vec<N, double> fallback,
                                double lo, double hi) const {
        const Json* v = member(o, key);
        if (!v) return fallback;
        if (!(v->is_array() && v->size() == N)) fail(where, "must be an array of " + std::to_string(N) + " numbers");
        glm::vec<N, double> r;
        for (int i = 0; i < N; ++i) {
            if (!(*v)[i].is_number()) fail(where, "must be an array of " + std::to_string(N) + " numbers");
            r[i] = (*v)[i].get<double>();
            if (!(std::isfinite(r[i]) && r[i] >= lo && r[i] <= hi))
                fail(where, "has " + (*v)[i].dump() + "; each must be in [" + show(lo) + ", " + show(hi) + "]");
        }
        return r;
    }
    static const Json& extension(const Json& o, const char* name) {
        static const Json none;
        const Json* e = member(o, "extensions");
        const Json* x = e ? member(*e, name) : nullptr;
        return x ? *x : none;
    }

    void parse() {
        std::error_code ec;
        if (!std::filesystem::exists(path_, ec)) fail("", "cannot read file: it does not exist");
        // A .gltf is all JSON: refused by its size before it is read (a
        // .glb's binary chunk may be large; its JSON chunk is checked below).
        const uintmax_t fileSize = std::filesystem::file_size(path_, ec);
        if (!ec && fileSize > kMaxGltfJsonBytes) {
            char magic[4] = {};
            std::ifstream(path_, std::ios::binary).read(magic, 4);
            check(std::memcmp(magic, "glTF", 4) == 0, "",
                  "is " + std::to_string(fileSize) + " bytes of JSON; whitted reads glTF JSON up to " +
                      std::to_string(kMaxGltfJsonBytes) + " bytes (keep large buffers in .bin files or a .glb)");
        }
        std::vector<unsigned char> bytes = readBytes(path_);
        std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
        // .glb: a 12-byte header, a JSON chunk, an optional BIN chunk.
        if (bytes.size() >= 12 && std::memcmp(bytes.data(), "glTF", 4) == 0) {
            auto word = [&](size_t at) {
                uint32_t w = 0;
                if (at + 4 <= bytes.size()) std::memcpy(&w, bytes.data() + at, 4);
                return w;
            };
            check(word(4) == 2, "", "is a binary glTF of version " + std::to_string(word(4)) + "; expected 2");
            check(word(8) == bytes.size(), "",
                  "is a binary glTF whose header gives its length as " + std::to_string(word(8)) + " bytes, but the file has " +
                      std::to_string(bytes.size()));
            size_t at = 12;
            bool haveJson = false;
            while (at + 8 <= bytes.size()) {
                uint32_t length = word(at), type = word(at + 4);
                check(size_t(length) <= bytes.size() - at - 8, "", "has a chunk that runs past the end of the file");
                if (type == 0x4E4F534Au && !haveJson) {
                    check(length <= kMaxGltfJsonBytes, "",
                          "has a JSON chunk of " + std::to_string(length) + " bytes; whitted reads glTF JSON up to " +
                              std::to_string(kMaxGltfJsonBytes) + " bytes");
                    text = std::string_view(reinterpret_cast<const char*>(bytes.data()) + at + 8, length);
                    haveJson = true;
                } else if (type == 0x004E4942u && !glbBinary_) {
                    glbBinary_ = std::vector<unsigned char>(bytes.begin() + long(at + 8), bytes.begin() + long(at + 8 + length));
                }
                at += 8 + length;
            }
            check(haveJson, "", "is a binary glTF without a JSON chunk");
            json_ = Json::parse(text, nullptr, false);
        } else {
            json_ = Json::parse(text, nullptr, false);
        }
        if (json_.is_discarded()) fail("", "is not valid JSON (nor a binary glTF)");
    }

    std::vector<unsigned char> uriBytes(const std::string& uri, const std::string& where) const {
        if (uri.rfind("data:", 0) == 0) {
            size_t comma = uri.find(',');
            check(comma != std::string::npos && uri.substr(0, comma).find(";base64") != std::string::npos, where,
                  "is a data URI that is not base64");
            auto bytes = decodeBase64(std::string_view(uri).substr(comma + 1));
            check(bytes.has_value(), where, "is a data URI with invalid base64");
            return *bytes;
        }
        std::filesystem::path file = path_.parent_path() / uriToPath(uri);
        std::error_code ec;
        check(std::filesystem::is_regular_file(file, ec), where, "names \"" + uri + "\", which does not exist");
        return readBytes(file);
    }

    void readBuffers() {
        const Json& buffers = array(json_, "buffers", "/buffers");
        for (size_t i = 0; i < buffers.size(); ++i) {
            std::string at = "/buffers/" + std::to_string(i);
            check(member(buffers[i], "byteLength"), at, "has no byteLength");
            size_t length = size_t(number(buffers[i], "byteLength", at + "/byteLength", 0, 0, 1e15));
            std::vector<unsigned char> data;
            if (const Json* uri = member(buffers[i], "uri")) {
                check(uri->is_string(), at + "/uri", "must be a string");
                data = uriBytes(uri->get<std::string>(), at + "/uri");
            } else {
                check(i == 0 && glbBinary_.has_value(), at, "has no uri and is not a .glb file's binary chunk");
                data = *glbBinary_;
            }
            check(data.size() >= length, at, "holds " + std::to_string(data.size()) + " bytes, fewer than its byteLength " +
                                                 std::to_string(length));
            data.resize(length);
            buffers_.push_back(std::move(data));
        }
        const Json& views = array(json_, "bufferViews", "/bufferViews");
        for (size_t i = 0; i < views.size(); ++i) {
            std::string at = "/bufferViews/" + std::to_string(i);
            View v;
            v.buffer = index(views[i], "buffer", at + "/buffer", buffers_.size());
            check(v.buffer >= 0, at, "has no buffer");
            v.offset = size_t(number(views[i], "byteOffset", at + "/byteOffset", 0, 0, 1e15));
            v.length = size_t(number(views[i], "byteLength", at + "/byteLength", 0, 0, 1e15));
            v.stride = size_t(number(views[i], "byteStride", at + "/byteStride", 0, 4, 252));
            check(v.stride % 4 == 0, at + "/byteStride", "is " + std::to_string(v.stride) + "; it must be a multiple of 4");
            check(v.offset + v.length <= buffers_[size_t(v.buffer)].size(), at, "runs past the end of its buffer");
            views_.push_back(v);
        }
    }

    // An accessor's elements as doubles, `components` per element
    // (normalised integers mapped to [0, 1] or [-1, 1]). indices: the
    // accessor of a primitive's indices, of unsigned integers only (glTF 2.0
    // §5.24.3: UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT, not normalised).
    // Its size is checked against its bufferView before anything is
    // allocated, and every float it holds is finite.
    std::vector<double> accessor(int id, const std::vector<int>& componentCounts, const std::string& where,
                                 bool indices = false) {
        const Json& accessors = array(json_, "accessors", "/accessors");
        check(id >= 0 && size_t(id) < accessors.size(), where, "names accessor " + std::to_string(id) + ", which does not exist");
        const Json& a = accessors[size_t(id)];
        std::string at = "/accessors/" + std::to_string(id);
        static const std::map<std::string, int> types = {{"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3}, {"VEC4", 4}};
        std::string type = string(a, "type", at + "/type", "");
        check(types.count(type), at + "/type", "is \"" + type + "\"; expected SCALAR, VEC2, VEC3 or VEC4");
        int n = types.at(type);
        check(std::find(componentCounts.begin(), componentCounts.end(), n) != componentCounts.end(), at + "/type",
              "is " + type + ", which " + where + " cannot use");
        int componentType = int(number(a, "componentType", at + "/componentType", 0, 0, 1e9));
        size_t size = componentType == 5120 || componentType == 5121   ? 1
                      : componentType == 5122 || componentType == 5123 ? 2
                      : componentType == 5125 || componentType == 5126 ? 4
                                                                       : 0;
        check(size > 0, at + "/componentType", "is " + std::to_string(componentType) + ", not a glTF component type");
        bool normalized = member(a, "normalized") && (*member(a, "normalized")) == true;
        if (indices)
            check((componentType == 5121 || componentType == 5123 || componentType == 5125) && !normalized,
                  at + "/componentType",
                  "is " + std::to_string(componentType) + (normalized ? " normalized" : "") +
                      "; indices must be UNSIGNED_BYTE (5121), UNSIGNED_SHORT (5123) or UNSIGNED_INT (5125)");
        check(member(a, "count"), at, "has no count");
        size_t count = size_t(number(a, "count", at + "/count", 0, 1, 1e9));
        check(!member(a, "sparse"), at + "/sparse", "sparse accessors are not supported");
        int viewId = index(a, "bufferView", at + "/bufferView", views_.size());
        if (viewId < 0) {  // all zeros, as the specification says; of use only to sparse accessors
            check(count <= kMaxGltfZeroAccessorCount, at + "/count",
                  "is " + std::to_string(count) + " for an accessor without a bufferView; whitted reads such an "
                  "accessor (all zeros) up to " + std::to_string(kMaxGltfZeroAccessorCount) + " elements");
            return std::vector<double>(count * size_t(n), 0.0);
        }
        const View& view = views_[size_t(viewId)];
        size_t offset = size_t(number(a, "byteOffset", at + "/byteOffset", 0, 0, 1e15));
        size_t element = size * size_t(n), stride = view.stride ? view.stride : element;
        check(stride >= element, at, "has elements of " + std::to_string(element) + " bytes, more than its bufferView's byteStride " +
                                         std::to_string(stride));
        check(offset % size == 0, at + "/byteOffset", "is not a multiple of the component size " + std::to_string(size));
        check(offset <= view.length && count - 1 <= (view.length - offset) / stride &&
                  offset + (count - 1) * stride + element <= view.length,
              at, "runs past the end of its bufferView");
        std::vector<double> out(count * size_t(n), 0.0);
        const unsigned char* base = buffers_[size_t(view.buffer)].data() + view.offset + offset;
        for (size_t i = 0; i < count; ++i)
            for (int c = 0; c < n; ++c) {
                const unsigned char* p = base + i * stride + size_t(c) * size;
                double v = 0;
                switch (componentType) {
                    case 5120: { int8_t x; std::memcpy(&x, p, 1); v = normalized ? std::max(x / 127.0, -1.0) : x; break; }
                    case 5121: { uint8_t x; std::memcpy(&x, p, 1); v = normalized ? x / 255.0 : x; break; }
                    case 5122: { int16_t x; std::memcpy(&x, p, 2); v = normalized ? std::max(x / 32767.0, -1.0) : x; break; }
                    case 5123: { uint16_t x; std::memcpy(&x, p, 2); v = normalized ? x / 65535.0 : x; break; }
                    case 5125: { uint32_t x; std::memcpy(&x, p, 4); v = x; break; }
                    default: {
                        float x;
                        std::memcpy(&x, p, 4);
                        check(std::isfinite(x), at, "holds a value that is not finite (element " + std::to_string(i) + ")");
                        v = x;
                        break;
                    }
                }
                out[i * size_t(n) + size_t(c)] = v;
            }
        return out;
    }

    // Images, decoded once for each encoding they are used with.
    std::shared_ptr<const TextureData> texture(const Json& info, const std::string& at, TextureEncoding encoding) {
        const Json& textures = array(json_, "textures", "/textures");
        int t = index(info, "index", at + "/index", textures.size());
        check(t >= 0, at, "has no texture index");
        if (number(info, "texCoord", at + "/texCoord", 0, 0, 1e9) != 0)
            warn(at + "/texCoord", "only texture coordinate set 0 is read; set 0 is used");
        std::string tat = "/textures/" + std::to_string(t);
        const Json& images = array(json_, "images", "/images");
        int image = index(textures[size_t(t)], "source", tat + "/source", images.size());
        check(image >= 0, tat, "has no source image (only PNG and JPEG sources are read)");
        auto key = std::make_pair(image, encoding);
        if (auto it = images_.find(key); it != images_.end()) return it->second;
        const Json& im = images[size_t(image)];
        std::string iat = "/images/" + std::to_string(image);
        std::string label = file_ + " " + iat;
        std::shared_ptr<const TextureData> data;
        try {
            if (const Json* uri = member(im, "uri")) {
                check(uri->is_string(), iat + "/uri", "must be a string");
                std::string u = uri->get<std::string>();
                if (u.rfind("data:", 0) == 0) {
                    std::vector<unsigned char> bytes = uriBytes(u, iat + "/uri");
                    std::string hint = u.find("image/jpeg") != std::string::npos ? "jpg" : "png";
                    data = std::make_shared<const TextureData>(readTextureMemory(bytes, hint, encoding, label));
                } else {
                    std::filesystem::path f = path_.parent_path() / uriToPath(u);
                    std::error_code ec;
                    check(std::filesystem::is_regular_file(f, ec), iat + "/uri", "names \"" + u + "\", which does not exist");
                    data = std::make_shared<const TextureData>(readTextureFile(f, encoding));
                }
            } else {
                int v = index(im, "bufferView", iat + "/bufferView", views_.size());
                check(v >= 0, iat, "has neither a uri nor a bufferView");
                const View& view = views_[size_t(v)];
                std::span<const unsigned char> bytes(buffers_[size_t(view.buffer)].data() + view.offset, view.length);
                std::string mime = string(im, "mimeType", iat + "/mimeType", "image/png");
                data = std::make_shared<const TextureData>(
                    readTextureMemory(bytes, mime == "image/jpeg" ? "jpg" : "png", encoding, label));
            }
        } catch (const TextureFileError& e) {
            fail(iat, std::string("cannot be read: ") + e.what());
        }
        images_[key] = data;
        return data;
    }

    void readMaterials() {
        const Json& materials = array(json_, "materials", "/materials");
        for (size_t i = 0; i < materials.size(); ++i) {
            const Json& m = materials[i];
            std::string at = "/materials/" + std::to_string(i);
            GltfMaterial g;
            g.name = string(m, "name", at + "/name", "");
            if (const Json* pbr = member(m, "pbrMetallicRoughness")) {
                std::string p = at + "/pbrMetallicRoughness";
                g.baseColorFactor = numbers<4>(*pbr, "baseColorFactor", p + "/baseColorFactor", g.baseColorFactor, 0, 1);
                g.metallicFactor = number(*pbr, "metallicFactor", p + "/metallicFactor", 1, 0, 1);
                g.roughnessFactor = number(*pbr, "roughnessFactor", p + "/roughnessFactor", 1, 0, 1);
                if (const Json* t = member(*pbr, "baseColorTexture"))
                    g.baseColorTexture = texture(*t, p + "/baseColorTexture", TextureEncoding::Colour);
                if (const Json* t = member(*pbr, "metallicRoughnessTexture"))
                    g.metallicRoughnessTexture = texture(*t, p + "/metallicRoughnessTexture", TextureEncoding::Data);
            }
            if (const Json* t = member(m, "normalTexture")) {
                g.normalTexture = texture(*t, at + "/normalTexture", TextureEncoding::Data);
                g.normalScale = number(*t, "scale", at + "/normalTexture/scale", 1, -1e3, 1e3);
            }
            g.emissiveFactor = numbers<3>(m, "emissiveFactor", at + "/emissiveFactor", g.emissiveFactor, 0, 1);
            if (const Json* t = member(m, "emissiveTexture"))
                g.emissiveTexture = texture(*t, at + "/emissiveTexture", TextureEncoding::Colour);
            std::string ext = at + "/extensions/";
            const Json& strength = extension(m, "KHR_materials_emissive_strength");
            g.emissiveStrength = number(strength, "emissiveStrength", ext + "KHR_materials_emissive_strength/emissiveStrength", 1, 0, 1e6);
            const Json& transmission = extension(m, "KHR_materials_transmission");
            g.transmissionFactor = number(transmission, "transmissionFactor",
                                          ext + "KHR_materials_transmission/transmissionFactor", 0, 0, 1);
            const Json& ior = extension(m, "KHR_materials_ior");
            g.ior = number(ior, "ior", ext + "KHR_materials_ior/ior", 1.5, 1, 10);
            const Json& volume = extension(m, "KHR_materials_volume");
            if (volume.is_object()) {
                std::string v = ext + "KHR_materials_volume/";
                g.hasVolume = true;
                g.thicknessFactor = number(volume, "thicknessFactor", v + "thicknessFactor", 0, 0, 1e6);
                g.attenuationColor = numbers<3>(volume, "attenuationColor", v + "attenuationColor", g.attenuationColor, 0, 1);
                g.attenuationDistance = number(volume, "attenuationDistance", v + "attenuationDistance",
                                               std::numeric_limits<double>::infinity(), 1e-9, 1e300);
            }
            out_.materials.push_back(std::move(g));
        }
    }

    void readMeshes() {
        const Json& meshes = array(json_, "meshes", "/meshes");
        for (size_t i = 0; i < meshes.size(); ++i) {
            std::string at = "/meshes/" + std::to_string(i);
            GltfMesh mesh;
            mesh.name = string(meshes[i], "name", at + "/name", "");
            const Json& primitives = array(meshes[i], "primitives", at + "/primitives");
            for (size_t k = 0; k < primitives.size(); ++k) {
                std::string p = at + "/primitives/" + std::to_string(k);
                const Json& prim = primitives[k];
                int mode = int(number(prim, "mode", p + "/mode", 4, 0, 6));
                GltfPrimitive out;
                out.material = index(prim, "material", p + "/material", out_.materials.size());
                if (mode < 4) {
                    warn(p + "/mode", "points and lines are not rendered");
                    mesh.primitives.push_back(std::move(out));
                    continue;
                }
                const Json* attributes = member(prim, "attributes");
                check(attributes && member(*attributes, "POSITION"), p + "/attributes", "has no POSITION");
                std::string a = p + "/attributes/";
                std::vector<double> pos = accessor(attributeIndex(*attributes, "POSITION", a), {3}, a + "POSITION");
                size_t count = pos.size() / 3;
                for (size_t v = 0; v < count; ++v) {
                    glm::dvec3 x(pos[v * 3], pos[v * 3 + 1], pos[v * 3 + 2]);
                    for (int c = 0; c < 3; ++c)
                        check(std::abs(x[c]) <= kMaxMagnitude, a + "POSITION",
                              "has a vertex beyond ±1e6 or not finite");
                    out.positions.push_back(x);
                }
                auto perVertex = [&](const char* name, int n) {
                    std::vector<double> values;
                    if (member(*attributes, name)) {
                        values = accessor(attributeIndex(*attributes, name, a), {n}, a + name);
                        check(values.size() == count * size_t(n), a + name, "has a count other than POSITION's");
                    }
                    return values;
                };
                std::vector<double> normals = perVertex("NORMAL", 3), uvs = perVertex("TEXCOORD_0", 2),
                                    tangents = perVertex("TANGENT", 4);
                for (size_t v = 0; v * 3 < normals.size(); ++v)
                    out.normals.emplace_back(normals[v * 3], normals[v * 3 + 1], normals[v * 3 + 2]);
                for (size_t v = 0; v * 2 < uvs.size(); ++v) out.uvs.emplace_back(uvs[v * 2], uvs[v * 2 + 1]);
                for (size_t v = 0; v * 4 < tangents.size(); ++v)
                    out.tangents.emplace_back(tangents[v * 4], tangents[v * 4 + 1], tangents[v * 4 + 2], tangents[v * 4 + 3]);
                std::vector<uint32_t> order;
                if (member(prim, "indices")) {
                    int id = index(prim, "indices", p + "/indices", 1u << 30);
                    for (double x : accessor(id, {1}, p + "/indices", true)) {
                        check(x < double(count), p + "/indices", "has an index beyond the vertices");
                        order.push_back(uint32_t(x));
                    }
                } else {
                    for (size_t v = 0; v < count; ++v) order.push_back(uint32_t(v));
                }
                if (mode == 4) {
                    order.resize(order.size() / 3 * 3);
                    out.indices = order;
                } else {
                    for (size_t t = 2; t < order.size(); ++t) {
                        if (mode == 5)  // strip: every other triangle turns over
                            out.indices.insert(out.indices.end(), {order[t - 2 + (t % 2)], order[t - 1 - (t % 2)], order[t]});
                        else  // fan
                            out.indices.insert(out.indices.end(), {order[0], order[t - 1], order[t]});
                    }
                }
                mesh.primitives.push_back(std::move(out));
            }
            out_.meshes.push_back(std::move(mesh));
        }
    }
    int attributeIndex(const Json& attributes, const char* name, const std::string& at) const {
        return index(attributes, name, at + name, 1u << 30);
    }

    void readCameras() {
        const Json& cameras = array(json_, "cameras", "/cameras");
        for (size_t i = 0; i < cameras.size(); ++i) {
            std::string at = "/cameras/" + std::to_string(i);
            const Json& c = cameras[i];
            GltfCamera camera;
            camera.name = string(c, "name", at + "/name", "");
            std::string type = string(c, "type", at + "/type", "");
            if (type == "perspective") {
                const Json* p = member(c, "perspective");
                check(p != nullptr, at, "is perspective and has no \"perspective\"");
                camera.yfov = number(*p, "yfov", at + "/perspective/yfov", 0, 1e-9, 3.14159265358979);
                check(member(*p, "yfov"), at + "/perspective", "has no yfov");
                camera.aspectRatio = number(*p, "aspectRatio", at + "/perspective/aspectRatio", 0, 1e-6, 1e6);
                // znear > 0 and zfar > znear (glTF 2.0 §5.13); whitted's rays start at the eye and run to
                // infinity, so the planes are checked and not used.
                check(member(*p, "znear"), at + "/perspective", "has no znear");
                double znear = number(*p, "znear", at + "/perspective/znear", 0, -1e300, 1e300);
                check(znear > 0, at + "/perspective/znear", "is " + show(znear) + "; it must be > 0");
                double zfar = number(*p, "zfar", at + "/perspective/zfar", 1e300, 0, 1e300);
                check(zfar > znear, at + "/perspective/zfar", "is " + show(zfar) + "; it must be > znear, " + show(znear));
            } else if (type == "orthographic") {
                const Json* o = member(c, "orthographic");
                check(o != nullptr, at, "is orthographic and has no \"orthographic\"");
                camera.orthographic = true;
                camera.xmag = number(*o, "xmag", at + "/orthographic/xmag", 0, 1e-9, 1e12);
                camera.ymag = number(*o, "ymag", at + "/orthographic/ymag", 0, 1e-9, 1e12);
                check(member(*o, "xmag") && member(*o, "ymag"), at + "/orthographic", "needs xmag and ymag");
                check(member(*o, "znear") && member(*o, "zfar"), at + "/orthographic", "needs znear and zfar");
                double znear = number(*o, "znear", at + "/orthographic/znear", 0, 0, 1e300);
                double zfar = number(*o, "zfar", at + "/orthographic/zfar", 0, 0, 1e300);
                check(zfar > znear, at + "/orthographic/zfar", "is " + show(zfar) + "; it must be > znear, " + show(znear));
            } else {
                fail(at + "/type", "is \"" + type + "\"; expected perspective or orthographic");
            }
            out_.cameras.push_back(camera);
        }
    }

    void readLights() {
        const Json& ext = extension(json_, "KHR_lights_punctual");
        const Json& lights = array(ext, "lights", "/extensions/KHR_lights_punctual/lights");
        for (size_t i = 0; i < lights.size(); ++i) {
            std::string at = "/extensions/KHR_lights_punctual/lights/" + std::to_string(i);
            const Json& l = lights[i];
            GltfLight light;
            light.name = string(l, "name", at + "/name", "");
            std::string type = string(l, "type", at + "/type", "");
            if (type == "point") light.type = GltfLight::Type::Point;
            else if (type == "spot") light.type = GltfLight::Type::Spot;
            else if (type == "directional") light.type = GltfLight::Type::Directional;
            else fail(at + "/type", "is \"" + type + "\"; expected point, spot or directional");
            light.color = numbers<3>(l, "color", at + "/color", light.color, 0, 1e6);
            light.intensity = number(l, "intensity", at + "/intensity", 1, 0, 1e12);
            light.range = number(l, "range", at + "/range", 0, 1e-9, 1e300);
            if (member(l, "range")) warn(at + "/range", "is ignored: the light reaches every distance");
            if (light.type == GltfLight::Type::Spot) {
                const Json* spot = member(l, "spot");
                static const Json none = Json::object();
                const Json& s = spot ? *spot : none;
                constexpr double halfPi = 1.57079632679489661923;
                light.innerConeAngle = number(s, "innerConeAngle", at + "/spot/innerConeAngle", 0, 0, halfPi);
                light.outerConeAngle = number(s, "outerConeAngle", at + "/spot/outerConeAngle", halfPi / 2, 0, halfPi);
                check(light.innerConeAngle < light.outerConeAngle, at + "/spot",
                      "innerConeAngle must be below outerConeAngle");
            }
            out_.lights.push_back(light);
        }
    }

    void readNodes() {
        const Json& nodes = array(json_, "nodes", "/nodes");
        check(nodes.size() <= kMaxGltfNodes, "/nodes",
              "has " + std::to_string(nodes.size()) + " nodes; whitted reads up to " + std::to_string(kMaxGltfNodes));
        for (size_t i = 0; i < nodes.size(); ++i) {
            const Json& n = nodes[i];
            std::string at = "/nodes/" + std::to_string(i);
            GltfNode node;
            node.name = string(n, "name", at + "/name", "");
            node.mesh = index(n, "mesh", at + "/mesh", out_.meshes.size());
            node.camera = index(n, "camera", at + "/camera", out_.cameras.size());
            const Json& lightExt = extension(n, "KHR_lights_punctual");
            node.light = index(lightExt, "light", at + "/extensions/KHR_lights_punctual/light", out_.lights.size());
            for (const Json& c : array(n, "children", at + "/children")) {
                if (!(c.is_number_integer() && c.get<int64_t>() >= 0 && size_t(c.get<int64_t>()) < nodes.size()))
                    fail(at + "/children", "has " + c.dump() + ", not a node index");
                node.children.push_back(int(c.get<int64_t>()));
            }
            if (const Json* m = member(n, "matrix")) {
                check(m->is_array() && m->size() == 16, at + "/matrix", "must be an array of 16 numbers");
                for (int k = 0; k < 16; ++k) {
                    check((*m)[size_t(k)].is_number(), at + "/matrix", "must be an array of 16 numbers");
                    glm::value_ptr(node.local)[k] = (*m)[size_t(k)].get<double>();  // column-major, as glm
                }
            } else {
                glm::dvec3 t = numbers<3>(n, "translation", at + "/translation", glm::dvec3(0), -kMaxMagnitude, kMaxMagnitude);
                glm::dvec4 r = numbers<4>(n, "rotation", at + "/rotation", glm::dvec4(0, 0, 0, 1), -1, 1);
                glm::dvec3 s = numbers<3>(n, "scale", at + "/scale", glm::dvec3(1), -1e6, 1e6);
                double length = glm::length(r);
                check(length > 1e-6, at + "/rotation", "is not a unit quaternion");
                glm::dquat q(r.w / length, r.x / length, r.y / length, r.z / length);
                node.local = glm::translate(glm::dmat4(1.0), t) * glm::mat4_cast(q) * glm::scale(glm::dmat4(1.0), s);
            }
            out_.nodes.push_back(std::move(node));
        }
        // Each node has at most one parent, and the tree has no cycles.
        std::vector<int> parent(nodes.size(), -1);
        for (size_t i = 0; i < out_.nodes.size(); ++i)
            for (int c : out_.nodes[i].children) {
                if (!(parent[size_t(c)] < 0 && c != int(i)))
                    fail("/nodes/" + std::to_string(i) + "/children",
                         "makes node " + std::to_string(c) + " a child twice (a node has at most one parent)");
                parent[size_t(c)] = int(i);
            }
        checkTree(parent);
        const Json& scenes = array(json_, "scenes", "/scenes");
        int scene = index(json_, "scene", "/scene", scenes.size());
        if (scene < 0 && !scenes.empty()) scene = 0;
        if (scene >= 0) {
            std::string at = "/scenes/" + std::to_string(scene) + "/nodes";
            std::vector<bool> listed(nodes.size(), false);
            for (const Json& r : array(scenes[size_t(scene)], "nodes", at)) {
                if (!(r.is_number_integer() && r.get<int64_t>() >= 0 && size_t(r.get<int64_t>()) < nodes.size() &&
                      parent[size_t(r.get<int64_t>())] < 0))
                    fail(at, "has " + r.dump() + ", not the index of a root node");
                check(!listed[size_t(r.get<int64_t>())], at, "lists root node " + r.dump() + " twice");
                listed[size_t(r.get<int64_t>())] = true;
                out_.sceneRoots.push_back(int(r.get<int64_t>()));
            }
        } else {  // no scene: every root node
            for (size_t i = 0; i < parent.size(); ++i)
                if (parent[i] < 0) out_.sceneRoots.push_back(int(i));
        }
    }

    // The nodes form a forest no deeper than kMaxGltfNodeDepth, in O(nodes):
    // with at most one parent each (checked by the caller), every node is
    // reached from a root unless its chain of parents ends in a cycle. One
    // iterative walk from the roots finds each node's depth; a node it did
    // not reach leads up to a cycle, whose first node met is reported.
    void checkTree(const std::vector<int>& parent) const {
        const size_t n = parent.size();
        std::vector<uint32_t> depth(n, 0);  // 0: not reached; else the level, roots at 1
        std::vector<int> open;
        for (size_t i = 0; i < n; ++i)
            if (parent[i] < 0) {
                depth[i] = 1;
                open.push_back(int(i));
            }
        while (!open.empty()) {
            const int i = open.back();
            open.pop_back();
            if (depth[size_t(i)] > kMaxGltfNodeDepth)
                fail("/nodes/" + std::to_string(i), "is more than " + std::to_string(kMaxGltfNodeDepth) +
                                                        " levels deep in the node tree; whitted reads trees up to that depth");
            for (int c : out_.nodes[size_t(i)].children) {
                depth[size_t(c)] = depth[size_t(i)] + 1;
                open.push_back(c);
            }
        }
        for (size_t i = 0; i < n; ++i) {
            if (depth[i] != 0) continue;
            std::vector<bool> seen(n, false);
            size_t p = i;
            while (!seen[p]) {
                seen[p] = true;
                p = size_t(parent[p]);
            }
            fail("/nodes/" + std::to_string(p), "is its own ancestor (the node tree has a cycle)");
        }
    }

    struct View {
        int buffer = 0;
        size_t offset = 0, length = 0, stride = 0;
    };
    std::filesystem::path path_;
    std::string file_;
    Json json_;
    std::optional<std::vector<unsigned char>> glbBinary_;
    std::vector<std::vector<unsigned char>> buffers_;
    std::vector<View> views_;
    std::map<std::pair<int, TextureEncoding>, std::shared_ptr<const TextureData>> images_;
    GltfFile out_;
};

}  // namespace

GltfFile readGltfFile(const std::filesystem::path& path) { return Reader(path).read(); }

}  // namespace whitted
