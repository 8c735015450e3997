// Local Phong shading at a hit point (scenes/scenes/README.md, "Shading model").
#ifndef WHITTED_SHADING_GLSL
#define WHITTED_SHADING_GLSL
#include "intersect.glsl"

struct LocalShading {
    vec3 ambient;
    vec3 diffuse;
    vec3 specular;
    uint shadowRays;
};

#ifdef WHITTED_RAY_TREE  // the ray-tree recorder's build (shaders/ray_tree.glsl)
#include "ray_tree.glsl"
#endif

// Ambient ka Cd A plus, per point light, its visibility (shadow ray) times
// kd Cd max(N.L, 0) + ks Cs max(R.V, 0)^shininess. n is the shading normal,
// ng the geometric one; both face the viewer and p is already offset to the
// viewer's side of the surface. A light behind the geometric surface gives
// nothing even where the shading normal leans towards it.
LocalShading shadeLocal(Material m, vec3 p, vec3 n, vec3 ng, vec3 viewDir) {
    LocalShading s;
    s.ambient = m.ka * m.diffuse * params.ambientLight;
    s.diffuse = vec3(0.0);
    s.specular = vec3(0.0);
    s.shadowRays = 0u;
    float kd = m.kd, ks = m.ks, shininess = m.shininess;
    uint lightCount = params.lightCount;
#ifdef WHITTED_PROFILE_NO_LIGHTS  // tools/profile_shader.sh: ambient only, no light loop
    lightCount = 0u;
#endif
    for (uint i = 0u; i < lightCount; ++i) {
        vec3 toLight = lights[i].position - p;
        float dist = length(toLight);
        vec3 l = toLight / dist;
        float nDotL = dot(n, l);
        if (nDotL <= 0.0 || dot(ng, l) <= 0.0 || (kd <= 0.0 && ks <= 0.0)) continue;
        s.shadowRays += 1u;
#ifdef WHITTED_PROFILE_NO_SHADOWS  // tools/profile_shader.sh: what shadow rays cost
        vec3 visibility = vec3(1.0);
#else
        vec3 visibility = shadowTransmittance(Ray(p, l), dist);
#endif
#ifdef WHITTED_RAY_TREE
        rayTreeShadowRay(i, Ray(p, l), dist, visibility, s.diffuse, s.specular);
#endif
        if (all(equal(visibility, vec3(0.0)))) continue;
        vec3 light = visibility * lights[i].color;
        s.diffuse += light * kd * m.diffuse * nDotL;
        if (ks > 0.0) {
            vec3 r = reflect(-l, n);
            s.specular += light * ks * m.specular * pow(max(dot(r, viewDir), 0.0), shininess);
        }
    }
    return s;
}

#endif
