#include "scene/scene_loader.h"

#include "io/texture_file.h"
#include "scene/camera_matrices.h"
#include "scene/environment_reader.h"
#include "scene/mesh_objects.h"
#include "scene/xml_reader.h"

#include "device_types.h"

#include <tinyxml2.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <stdexcept>
#include <system_error>
#include <tuple>
#include <utility>
#include <vector>

namespace whitted {

namespace {

using namespace xml;

// The format's limits (scenes/README.md "Scene files") are the XML reader's
// (scene/xml_reader.h), the image side gpu::kMaxImageSide and these.

// ---- Value ranges ------------------------------------------------------------------

// kIorRange, kShininessRange, kFovRange and the spot angles: scene_loader.h.

// ---- The schema ----------------------------------------------------------------------

const std::vector<std::string> kTypeNames = {"sphere", "cylinder", "mesh", "plane", "triangle", "box", "csg"};
// The types a csg object's child may have: closed solids.
const std::vector<std::string> kCsgChildTypes = {"sphere", "cylinder", "box", "csg"};
// The material elements of an <object> and of its <properties>: a csg child
// with none of them takes the csg object's material.
const std::vector<std::string_view> kObjectMaterialElements = {"diffuse_color", "specular_color"};
const std::vector<std::string_view> kMaterialProperties = {
    "refraction_coef", "transmission_coef", "specular_coef", "diffuse_coef", "ambiente_coef", "reflective",
    "shininess",       "reflection_coef",   "checker_color", "checker_size", "absorption",
    "diffuse_texture", "texture_scale",   "normal_map",    "normal_strength", "fresnel",
    "transmission_color", "emission", "emission_texture", "ambient_color",
    "roughness", "roughness_texture"};

// <properties>: the seed's material elements, the extensions, then the
// shape elements (each applies to some types only; see readShape).
const std::vector<ChildRule> kPropertyRules = {{"type"},
                                               {"refraction_coef"},
                                               {"transmission_coef"},
                                               {"specular_coef"},
                                               {"diffuse_coef"},
                                               {"ambiente_coef"},
                                               {"reflective"},
                                               {"shininess"},
                                               {"reflection_coef"},
                                               {"checker_color"},
                                               {"checker_size"},
                                               {"absorption"},
                                               {"diffuse_texture"},
                                               {"texture_scale"},
                                               {"normal_map"},
                                               {"normal_strength"},
                                               {"fresnel"},
                                               {"transmission_color"},
                                               {"emission"},
                                               {"emission_texture"},
                                               {"ambient_color"},
                                               {"roughness"},
                                               {"roughness_texture"},
                                               {"radius"},
                                               {"height"},
                                               {"axis"},
                                               {"normal"},
                                               {"size"},
                                               {"vertex", true},
                                               {"polygons"},
                                               {"file"},
                                               {"scale"},
                                               {"rotation"},
                                               {"matrix"},
                                               {"operation"}};

// ---- The loader --------------------------------------------------------------------

// Reads one parsed document into a Scene; every method refuses bad input
// through diag_ with the line of the element at fault.
class SceneReader {
public:
    SceneReader(const std::filesystem::path& name, Scene& scene) : diag_(name.string(), scene.warnings), scene_(scene) {
        scene_.sourcePath = name;
    }

    void read(const tinyxml2::XMLDocument& doc) {
        const XMLElement* root = doc.RootElement();
        if (!root) diag_.fail(nullptr, "no root element; expected <scene>");
        if (std::string_view(root->Name()) != "scene")
            diag_.fail(root, "root element is " + tag(root->Name()) + ", expected <scene>");
        if (const XMLElement* second = root->NextSiblingElement())
            diag_.fail(second, "second root element " + tag(second->Name()) + "; a scene file holds one <scene>");
        // tinyxml2 keeps text beside the root element ("junk <scene>...")
        // without complaint.
        for (const XMLNode* node = doc.FirstChild(); node; node = node->NextSibling())
            if (const XMLText* text = node->ToText(); text && !trimmed(text->Value()).empty())
                diag_.fail(text, "unexpected text " + inQuotes(trimmed(text->Value())) + " outside <scene>");

        ElementReader s(diag_, root, {{"camera"}, {"lights"}, {"objects"}, {"ambient_light"}, {"environment"},
                                      {"prototypes"}, {"instances"}});
        scene_.camera = readCamera(s.required("camera"));
        // The environment before the lights: one that gives light makes a scene without lights no mistake.
        if (const XMLElement* environment = s.optional("environment"))
            scene_.environment = readEnvironment(diag_, environment, scene_.sourcePath.parent_path());
        readLights(s.required("lights"));
        readObjects(s.required("objects"));
        if (const XMLElement* prototypes = s.optional("prototypes")) readPrototypes(prototypes);
        if (const XMLElement* instances = s.optional("instances")) readInstances(instances);
        if (scene_.objects.empty() && scene_.instances.empty())
            diag_.warn(s.element()->FirstChildElement("objects"), "scene has no objects; the image will be black");
        if (const XMLElement* ambient = s.optional("ambient_light"))
            scene_.ambientLight = colour(diag_, ambient, kNonNegative);
    }

private:
    // ---- Camera ----

