#ifndef WHITTED_TRIANGLE_GLSL
#define WHITTED_TRIANGLE_GLSL
#include "../device_types.h"
#include "../ray.glsl"

// Watertight ray/triangle test: "Watertight Ray/Triangle Intersection", Woop,
// Benthin and Wald, JCGT 2(1), 2013. The ray is sheared so it runs along +z,
// and the 2D edge functions are evaluated with the same arithmetic for both
// triangles sharing an edge, so a ray can not slip between them: this fixes
// the seed's holes in meshes seen by shadow and reflection rays. Edges count
// as inside (>= 0 on every edge function); the paper's double-precision
// re-evaluation of exactly-zero edge functions is left out.
bool intersectTriangle(vec3 v0, vec3 v1, vec3 v2, Ray ray, float tMin, inout float tHit, out vec3 normal) {
    // Axis permutation: kz is the dominant axis of the direction.
    vec3 ad = abs(ray.dir);
    int kz = ad.x > ad.y ? (ad.x > ad.z ? 0 : 2) : (ad.y > ad.z ? 1 : 2);
    int kx = kz == 2 ? 0 : kz + 1;
    int ky = kx == 2 ? 0 : kx + 1;
    if (ray.dir[kz] < 0.0) { int s = kx; kx = ky; ky = s; }
    float sx = ray.dir[kx] / ray.dir[kz];
    float sy = ray.dir[ky] / ray.dir[kz];
    float sz = 1.0 / ray.dir[kz];

    // Vertices relative to the origin, sheared. Every vertex goes through
    // the same arithmetic whichever triangle it belongs to (`precise`: no
    // FMA contraction that the compiler could apply to one and not another).
    precise vec3 a = v0 - ray.origin;
    precise vec3 b = v1 - ray.origin;
    precise vec3 c = v2 - ray.origin;
    precise float ax = a[kx] - sx * a[kz], ay = a[ky] - sy * a[kz];
    precise float bx = b[kx] - sx * b[kz], by = b[ky] - sy * b[kz];
    precise float cx = c[kx] - sx * c[kz], cy = c[ky] - sy * c[kz];

    // Scaled barycentric coordinates (edge functions). Unfused, an edge seen
    // from its two triangles gives w and exactly -w: the antisymmetry the
    // watertightness rests on.
    precise float u = cx * by - cy * bx;
    precise float v = ax * cy - ay * cx;
    precise float w = bx * ay - by * ax;
    if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) return false;
    float det = u + v + w;
    if (det == 0.0) return false;

    // Scaled hit distance, compared before the division.
    float az = sz * a[kz], bz = sz * b[kz], cz = sz * c[kz];
    float tScaled = u * az + v * bz + w * cz;
    float t = tScaled / det;
    if (!(t > tMin && t < tHit)) return false;
    tHit = t;
    normal = normalize(cross(v1 - v0, v2 - v0));
    return true;
}

// Inverse of encodeOctahedral() in host/shapes/triangle.cpp (Cigolle et
// al., JCGT 2014): unfold the lower half of the octahedron, normalize.
vec3 decodeOctahedral(uint bits) {
    const uint mask = (1u << kOctahedralBits) - 1u;
    vec2 e = vec2(uvec2(bits & mask, (bits >> kOctahedralBits) & mask)) / float(mask) * 2.0 - 1.0;
    vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    float fold = max(-n.z, 0.0);
    n.xy += mix(vec2(fold), vec2(-fold), greaterThanEqual(n.xy, vec2(0.0)));
    return normalize(n);
}

