#include "scene/quick_look.h"

#include "scene/authored_scene.h"
#include "scene/scene_loader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>

namespace whitted {
namespace {

// The quick look's framing of the scene's mesh objects (camera, when
// placeCamera) and its lights and floor (when addLightsAndFloor).
void frameModel(Scene& scene, bool placeCamera, bool addLightsAndFloor) {
    static const std::vector<Triangle> none;
    auto meshTriangles = [&](const Object& o) -> const std::vector<Triangle>& {
        const Mesh* mesh = std::get_if<Mesh>(&o.shape);
        return mesh ? mesh->triangles : none;
    };
    // Bounds: the box of the vertices, and the sphere about its centre. A
    // file with materials of its own is one mesh object per material.
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
    for (const Object& o : scene.objects)
        for (const Triangle& t : meshTriangles(o))
            for (const glm::dvec3& v : {t.v0, t.v1, t.v2}) lo = glm::min(lo, v), hi = glm::max(hi, v);
    glm::dvec3 centre = 0.5 * (lo + hi);
    double radius = 0;
    for (const Object& o : scene.objects)
        for (const Triangle& t : meshTriangles(o))
            for (const glm::dvec3& v : {t.v0, t.v1, t.v2}) radius = std::max(radius, glm::length(v - centre));
    radius = std::max(radius, 1e-6);

    // Camera: y up (glTF's convention, and most OBJ files'), looking at the
    // centre from 35 degrees to the right of +z and 25 degrees above, far
    // enough for the bounding sphere to fit the narrower field of view with
    // a 30% margin: distance = 1.3 r / sin(fov / 2).
    Camera framed;
    Camera& camera = placeCamera ? scene.camera : framed;
    camera.width = 640;
    camera.height = 480;
    camera.verticalFovDegrees = 40;
    double aspect = double(camera.width) / camera.height;
    double halfV = glm::radians(camera.verticalFovDegrees) / 2;
    double halfH = std::atan(std::tan(halfV) * aspect);
    double distance = 1.3 * radius / std::sin(std::min(halfV, halfH));
    double azimuth = glm::radians(35.0), elevation = glm::radians(25.0);
    glm::dvec3 toEye(std::sin(azimuth) * std::cos(elevation), std::sin(elevation),
                     std::cos(azimuth) * std::cos(elevation));
    camera.eye = centre + distance * toEye;
    camera.windowCenter = centre;
    camera.up = {0, 1, 0};

    if (!addLightsAndFloor) return;
    // Lights (no falloff): a key high up to the left of the camera, and a
    // dimmer fill low on the right, so that no side facing the camera is black.
    glm::dvec3 right = glm::normalize(glm::cross(-toEye, camera.up));
    scene.lights.clear();
    scene.lights.push_back({.position = centre + 4 * radius * (0.5 * toEye - right + glm::dvec3(0, 1.5, 0)), .color = glm::dvec3(0.85)});
    scene.lights.push_back({.position = centre + 4 * radius * (toEye + right + glm::dvec3(0, 0.2, 0)), .color = glm::dvec3(0.25)});

    // A grey checkered floor just under the model (a thousandth of its size
    // below, so a model standing on y = min does not touch it).
    Object floor;
    floor.shape = Plane{glm::dvec3(centre.x, lo.y - 1e-3 * radius, centre.z), glm::dvec3(0, 1, 0)};
    floor.material.diffuseColor = glm::dvec3(0.6);
    floor.material.checkerColor = glm::dvec3(0.45);
    floor.material.checkerSize = radius;
    floor.material.checkerOrigin = std::get<Plane>(floor.shape).point;
    floor.material.ambient = 0.1;
    floor.material.diffuse = 0.8;
    scene.objects.push_back(floor);

    // A neutral environment (scenes/README.md "Quick looks"): a grey sky, lighter at the horizon, over a
    // darker ground, seen behind the model and in its mirrors and glass (a chrome model reflects a world, not
    // black) but lighting nothing, so that the two lights above alone set the exposure and the look stays quick.
    Environment world;
    world.kind = Environment::Kind::Gradient;
    world.zenith = glm::dvec3(0.45, 0.48, 0.52);
    world.horizon = glm::dvec3(0.8);
    world.ground = glm::dvec3(0.25);
    world.shadowSamples = 0;
    scene.environment = world;
}

}  // namespace

bool isSceneFile(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext == ".xml";
}

std::filesystem::path quickLookScenePath(const std::filesystem::path& model) {
    return model.parent_path() / (model.filename().string() + ".whitted.xml");
}

Scene quickLookScene(const std::filesystem::path& model) {
    std::error_code ec;
    if (!std::filesystem::exists(model, ec)) throw SceneError(model.string(), 0, "cannot read file: it does not exist");
    std::filesystem::path scenePath = quickLookScenePath(model);
    // The model goes through the scene loader as an XML mesh object with a
    // <file> and no colour, so it is read exactly as a scene file would
    // read it. The camera and the light are placeholders, replaced below.
    std::string file = model.filename().string();
    std::string escaped;
    for (char c : file) escaped += c == '&' ? "&amp;" : c == '<' ? "&lt;" : c == '>' ? "&gt;" : std::string(1, c);
    std::string xml = R"(<scene><camera><position x="0" y="0" z="0"/><window_position x="0" y="0" z="-1"/></camera>)"
                      R"(<lights><light><position x="0" y="0" z="0"/><color r="1" g="1" b="1"/></light></lights>)"
                      R"(<objects><object><properties><type>mesh</type><file>)" +
                      escaped +
                      R"(</file><ambiente_coef>0.1</ambiente_coef><diffuse_coef>0.9</diffuse_coef>)"
                      R"(<specular_coef>0.2</specular_coef></properties></object></objects></scene>)";
    Scene scene;
    try {
        scene = loadSceneFromString(xml, scenePath);
    } catch (const SceneError& e) {
        throw SceneError(model.string(), 0, e.message());
    }
    for (std::string& w : scene.warnings) {  // "scene.xml:1: mesh file ..." -> "model: mesh file ..."
        size_t at = w.find(": ");
        if (at != std::string::npos) w = model.string() + w.substr(at);
    }

    frameModel(scene, true, true);
    return scene;
}

Scene loadSceneOrModel(const std::filesystem::path& path, const std::string& camera) {
    if (isSceneFile(path)) {
        Scene scene = loadScene(path);
        if (!camera.empty() && camera != "0" && camera != "camera")
            throw SceneError(path.string(), 0, "--camera " + camera + " names no camera; a scene file has one, 0");
        return scene;
    }
    AuthoredScene authored;
    if (isGltfFile(path)) {
        authored = loadGltfScene(path);
    } else if (!objMaterialLibraries(path).empty()) {
        authored = loadObjMtlScene(path);
    } else {
        if (!camera.empty()) throw SceneError(path.string(), 0, "--camera " + camera + ": the file has no cameras");
        return quickLookScene(path);
    }
    // Defaults only where nothing is authored: the quick look's camera when
    // the file has none, its lights and floor when it has no lights.
    Scene scene = std::move(authored.scene);
    scene.sourcePath = quickLookScenePath(path);
    bool hasCamera = !authored.cameras.empty();
    if (hasCamera) scene.camera = chooseCamera(authored.cameras, camera, path.string()).camera;
    else if (!camera.empty()) chooseCamera(authored.cameras, camera, path.string());  // throws: no cameras
    frameModel(scene, !hasCamera, scene.lights.empty());
    return scene;
}

}  // namespace whitted