    Camera readCamera(const XMLElement* e) const {
        ElementReader c(diag_, e,
                        {{"position"}, {"window_position"}, {"up"}, {"fov"}, {"window_height"}, {"width"}, {"height"}, {"projection"},
                         {"intrinsics"}, {"aperture_radius"}, {"focus_distance"}});
        Camera camera;
        camera.eye = vector(diag_, c.required("position"));
        camera.windowCenter = vector(diag_, c.required("window_position"));
        if (cameraFrameProblem(camera) == CameraFrameProblem::EyeAtWindow)
            diag_.fail(e, "camera <position> and <window_position> coincide");
        const double distance = glm::length(camera.windowCenter - camera.eye);

        // The image frame needs an up that is not along the view.
        if (const XMLElement* up = c.optional("up")) {
            camera.up = direction(diag_, up);
            if (cameraFrameProblem(camera) == CameraFrameProblem::UpAlongView)
                diag_.fail(up, "camera <up> is parallel to the viewing direction");
        } else if (cameraFrameProblem(camera) == CameraFrameProblem::UpAlongView) {
            diag_.fail(
                e, "camera looks along the default <up> (0, 1, 0); give an <up> not parallel to the viewing direction");
        }

        // The field of view, given directly or as the window's height at its
        // distance from the eye.
        const XMLElement* fov = c.optional("fov");
        const XMLElement* windowHeight = c.optional("window_height");
        if (fov && windowHeight)
            diag_.fail(laterOf(fov, windowHeight), "<camera> has both <fov> and <window_height>; give one");
        // An orthographic camera's window is <window_height> high, its rays
        // parallel to the view (scenes/README.md "Scene files").
        if (const XMLElement* projection = c.optional("projection")) {
            std::string name = valueText(diag_, projection);
            if (name == "orthographic") {
                camera.projection = Camera::Projection::Orthographic;
                if (fov) diag_.fail(fov, "an orthographic <camera> has no <fov>; give its <window_height>");
                if (!windowHeight)
                    diag_.fail(projection, "an orthographic <camera> needs a <window_height> (the window's height in "
                                           "scene units)");
                camera.windowHeight = number(diag_, windowHeight, kPositive);
                windowHeight = nullptr;
            } else if (name != "perspective") {
                diag_.fail(projection, "<projection> must be perspective or orthographic, got " + inQuotes(name));
            }
        }
        if (fov) camera.verticalFovDegrees = number(diag_, fov, kFovRange);
        if (windowHeight) {
            double height = number(diag_, windowHeight, kPositive);
            camera.verticalFovDegrees = glm::degrees(2.0 * std::atan(height / 2.0 / distance));
            if (!kFovRange.contains(camera.verticalFovDegrees))
                diag_.fail(windowHeight, "<window_height> gives a field of view of " +
                                             showBound(camera.verticalFovDegrees) + " degrees; it must be " +
                                             kFovRange.describe());
        }

        constexpr int maxSide = int(gpu::kMaxImageSide);
        if (const XMLElement* width = c.optional("width")) camera.width = integer(diag_, width, 1, maxSide);
        if (const XMLElement* height = c.optional("height")) camera.height = integer(diag_, height, 1, maxSide);
        // A pinhole K in pixels of width x height (scene/scene.h
        // Camera::intrinsics; Python's Camera.set_from_matrices).
        if (const XMLElement* k = c.optional("intrinsics")) {
            if (camera.projection == Camera::Projection::Orthographic)
                diag_.fail(k, "an orthographic <camera> has no <intrinsics>");
            if (fov || windowHeight)
                diag_.fail(laterOf(k, fov ? fov : windowHeight),
                           "<camera> has both <intrinsics> and " + std::string(fov ? "<fov>" : "<window_height>") +
                               "; give one");
            auto v = components(diag_, k, {{"fx", kPositive}, {"fy", kPositive}, {"cx", kAnyValue}, {"cy", kAnyValue}});
            camera.intrinsics = Camera::Intrinsics{.fx = v[0], .fy = v[1], .cx = v[2], .cy = v[3]};
            camera.verticalFovDegrees = intrinsicsVerticalFov(*camera.intrinsics, camera.height);
        }
        // Depth of field: a thin lens (scenes/README.md "Depth of field").
        if (const XMLElement* a = c.optional("aperture_radius")) camera.apertureRadius = number(diag_, a, kNonNegative);
        if (const XMLElement* f = c.optional("focus_distance")) camera.focusDistance = number(diag_, f, kPositive);
        return camera;
    }


