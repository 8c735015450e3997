// Image textures (scenes/README.md "Textures"): texture coordinates of any primitive,
// the filter footprint by ray cones, and the texture lookups.
//
// Level of detail by ray cones ("Texture Level of Detail Strategies for
// Real-Time Ray Tracing", Akenine-Möller, Nilsson, Andersson, Barré-Brisebois,
// Toth and Karras, Ray Tracing Gems ch. 20, 2019): every ray carries a cone,
// a width w and a spread angle gamma, starting at the eye with w = 0 and
// gamma = the angle of one pixel; at a hit at distance t the footprint is
// w + gamma t wide, and the mip level is
//     lambda = log2(w) + 1/2 log2(texels per world area) - log2|n . d|,
// the chapter's Delta_0 + log2|W| - log2|n.d| with Delta_0 written for any
// mapping through |dp/du x dp/dv| instead of a triangle's area ratio.
// Reflected and refracted rays continue the cone, widened or narrowed by the
// surface's curvature (shaders/whitted.comp). Ray cones rather than ray
// differentials (Igehy 1999): one width and one angle per pending ray in the
// explicit ray stack (2 floats instead of 12), no per-shape derivative
// transport, no screen-space differences (so no seams at a mapping's
// discontinuities, a sphere's longitude wrap included), at the price of an
// isotropic footprint that over-blurs at grazing angles.
#ifndef WHITTED_TEXTURE_GLSL
#define WHITTED_TEXTURE_GLSL
#extension GL_EXT_nonuniform_qualifier : require
#include "material.glsl"
#include "scene.glsl"
#include "shapes/primitive.glsl"

layout(set = 0, binding = kBindingTextures) uniform sampler2D textures[kMaxTextures];
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer SurfaceAttributesArray {
    SurfaceAttributes v[];
};
#define surfaceAttributes (SurfaceAttributesArray(params.attributeAddress).v)

// Primitive i's attributes, member by member (why: shaders/scene.glsl, loadMaterial).
SurfaceAttributes surfaceAttributesAt(uint i) {
    return SurfaceAttributes(surfaceAttributes[i].uv0, surfaceAttributes[i].uv1, surfaceAttributes[i].uv2,
                             vec2(0.0), surfaceAttributes[i].tangents, surfaceAttributes[i].hasTangents);
}

// Texture coordinates of primitive `index` at its point p; n is the shape's
// geometric normal there (as the intersection gave it), which tells a
// box's faces and a cylinder's caps apart. textureScale: the material's
// (planes only).
SurfaceUv surfaceUv(Primitive prim, uint index, vec3 n, vec3 p, float textureScale) {
    switch (prim.shape) {
        case kShapeSphere: return sphereUv(sphereCenter(prim), sphereRadius(prim), p);
        case kShapeCylinder:
            return cylinderUv(cylinderBase(prim), cylinderAxis(prim), cylinderRadius(prim), cylinderHeight(prim), n, p);
        case kShapePlane: return planeUv(planePoint(prim), planeUnitNormal(prim), textureScale, p);
        case kShapeBox: return boxUv(boxMin(prim), boxMax(prim), n, p);
    }
    // A triangle of a textured mesh (the loader refuses textures on others).
    vec3 v0 = triangleV0(prim), v1 = triangleV1(prim), v2 = triangleV2(prim);
    if (all(equal(params.attributeAddress, uvec2(0u)))) return triangleUv(v0, v1, v2, vec2(0.0), vec2(0.0), vec2(0.0), p);
    SurfaceAttributes at = surfaceAttributesAt(index);
    SurfaceUv s = triangleUv(v0, v1, v2, at.uv0, at.uv1, at.uv2, p);
    // A model file's vertex tangents, interpolated as vertex normals are.
    if (at.hasTangents != 0u) s.tangent = shadingNormalTriangle(v0, v1, v2, at.tangents, p);
    return s;
}