// Phong's interpolated normal of a smooth triangle at point p on it: the
// vertex normals weighted by p's barycentric coordinates (computed from p as
// in Ericson, "Real-Time Collision Detection", 3.4), not oriented.
vec3 shadingNormalTriangle(vec3 v0, vec3 v1, vec3 v2, uvec3 packedNormals, vec3 p) {
    vec3 e0 = v1 - v0, e1 = v2 - v0, ep = p - v0;
    float d00 = dot(e0, e0), d01 = dot(e0, e1), d11 = dot(e1, e1);
    float d20 = dot(ep, e0), d21 = dot(ep, e1);
    float denom = d00 * d11 - d01 * d01;
    float b1 = clamp((d11 * d20 - d01 * d21) / denom, 0.0, 1.0);
    float b2 = clamp((d00 * d21 - d01 * d20) / denom, 0.0, 1.0 - b1);
    vec3 n = (1.0 - b1 - b2) * decodeOctahedral(packedNormals.x) + b1 * decodeOctahedral(packedNormals.y) +
             b2 * decodeOctahedral(packedNormals.z);
    float length2 = dot(n, n);
    return length2 > 1e-12 ? n * inversesqrt(length2) : normalize(cross(e0, e1));
}

// The vertices' texture coordinates interpolated at p (barycentric
// coordinates from p as in shadingNormalTriangle), and dp/du, dp/dv from the
// triangle's edges in world and texture space (pbrt-v3, 3.6.2). A triangle
// whose UVs have no area gets an arbitrary frame of unit area.
SurfaceUv triangleUv(vec3 v0, vec3 v1, vec3 v2, vec2 uv0, vec2 uv1, vec2 uv2, vec3 p) {
    vec3 e0 = v1 - v0, e1 = v2 - v0, ep = p - v0;
    float d00 = dot(e0, e0), d01 = dot(e0, e1), d11 = dot(e1, e1);
    float d20 = dot(ep, e0), d21 = dot(ep, e1);
    float denom = d00 * d11 - d01 * d01;
    float b1 = (d11 * d20 - d01 * d21) / denom;
    float b2 = (d00 * d21 - d01 * d20) / denom;
    SurfaceUv s;
    s.tangent = vec3(0.0);
    s.uv = (1.0 - b1 - b2) * uv0 + b1 * uv1 + b2 * uv2;
    vec2 duv02 = uv0 - uv2, duv12 = uv1 - uv2;
    vec3 dp02 = v0 - v2, dp12 = v1 - v2;
    float det = duv02.x * duv12.y - duv02.y * duv12.x;
    if (abs(det) < 1e-12) {
        vec3 n = normalize(cross(e0, e1));
        s.dpdu = planarTangent(n);
        s.dpdv = cross(n, s.dpdu);
    } else {
        s.dpdu = (duv12.y * dp02 - duv02.y * dp12) / det;
        s.dpdv = (duv02.x * dp12 - duv12.x * dp02) / det;
    }
    return s;
}

// Signed curvature of a smooth triangle (packed vertex normals) where its
// geometric normal is n: the mean over the edges of
// (n_j - n_i) . (p_j - p_i) / |p_j - p_i|^2 with the vertex normals turned
// to the winding's side (1/r exactly on a sphere's tessellation), positive
// where the surface is convex towards n.
float triangleCurvature(vec3 v0, vec3 v1, vec3 v2, uvec3 packedNormals, vec3 n) {
    vec3 p[3] = vec3[3](v0, v1, v2);
    vec3 v[3] = vec3[3](decodeOctahedral(packedNormals.x), decodeOctahedral(packedNormals.y),
                        decodeOctahedral(packedNormals.z));
    vec3 ng = cross(p[1] - p[0], p[2] - p[0]);
    float k = 0.0;
    for (int i = 0; i < 3; ++i) {
        int j = i == 2 ? 0 : i + 1;
        vec3 ni = dot(v[i], ng) < 0.0 ? -v[i] : v[i];
        vec3 nj = dot(v[j], ng) < 0.0 ? -v[j] : v[j];
        vec3 e = p[j] - p[i];
        k += dot(nj - ni, e) / dot(e, e);
    }
    return (dot(n, ng) < 0.0 ? -k : k) / 3.0;
}

#endif