    // ---- Lights ----

    void readLights(const XMLElement* e) {
        ElementReader lights(diag_, e, {{"light", true}});
        for (const XMLElement* light : lights.all("light")) scene_.lights.push_back(readLight(light));
        bool environmentLight = scene_.environment && scene_.environment->shadowSamples > 0;
        if (scene_.lights.empty() && !environmentLight)
            diag_.warn(e, "scene has no lights; only ambient light will show");
    }

    // A point light (the seed's), a spot or a directional light
    // (scenes/README.md "Lights"). Each type takes only the elements it
    // uses; the rest are refused as not applying to it.
    Light readLight(const XMLElement* e) const {
        ElementReader l(diag_, e,
                        {{"type"},
                         {"position"},
                         {"color"},
                         {"intensity"},
                         {"falloff"},
                         {"direction"},
                         {"inner_angle"},
                         {"outer_angle"},
                         {"radius"},
                         {"shadow_samples"},
                         {"u"},
                         {"v"},
                         {"two_sided"},
                         {"name"}});
        Light light;
        light.sourceLine = e->GetLineNum();
        if (const XMLElement* type = l.optional("type")) {
            std::string t = valueText(diag_, type);
            if (t == "point")
                light.type = Light::Type::Point;
            else if (t == "spot")
                light.type = Light::Type::Spot;
            else if (t == "directional")
                light.type = Light::Type::Directional;
            else if (t == "rect")
                light.type = Light::Type::Rect;
            else
                diag_.fail(type, "<type> of a light must be point, spot, directional or rect, got " + inQuotes(t));
        }
        const char* typeName = light.type == Light::Type::Point         ? "point"
                               : light.type == Light::Type::Spot        ? "spot"
                               : light.type == Light::Type::Directional ? "directional"
                                                                        : "rect";
        auto notApplying = [&](const XMLElement* element, const std::string& why) {
            diag_.fail(element, tag(element->Name()) + " does not apply to a " + typeName + " light; " + why);
        };

        const XMLElement* position = l.optional("position");
        if (light.type == Light::Type::Directional) {
            if (position)
                diag_.fail(position, "a directional light has no <position>: its light comes from infinitely far, "
                                     "along its <direction>");
        } else {
            light.position = vector(diag_, l.required("position"));
        }
        light.color = colour(diag_, l.required("color"), kNonNegative);
        if (const XMLElement* intensity = l.optional("intensity"))
            light.intensity = number(diag_, intensity, kNonNegative);
        if (const XMLElement* falloff = l.optional("falloff")) {
            if (light.type == Light::Type::Directional)
                notApplying(falloff, "its light does not weaken with distance");
            std::string f = valueText(diag_, falloff);
            if (f == "none")
                light.falloff = Light::Falloff::None;
            else if (f == "inverse_square")
                light.falloff = Light::Falloff::InverseSquare;
            else
                diag_.fail(falloff, "<falloff> must be none or inverse_square, got " + inQuotes(f));
        }

        const XMLElement* direction = l.optional("direction");
        if (light.type == Light::Type::Point || light.type == Light::Type::Rect) {
            if (direction) notApplying(direction, "only spot and directional lights have one");
        } else {
            if (!direction)
                diag_.fail(e, "<light> is missing <direction> (required for a " + std::string(typeName) + " light)");
            light.direction = xml::direction(diag_, direction);
        }

        const XMLElement* inner = l.optional("inner_angle");
        const XMLElement* outer = l.optional("outer_angle");
        if (light.type != Light::Type::Spot) {
            if (const XMLElement* angle = inner ? inner : outer) notApplying(angle, "only a spot light has a cone");
        } else {
            if (inner) light.innerAngleDegrees = number(diag_, inner, kInnerAngleRange);
            if (outer) light.outerAngleDegrees = number(diag_, outer, kOuterAngleRange);
            if (!(light.innerAngleDegrees < light.outerAngleDegrees))
                diag_.fail(outer ? outer : inner, "<outer_angle> (" + showBound(light.outerAngleDegrees) +
                                                      ") must be greater than <inner_angle> (" +
                                                      showBound(light.innerAngleDegrees) +
                                                      "); a spot has 0 <= inner < outer <= 90 degrees");
        }
        readAreaLight(l, light, notApplying);
        if (const XMLElement* name = l.optional("name")) light.name = valueText(diag_, name);
        return light;
    }