// Mip level of texture `slot` for a cone `coneWidth` wide where it meets
// the surface at cosine `cosine` (see the top of this file).
float rayConeLod(uint slot, SurfaceUv s, float coneWidth, float cosine) {
    if ((params.options & kOptionTextureLodZero) != 0u) return 0.0;
    vec2 size = vec2(textureSize(textures[nonuniformEXT(slot)], 0));
    float worldArea = max(length(cross(s.dpdu, s.dpdv)), 1e-30);  // of one unit square of texture
    return log2(max(abs(coneWidth), 1e-30)) + 0.5 * log2(size.x * size.y / worldArea) - log2(max(cosine, 1e-6));
}

// The texture's linear RGB at uv (v up: the image's first row is v = 1).
vec3 textureColor(uint slot, vec2 uv, float lod) {
    return textureLod(textures[nonuniformEXT(slot)], vec2(uv.x, 1.0 - uv.y), lod).rgb;
}

// The colour Cd a shadow ray's crossing of primitive i (material k) at p,
// geometric normal n, filters by (POV-Ray's filter): the pigment times the
// diffuse texture, at mip level 0 (a shadow ray carries no cone).
vec3 crossingColour(uint i, uint k, vec3 p, vec3 n) {
    vec3 cd = pigment(materials[k].diffuse, materials[k].checkerColor, materials[k].checkerSize, materials[k].checkerOrigin, p);
#ifndef WHITTED_NO_TEXTURES  // the build for scenes without textures (host/render/device_policy.cpp)
    uint slot = materials[k].diffuseTexture;
    if (slot != kNoTexture)
        cd *= textureColor(slot, surfaceUv(primitives[i], i, n, p, materials[k].textureScale).uv, 0.0);
#endif
    return cd;
}

// Normal mapping: the map's texel m = 2 rgb - 1 is a normal in tangent
// space, OpenGL's convention (x along +u, y along +v: green up, z along the
// surface normal), its x and y scaled by `strength`. The tangent frame is the
// mapping's: T = dp/du made perpendicular to the shading normal ns
// (Gram-Schmidt), B = ns x T turned to dp/dv's side, N = ns. A model file's
// mesh uses its vertex tangents instead of dp/du (Assimp's
// aiProcess_CalcTangentSpace, interpolated across the triangle, as
// MikkTSpace's per-vertex tangents are), orthogonalised the same way; inline
// polygons use their triangle's dp/du. ns faces the viewer, so a map reads
// the same from either side.
vec3 normalMapped(uint slot, float strength, SurfaceUv s, vec3 ns, float lod) {
    vec3 m = textureLod(textures[nonuniformEXT(slot)], vec2(s.uv.x, 1.0 - s.uv.y), lod).rgb * 2.0 - 1.0;
    m.xy *= strength;
    vec3 along = dot(s.tangent, s.tangent) > 0.0 ? s.tangent : s.dpdu;
    vec3 t = along - dot(along, ns) * ns;
    if (dot(t, t) < 1e-20) return ns;
    t = normalize(t);
    vec3 b = cross(ns, t);
    if (dot(b, s.dpdv) < 0.0) b = -b;
    vec3 mapped = m.x * t + m.y * b + m.z * ns;
    float length2 = dot(mapped, mapped);
    return length2 > 1e-20 ? mapped * inversesqrt(length2) : ns;
}

// Signed curvature of primitive `prim` at p where its geometric normal is n,
// positive where the surface is convex towards n (the outside of spheres
// and cylinders): each shape's own function (shaders/shapes/), 0 on flat
// shapes (planes, boxes, flat triangles).
float surfaceCurvature(Primitive prim, vec3 n, vec3 p) {
    switch (prim.shape) {
        case kShapeSphere: return sphereCurvature(sphereCenter(prim), sphereRadius(prim), n, p);
        case kShapeCylinder: return cylinderCurvature(cylinderBase(prim), cylinderAxis(prim), cylinderRadius(prim), n, p);
        case kShapeTriangle: {
            if (!kHasSmoothTriangles || !triangleSmooth(prim)) return 0.0;
            return triangleCurvature(triangleV0(prim), triangleV1(prim), triangleV2(prim), triangleNormals(prim), n);
        }
    }
    return 0.0;
}

#endif
