// Rays, hits and the robust secondary-ray origin offset.
#ifndef WHITTED_RAY_GLSL
#define WHITTED_RAY_GLSL

struct Ray {
    vec3 origin;
    vec3 dir;  // unit length
};

// Nearest hit along a ray. normal is the shape's geometric normal: outward
// for closed shapes, winding order for triangles, the given normal for
// planes. Which side was hit is decided by the caller (dot with ray.dir).
struct Hit {
    float t;
    vec3 normal;
    uint primitive;
    uint instance;  // the instance whose prototype holds it (normal already in world space), or kNoInstance
};

// Texture coordinates at a surface point (scenes/README.md "Textures") and their
// derivatives: the world-space change of the point per unit of u and of v.
// |dpdu x dpdv| is the world area one unit square of texture covers, which
// the ray-cone LOD needs (shaders/texture.glsl).
struct SurfaceUv {
    vec2 uv;
    vec3 dpdu;
    vec3 dpdv;
    vec3 tangent;  // a mesh's interpolated vertex tangent, or zero (then dpdu is the tangent)
};

// A unit vector perpendicular to unit n, the same for the same n: the
// u direction of planar mappings, normalize(n x z) (x when n is along z).
vec3 planarTangent(vec3 n) {
    vec3 t = cross(n, vec3(0.0, 0.0, 1.0));
    return dot(t, t) > 1e-12 ? normalize(t) : vec3(1.0, 0.0, 0.0);
}

// Moves a surface point off the surface along n so that a ray leaving from it
// does not re-hit the surface it starts on, whatever the point's magnitude:
// integer ulp offset far from the origin, float offset near it.
// "A Fast and Robust Method for Avoiding Self-Intersection", Wächter and
// Binder, Ray Tracing Gems ch. 6 (2019).
vec3 offsetRay(vec3 p, vec3 n) {
    const float kOrigin = 1.0 / 32.0;
    const float kFloatScale = 1.0 / 65536.0;
    const float kIntScale = 256.0;
    ivec3 offsetInt = ivec3(kIntScale * n);
    vec3 pInt = vec3(
        intBitsToFloat(floatBitsToInt(p.x) + (p.x < 0.0 ? -offsetInt.x : offsetInt.x)),
        intBitsToFloat(floatBitsToInt(p.y) + (p.y < 0.0 ? -offsetInt.y : offsetInt.y)),
        intBitsToFloat(floatBitsToInt(p.z) + (p.z < 0.0 ? -offsetInt.z : offsetInt.z)));
    return vec3(abs(p.x) < kOrigin ? p.x + kFloatScale * n.x : pInt.x,
                abs(p.y) < kOrigin ? p.y + kFloatScale * n.y : pInt.y,
                abs(p.z) < kOrigin ? p.z + kFloatScale * n.z : pInt.z);
}

#endif