    // What makes a light an area light (scenes/README.md "Area lights"): a
    // point or spot light's <radius>, a rect light's <u>, <v> and
    // <two_sided>, and either's <shadow_samples>.
    template <typename NotApplying>
    void readAreaLight(ElementReader& l, Light& light, const NotApplying& notApplying) const {
        const XMLElement* radius = l.optional("radius");
        if (radius) {
            if (light.type != Light::Type::Point && light.type != Light::Type::Spot)
                notApplying(radius, "only point and spot lights are spheres (a rect light has <u> and <v>)");
            light.radius = number(diag_, radius, kLightRadiusRange);
        }
        for (const char* rectOnly : {"u", "v", "two_sided"})
            if (const XMLElement* element = l.optional(rectOnly); element && light.type != Light::Type::Rect)
                notApplying(element, "only a rect light has edges and faces");
        if (light.type == Light::Type::Rect) {
            const XMLElement* u = l.required("u");
            const XMLElement* v = l.required("v");
            light.u = vector(diag_, u);
            light.v = vector(diag_, v);
            if (glm::length(light.u) == 0.0) diag_.fail(u, "<u> of a rect light must not be zero");
            if (glm::length(light.v) == 0.0) diag_.fail(v, "<v> of a rect light must not be zero");
            if (!rectEdgesSpan(light.u, light.v))
                diag_.fail(v, "<v> of a rect light must not be parallel to its <u>: the rectangle has no area");
            if (const XMLElement* twoSided = l.optional("two_sided")) light.twoSided = boolean(diag_, twoSided);
        }
        if (const XMLElement* samples = l.optional("shadow_samples")) {
            if (!light.area())
                notApplying(samples, "it needs one shadow ray: only an area light (a point or spot light with a "
                                     "<radius> above 0, a rect light) takes more");
            light.shadowSamples = integer(diag_, samples, 1, kMaxShadowSamples);
        }
    }

    // ---- Objects ----

    void readObjects(const XMLElement* e) {
        ElementReader objects(diag_, e, {{"object", true}});
        for (const XMLElement* object : objects.all("object"))
            for (Object& o : readObject(object)) scene_.objects.push_back(std::move(o));
    }

    // ---- Instances (scenes/README.md "Instances") ----

    // <prototypes>: each <prototype> a <name> and the mesh and triangle
    // <objects> it holds, in its own space; drawn only through instances.
    void readPrototypes(const XMLElement* e) {
        ElementReader prototypes(diag_, e, {{"prototype", true}});
        for (const XMLElement* element : prototypes.all("prototype")) {
            ElementReader p(diag_, element, {{"name"}, {"objects"}});
            Prototype prototype;
            prototype.sourceLine = element->GetLineNum();
            const XMLElement* name = p.required("name");
            prototype.name = valueText(diag_, name);
            if (prototype.name.empty()) diag_.fail(name, "<name> of a <prototype> is empty");
            for (const Prototype& other : scene_.prototypes)
                if (other.name == prototype.name)
                    diag_.fail(name, "a second <prototype> named " + inQuotes(prototype.name) + " (the first on line " +
                                         std::to_string(other.sourceLine) + ")");
            ElementReader objects(diag_, p.required("objects"), {{"object", true}});
            if (objects.all("object").empty())
                diag_.fail(objects.element(), "<objects> of a <prototype> holds no <object>; it needs at least one");
            for (const XMLElement* object : objects.all("object")) {
                for (Object& o : readObject(object)) {
                    if (!std::holds_alternative<Mesh>(o.shape) && !std::holds_alternative<Triangle>(o.shape))
                        diag_.fail(object, "a <prototype> holds meshes and triangles only, got type " +
                                               valueText(diag_, object->FirstChildElement("properties")
                                                                    ->FirstChildElement("type")));
                    prototype.objects.push_back(std::move(o));
                }
            }
            scene_.prototypes.push_back(std::move(prototype));
        }
    }

