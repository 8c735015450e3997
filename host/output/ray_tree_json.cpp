// The ray tree's JSON record (output/ray_tree_json.h): what `whitted trace
// --json` prints and what the Python module's trace_pixel returns.
#include "output/ray_tree_json.h"

#include "device_types.h"
#include "ray_tree_types.h"

#include <nlohmann/json.hpp>

namespace whitted {

namespace {
nlohmann::json rgbJson(glm::vec3 c) { return {c.r, c.g, c.b}; }

// The full record: every field of every ray, shadow ray and crossing, the
// objects named.
nlohmann::json rayTreeJsonValue(const RayTree& tree, const Scene& scene, std::span<const uint64_t> objectIds) {
    auto object = [&](uint32_t material) -> nlohmann::json {
        if (material == gpu::kNoObject) return nullptr;
        bool isObject = material < scene.objects.size();
        nlohmann::json id = nullptr;  // a csg part's own material has none
        if (isObject) id = material < objectIds.size() ? objectIds[material] : uint64_t(material);
        return {{"material", material},
                {"id", id},
                {"label", objectLabel(scene, material)},
                {"name", isObject ? scene.objects[material].name : ""}};
    };
    nlohmann::json rays = nlohmann::json::array();
    for (uint32_t i = 0; i < tree.rays.size(); ++i) {
        const gpu::RayTreeRay& r = tree.rays[i];
        nlohmann::json ray = {{"index", i},
                              {"kind", rayKindName(r.kind)},
                              {"depth", r.depth},
                              {"parent", r.parent == gpu::kNoObject ? nlohmann::json(nullptr) : nlohmann::json(r.parent)},
                              {"origin", rgbJson(r.origin)},
                              {"direction", rgbJson(r.direction)},
                              {"weight", rgbJson(r.weight)},
                              {"ambient", rgbJson(r.ambient)},
                              {"diffuse", rgbJson(r.diffuse)},
                              {"specular", rgbJson(r.specular)},
                              {"emission", rgbJson(r.emission)},
                              {"contribution", rgbJson(r.contribution)},
                              {"hit", nullptr}};
        if (r.primitive != gpu::kNoObject)
            ray["hit"] = {{"t", r.t},
                          {"object", object(r.material)},
                          {"primitive", r.primitive},
                          {"shape", shapeName(r.shape)},
                          {"front_face", r.frontFace != 0},
                          {"point", rgbJson(r.point)},
                          {"normal", rgbJson(r.normal)}};
        nlohmann::json shadows = nlohmann::json::array();
        for (const gpu::RayTreeShadowRay& sr : tree.shadowRaysOf(i)) {
            nlohmann::json crossings = nlohmann::json::array();
            for (const gpu::RayTreeCrossing& c : tree.crossingsOf(sr))
                crossings.push_back({{"t", c.t},
                                     {"object", object(c.material)},
                                     {"primitive", c.primitive},
                                     {"filter", rgbJson(c.filterColour)}});
            shadows.push_back({{"light", sr.light},
                               {"origin", rgbJson(sr.origin)},
                               {"direction", rgbJson(sr.direction)},
                               {"distance", sr.distance},
                               {"outcome", shadowOutcomeName(sr.outcome)},
                               {"blocker", object(sr.blockerMaterial)},
                               {"blocker_t", sr.blockerT},
                               {"visibility", rgbJson(sr.visibility)},
                               {"transmittance", rgbJson(sr.transmittance)},
                               {"absorption", rgbJson(sr.absorption)},
                               {"diffuse", rgbJson(sr.diffuse)},
                               {"specular", rgbJson(sr.specular)},
                               {"crossings", crossings},
                               {"dropped_crossings", sr.droppedCrossings}});
        }
        ray["shadow_rays"] = shadows;
        rays.push_back(ray);
    }
    return {{"pixel", {tree.x, tree.y}},
            {"width", tree.width},
            {"height", tree.height},
            {"max_depth", tree.maxDepth},
            {"color", rgbJson(tree.color())},
            {"dropped", tree.dropped},
            {"complete", tree.dropped == 0},
            {"rays", rays}};
}

}  // namespace

std::string rayTreeJson(const RayTree& tree, const Scene& scene, std::span<const uint64_t> objectIds) {
    return rayTreeJsonValue(tree, scene, objectIds).dump(2) + "\n";
}

std::string rayTreesJson(const std::vector<RayTree>& trees, const Scene& scene) {
    nlohmann::json all = nlohmann::json::array();
    for (const RayTree& tree : trees) all.push_back(rayTreeJsonValue(tree, scene, {}));
    return all.dump(2) + "\n";
}

}  // namespace whitted