    // <instances>: each <instance> names its <prototype>, places it
    // (<position>, <matrix> or <scale> and <rotation>) and may give a
    // <name> and a material of its own (<properties> with the material
    // elements, <diffuse_color> and <specular_color> beside it).
    void readInstances(const XMLElement* e) {
        ElementReader instances(diag_, e, {{"instance", true}});
        for (const XMLElement* element : instances.all("instance")) {
            ElementReader r(diag_, element,
                            {{"prototype"}, {"name"}, {"position"}, {"matrix"}, {"scale"}, {"rotation"},
                             {"diffuse_color"}, {"specular_color"}, {"properties"}});
            Instance instance;
            instance.sourceLine = element->GetLineNum();
            const XMLElement* prototype = r.required("prototype");
            std::string name = valueText(diag_, prototype);
            auto found = std::find_if(scene_.prototypes.begin(), scene_.prototypes.end(),
                                      [&](const Prototype& p) { return p.name == name; });
            if (found == scene_.prototypes.end())
                diag_.fail(prototype, "<prototype> " + inQuotes(name) + " is not one of the scene's <prototypes>");
            instance.prototype = uint32_t(found - scene_.prototypes.begin());
            if (const XMLElement* n = r.optional("name")) instance.name = valueText(diag_, n);
            instance.worldFromObject = readInstanceTransform(diag_, r);
            if (const XMLElement* properties = r.optional("properties")) {
                ElementReader p(diag_, properties, kPropertyRules);
                instance.material = readMaterial(r, p);
                if (const XMLElement* extra = p.firstUnused())
                    diag_.fail(extra,
                               tag(extra->Name()) + " does not apply to an <instance>; only material elements do");
            } else if (const XMLElement* colour = r.optional("diffuse_color") ? r.optional("diffuse_color")
                                                                               : r.optional("specular_color")) {
                diag_.fail(colour,
                           tag(colour->Name()) + " of an <instance> needs <properties> beside it (its own material)");
            }
            scene_.instances.push_back(std::move(instance));
        }
    }

    // A top-level <object> (csg == nullptr), or a child of a csg object:
    // then its position is relative to csg->origin, it must be a closed
    // solid, and without material elements it takes csg->material.
    struct CsgParent {
        glm::dvec3 origin;
        const Material* material;
        int depth;  // of the parent: 1 for a top-level csg object
    };

    // One object, or for a model file with materials of its own, used when
    // the scene gives the object no colour (scenes/README.md "Model files"), one per
    // material of the file (a csg child is one object: meshes are refused there).
    std::vector<Object> readObject(const XMLElement* e, const CsgParent* csg = nullptr) {
        ElementReader object(diag_, e,
                             {{"position"},
                              {"diffuse_color"},
                              {"specular_color"},
                              {"properties"},
                              {"objects"},
                              {"name"}});
        ElementReader properties(diag_, object.required("properties"), kPropertyRules);
        fileMaterials_ = FileMaterials();
        fileMaterials_.wanted = !e->FirstChildElement("diffuse_color") &&
                                !properties.element()->FirstChildElement("diffuse_texture");

        const XMLElement* typeElement = properties.required("type");
        std::string type = valueText(diag_, typeElement);
        if (std::find(kTypeNames.begin(), kTypeNames.end(), type) == kTypeNames.end())
            diag_.fail(typeElement, "<type> must be " + joined(kTypeNames, " or ") + ", got " + inQuotes(type));
        if (csg && std::find(kCsgChildTypes.begin(), kCsgChildTypes.end(), type) == kCsgChildTypes.end())
            diag_.fail(typeElement, "a csg child cannot be of type " + type +
                                        "; it must be a closed solid: " + joined(kCsgChildTypes, " or "));
        if (csg && type == "csg" && csg->depth + 1 > int(kCsgMaxDepth))
            diag_.fail(e, "csg objects nested " + std::to_string(csg->depth + 1) + " deep; at most " +
                              std::to_string(kCsgMaxDepth) + " levels (the shader's evaluation stack)");
        glm::dvec3 origin = csg ? csg->origin : glm::dvec3(0);

        Object result;
        result.sourceLine = e->GetLineNum();
        if (const XMLElement* name = object.optional("name")) result.name = valueText(diag_, name);
        bool ownMaterial = !csg || hasMaterial(e);
        result.material = ownMaterial ? readMaterial(object, properties) : *csg->material;
        if (type == "csg") {
            result.shape = readCsg(object, properties, origin, result.material, csg ? csg->depth + 1 : 1);
        } else {
            if (const XMLElement* objects = object.optional("objects"))
                diag_.fail(objects, "<objects> does not apply to type " + type + "; only a csg object has children");
            result.shape = readShape(type, object, properties, origin);
        }
        readTextures(type, properties, result);
        // A checker is anchored at the object's position (the origin without one).
        const XMLElement* position = object.optional("position");
        if (ownMaterial && position && result.material.checkerSize > 0)
            result.material.checkerOrigin = origin + vector(diag_, position);

        // The shape readers took what their type uses; anything left over
        // belongs to another type.
        if (const XMLElement* extra = properties.firstUnused())
            diag_.fail(extra, tag(extra->Name()) + " does not apply to type " + type);
        if (fileMaterials_.materials.empty()) return {std::move(result)};
        return splitByFileMaterial(std::move(result), fileMaterials_);
    }

    // ---- Textures ----

    // <diffuse_texture>, <normal_map>, <emission_texture> and <roughness_texture> (with
    // <roughness>) on every type but triangle (which
    // has no texture coordinates; a mesh of one polygon with <uv> has),
    // <normal_strength> with a <normal_map>, <texture_scale> on
    // planes only (scenes/README.md "Textures"). Left unread elsewhere, they are
    // reported as not applying to the type.
    void readTextures(const std::string& type, ElementReader& properties, Object& object) {
        if (type == "triangle") return;
        for (auto [name, encoding, target] : {std::tuple("diffuse_texture", TextureEncoding::Colour,
                                                         &object.material.diffuseTexture),
                                              std::tuple("normal_map", TextureEncoding::Data,
                                                         &object.material.normalMap),
                                              std::tuple("emission_texture", TextureEncoding::Colour,
                                                         &object.material.emissionTexture),
                                              std::tuple("roughness_texture", TextureEncoding::Data,
                                                         &object.material.roughnessTexture)}) {
            const XMLElement* e = properties.optional(name);
            if (!e) continue;
            if (const Mesh* mesh = std::get_if<Mesh>(&object.shape); mesh && mesh->uvs.empty())
                diag_.fail(e, tag(name) + " on a mesh needs texture coordinates: the mesh file has none, or "
                                          "the <polygon>s have no <uv>");
            *target = readTexture(e, encoding);
            if (target == &object.material.roughnessTexture && !(object.material.roughness > 0))
                diag_.fail(e, "<roughness_texture> multiplies <roughness>: it needs <roughness> > 0 beside it in "
                              "<properties>");
        }
        if (const XMLElement* e = properties.optional("normal_strength")) {
            if (!object.material.normalMap)
                diag_.fail(e, "<normal_strength> needs <normal_map> beside it in <properties>");
            object.material.normalStrength = number(diag_, e, kNonNegative);
        }
        if (type == "plane")
            if (const XMLElement* e = properties.optional("texture_scale"))
                object.material.textureScale = number(diag_, e, kPositive);
    }

    // A texture file, its path relative to the scene file's folder; each
    // file is read once per scene.
    TextureRef readTexture(const XMLElement* e, TextureEncoding encoding) {
        std::string written = valueText(diag_, e);
        if (written.empty()) diag_.fail(e, tag(e->Name()) + " is empty; expected the path of an image file");
        std::filesystem::path path(written);
        if (path.is_relative()) path = scene_.sourcePath.parent_path() / path;
        auto& cached = textures_[{path, encoding}];
        if (!cached) {
            try {
                cached = std::make_shared<const TextureData>(readTextureFile(path, encoding));
            } catch (const TextureFileError& error) {
                diag_.fail(e, "texture file \"" + written + "\" " + error.what());
            }
        }
        return {written, cached};
    }

    // Whether an <object> (already checked by readObject's readers) gives
    // any material element.
    static bool hasMaterial(const XMLElement* object) {
        auto has = [](const XMLElement* e, std::string_view name) {
            return e && e->FirstChildElement(std::string(name).c_str()) != nullptr;
        };
        const XMLElement* properties = object->FirstChildElement("properties");
        return std::any_of(kObjectMaterialElements.begin(), kObjectMaterialElements.end(),
                           [&](std::string_view n) { return has(object, n); }) ||
               std::any_of(kMaterialProperties.begin(), kMaterialProperties.end(),
                           [&](std::string_view n) { return has(properties, n); });
    }


    // A csg object (scenes/README.md "CSG"): <operation> in <properties>, its children
    // in <objects>, placed relative to its <position> (the parent's origin
    // without one). The leaves of a top-level csg object are limited by the
    // shader's fixed-size state (device_types.h).
    Csg readCsg(ElementReader& object, ElementReader& properties, const glm::dvec3& origin, const Material& material,
                int depth) {
        const XMLElement* e = object.element();
        Csg csg;
        const XMLElement* operation = properties.optional("operation");
        if (!operation) diag_.fail(e, "<object> is missing <operation> (required for type csg)");
        std::string op = valueText(diag_, operation);
        if (op == "union")
            csg.operation = Csg::Operation::Union;
        else if (op == "intersection")
            csg.operation = Csg::Operation::Intersection;
        else if (op == "difference")
            csg.operation = Csg::Operation::Difference;
        else
            diag_.fail(operation, "<operation> must be union, intersection or difference, got " + inQuotes(op));
        const XMLElement* position = object.optional("position");
        csg.position = origin + (position ? vector(diag_, position) : glm::dvec3(0));
        const XMLElement* objectsElement = object.optional("objects");
        if (!objectsElement) diag_.fail(e, "<object> is missing <objects> (required for type csg)");
        ElementReader objects(diag_, objectsElement, {{"object", true}});
        if (objects.all("object").size() < 2)
            diag_.fail(objectsElement, "<objects> of a csg object holds " +
                                           std::to_string(objects.all("object").size()) +
                                           " <object>; a csg object needs at least two");
        CsgParent parent{csg.position, &material, depth};
        for (const XMLElement* child : objects.all("object")) {
            Object o = std::move(readObject(child, &parent).front());  // one: no mesh children
            csg.children.push_back({std::move(o.shape), o.material, hasMaterial(child), o.sourceLine});
        }
        if (depth == 1 && csgLeafCount(csg) > kCsgMaxLeaves)
            diag_.fail(e, "csg object has " + std::to_string(csgLeafCount(csg)) +
                              " leaf shapes (spheres, cylinders, boxes) in all; at most " +
                              std::to_string(kCsgMaxLeaves) + " (the shader's span arrays)");
        return csg;
    }

    Material readMaterial(ElementReader& object, ElementReader& properties) const {
        Material m;
        if (const XMLElement* c = object.optional("diffuse_color")) m.diffuseColor = colour(diag_, c, kUnitInterval);
        if (const XMLElement* c = object.optional("specular_color")) m.specularColor = colour(diag_, c, kUnitInterval);
        if (const XMLElement* k = properties.optional("ambiente_coef")) m.ambient = number(diag_, k, kUnitInterval);
        if (const XMLElement* k = properties.optional("diffuse_coef")) m.diffuse = number(diag_, k, kUnitInterval);
        if (const XMLElement* k = properties.optional("specular_coef")) m.specular = number(diag_, k, kUnitInterval);
        if (const XMLElement* k = properties.optional("transmission_coef"))
            m.transmission = number(diag_, k, kUnitInterval);
        if (const XMLElement* k = properties.optional("refraction_coef")) m.ior = number(diag_, k, kIorRange);
        if (const XMLElement* k = properties.optional("shininess")) m.shininess = number(diag_, k, kShininessRange);

        // The seed's <reflective> switch mirrors with ks; <reflection_coef>
        // sets kr itself and must not contradict an explicit false.
        const XMLElement* reflective = properties.optional("reflective");
        const XMLElement* reflection = properties.optional("reflection_coef");
        bool isReflective = reflective && boolean(diag_, reflective);
        if (reflection) {
            if (reflective && !isReflective)
                diag_.fail(reflection, "<reflection_coef> contradicts <reflective>false</reflective>");
            m.reflection = number(diag_, reflection, kUnitInterval);
        } else if (isReflective) {
            m.reflection = m.specular;
        }

        // A checker takes its second colour and its cell size together.
        const XMLElement* checkerColor = properties.optional("checker_color");
        const XMLElement* checkerSize = properties.optional("checker_size");
        if (checkerColor && !checkerSize)
            diag_.fail(checkerColor, "<checker_color> needs <checker_size> beside it in <properties>");
        if (checkerSize && !checkerColor)
            diag_.fail(checkerSize, "<checker_size> needs <checker_color> beside it in <properties>");
        if (checkerColor) {
            m.checkerColor = colour(diag_, checkerColor, kUnitInterval);
            m.checkerSize = number(diag_, checkerSize, kPositive);
        }
        if (const XMLElement* a = properties.optional("absorption")) m.absorption = colour(diag_, a, kNonNegative);
        // The additions for authored scenes (scenes/README.md "Materials").
        if (const XMLElement* f = properties.optional("fresnel")) m.fresnel = boolean(diag_, f);
        if (const XMLElement* c = properties.optional("transmission_color"))
            m.transmissionColor = colour(diag_, c, kUnitInterval);
        if (const XMLElement* c = properties.optional("emission")) m.emission = colour(diag_, c, kNonNegative);
        if (const XMLElement* c = properties.optional("ambient_color")) m.ambientColor = colour(diag_, c, kUnitInterval);
        if (const XMLElement* r = properties.optional("roughness")) m.roughness = number(diag_, r, kUnitInterval);
        return m;
    }

    Shape readShape(const std::string& type, ElementReader& object, ElementReader& properties,
                    const glm::dvec3& origin) {
        // What the type requires is reported against <object>.
        auto missing = [&](std::string_view name) {
            diag_.fail(object.element(), "<object> is missing " + tag(name) + " (required for type " + type + ")");
        };
        auto need = [&](std::string_view name) {
            const XMLElement* e = properties.optional(name);
            if (!e) missing(name);
            return e;
        };

        // Only meshes and triangles, whose vertices are relative to it, may
        // leave the position out.
        const XMLElement* positionElement = object.optional("position");
        if (!positionElement && type != "mesh" && type != "triangle") missing("position");
        glm::dvec3 position = origin + (positionElement ? vector(diag_, positionElement) : glm::dvec3(0));

        if (type == "sphere") return Sphere{position, number(diag_, need("radius"), kPositive)};
        if (type == "cylinder") {
            double radius = number(diag_, need("radius"), kPositive);
            double height = number(diag_, need("height"), kPositive);
            const XMLElement* axis = properties.optional("axis");
            return Cylinder{position, axis ? direction(diag_, axis) : glm::dvec3(0, 1, 0), radius, height};
        }
        if (type == "plane") return Plane{position, direction(diag_, need("normal"))};
        if (type == "box") {
            const XMLElement* sizeElement = need("size");
            Box box{position, position + vector(diag_, sizeElement, kPositive)};
            // A size far below the position's magnitude vanishes when added.
            for (int i = 0; i < 3; ++i)
                if (!(box.min[i] < box.max[i]))
                    diag_.fail(sizeElement, std::string("<size> ") + "xyz"[i] +
                                                " is too small to register beside the <position>; the box would be flat");
            return box;
        }
        if (type == "triangle") {
            if (properties.all("vertex").empty()) missing("vertex");
            Triangle t = readTriangle(diag_, properties.element(), properties.all("vertex"), position);
            if (degenerate(t))
                diag_.fail(object.element(), "<object> of type triangle is degenerate: its vertices are collinear");
            return t;
        }
        return readMeshObject(diag_, object, properties, position, scene_.sourcePath.parent_path(), fileMaterials_,
                              modelFiles_);
    }

    Diagnostics diag_;
    Scene& scene_;
    std::map<std::pair<std::filesystem::path, TextureEncoding>, std::shared_ptr<const TextureData>> textures_;
    // The object being read: whether a model file's materials apply, and
    // those read with each kept triangle's index into them.
    FileMaterials fileMaterials_;
    ModelFiles modelFiles_;  // each model file read once, however many <file part> take from it
};

// tinyxml2's ErrorStr() is "Error=NAME ErrorID=N (0xN) Line number=L: detail"
// (the detail is optional); the line goes in front, so keep the name and the
// detail.
std::string xmlErrorMessage(const tinyxml2::XMLDocument& doc) {
    std::string message = std::string("malformed XML: ") + doc.ErrorName();
    std::string full = doc.ErrorStr();
    size_t lineField = full.find("Line number=");
    size_t detail = lineField == std::string::npos ? std::string::npos : full.find(": ", lineField);
    if (detail != std::string::npos) message += " (" + full.substr(detail + 2) + ")";
    // tinyxml2's catch-all: a node that starts on this line did not parse and
    // said nothing more; mostly an element the file ends inside, or a '<'
    // that starts no valid tag.
    else if (doc.ErrorID() == tinyxml2::XML_ERROR_PARSING)
        message += " (a tag that starts on this line is invalid or never closed)";
    return message;
}

// The line of xml[offset], counting from 1.
int lineOf(std::string_view xml, size_t offset) {
    return 1 + int(std::count(xml.begin(), xml.begin() + std::ptrdiff_t(offset), '\n'));
}

}  // namespace

Scene loadSceneFromString(std::string_view xml, const std::filesystem::path& name) {
    // tinyxml2 reads UTF-8 only, and stops at a NUL byte: it would take
    // whatever came before it as the whole file.
    if (xml.starts_with("\xFF\xFE") || xml.starts_with("\xFE\xFF"))
        throw SceneError(name.string(), 1, "the file is UTF-16; a scene file is UTF-8 XML text");
    if (size_t nul = xml.find('\0'); nul != std::string_view::npos)
        throw SceneError(name.string(), lineOf(xml, nul), "NUL byte; a scene file is UTF-8 XML text, not binary data");
    // Nothing but XML whitespace, after a UTF-8 byte order mark if any
    // (tinyxml2 calls most of these XML_ERROR_EMPTY_DOCUMENT).
    std::string_view content = xml.starts_with("\xEF\xBB\xBF") ? xml.substr(3) : xml;
    if (content.find_first_not_of(" \t\r\n") == std::string_view::npos)
        throw SceneError(name.string(), 1, "the file is empty, expected a <scene> document");
    tinyxml2::XMLDocument doc;
    if (doc.Parse(xml.data(), xml.size()) != tinyxml2::XML_SUCCESS)
        throw SceneError(name.string(), doc.ErrorLineNum(), xmlErrorMessage(doc));
    Scene scene;
    SceneReader(name, scene).read(doc);
    return scene;
}

Scene loadScene(const std::filesystem::path& path) {
    auto cannotRead = [&](const std::string& reason) {
        return SceneError(path.string(), 0, "cannot read file: " + reason);
    };
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw cannotRead("it is a directory");
    errno = 0;
    std::ifstream in(path, std::ios::binary);
    if (!in) throw cannotRead(errno ? std::generic_category().message(errno) : "cannot open it");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw cannotRead("read error");
    return loadSceneFromString(text, path);
}

}  // namespace whitted
