// Instances (scenes/README.md "Instances"; host/render/gpu_instances.h): a
// prototype's primitives are stored once, in object space, under a tree of
// their own, and each instance is a stand-in primitive (kShapeInstance) in
// the scene's BVH with its affine transforms (InstanceRecord). This is the
// two-level BVH of Wald, Boulos and Shirley ("Ray Tracing Deformable Scenes
// Using Dynamic Bounding Volume Hierarchies", ACM TOG 2007), and the bottom
// and top levels of DXR and Vulkan ray tracing: the walk (bvh.glsl) that
// reaches a stand-in carries the ray into object space and goes on in the
// prototype's tree; when it pops back below where it entered, the world ray
// returns. The object-space ray is not normalised, so a hit's t is the same
// number in both spaces and the walk's interval and stacked entry distances
// need no conversion. The prototype's boxes and triangles are tested against
// that one object-space ray, so the conservative box test (bvh.glsl) and
// the watertight triangle test (shapes/triangle.glsl) hold in object space
// exactly as they hold in world space for a flattened copy: neighbouring
// triangles share their object-space vertices bit for bit.
//
// Shading sees a hit on an instance as a flattened copy would give it: the
// normal through the inverse transpose (which keeps a closed mesh's outside
// out under a mirroring transform), and hitPrimitive's triangle in world
// space with the instance's material and object id.
#ifndef WHITTED_INSTANCE_GLSL
#define WHITTED_INSTANCE_GLSL
#include "scene.glsl"
#include "ray.glsl"
#include "shapes/triangle.glsl"

layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer InstanceArray { InstanceRecord v[]; };
#define instanceRecords (InstanceArray(params.instanceAddress).v)

// Whether the scene has instances: their stand-ins' bit in the BVH's shape
// mask (a specialization constant, intersect.glsl), so that a scene without
// compiles none of this.
const bool kSceneHasInstances = (kShapeMask & (1u << kShapeInstance)) != 0u;

// The instance whose prototype the BVH walk is in (kNoInstance: the
// world's level), for the material a shadow ray's crossing filters with.
uint gWalkInstance = kNoInstance;

// The ray in instance k's object space (origin and direction through
// objectFromWorld; the direction keeps its length).
Ray objectRay(uint k, Ray ray) {
    vec4 r0 = instanceRecords[k].objectFromWorld0, r1 = instanceRecords[k].objectFromWorld1,
         r2 = instanceRecords[k].objectFromWorld2;
    return Ray(vec3(dot(r0.xyz, ray.origin) + r0.w, dot(r1.xyz, ray.origin) + r1.w, dot(r2.xyz, ray.origin) + r2.w),
               vec3(dot(r0.xyz, ray.dir), dot(r1.xyz, ray.dir), dot(r2.xyz, ray.dir)));
}

// An object-space point and direction of instance k in world space.
vec3 instancePoint(uint k, vec3 p) {
    vec4 r0 = instanceRecords[k].worldFromObject0, r1 = instanceRecords[k].worldFromObject1,
         r2 = instanceRecords[k].worldFromObject2;
    return vec3(dot(r0.xyz, p) + r0.w, dot(r1.xyz, p) + r1.w, dot(r2.xyz, p) + r2.w);
}
vec3 instanceVector(uint k, vec3 v) {
    return vec3(dot(instanceRecords[k].worldFromObject0.xyz, v), dot(instanceRecords[k].worldFromObject1.xyz, v),
                dot(instanceRecords[k].worldFromObject2.xyz, v));
}

// An object-space normal of instance k in world space, unit: through the
// inverse transpose of the linear part, the transpose of objectFromWorld's.
vec3 instanceNormal(uint k, vec3 n) {
    return normalize(instanceRecords[k].objectFromWorld0.xyz * n.x + instanceRecords[k].objectFromWorld1.xyz * n.y +
                     instanceRecords[k].objectFromWorld2.xyz * n.z);
}

// The material primitive i is shaded with in instance k (kNoInstance: none).
uint instanceMaterial(uint k, uint i) {
    if (!kSceneHasInstances || k == kNoInstance) return primitives[i].material;
    uint own = instanceRecords[k].material;
    return own != kNoMaterialOverride ? own : primitives[i].material;
}

// The BVH walk (bvh.glsl) reaches instance stand-in `prim`, alone in its
// leaf: the ray goes into the instance's object space (the world ray kept in
// worldRay) and the walk on at its prototype's root, which this returns.
uint enterInstance(uint prim, inout Ray ray, out Ray worldRay) {
    gWalkInstance = primitiveInstance(primitives[prim]);
    worldRay = ray;
    ray = objectRay(gWalkInstance, ray);
    return instanceRecords[gWalkInstance].rootNode;
}

// The walk pops back below where it entered the instance: the world ray again.
Ray leaveInstance(Ray worldRay) {
    gWalkInstance = kNoInstance;
    return worldRay;
}

// encodeOctahedral() of host/shapes/triangle.cpp (decodeOctahedral's inverse).
uint encodeOctahedral(vec3 n) {
    vec3 p = n / (abs(n.x) + abs(n.y) + abs(n.z));
    vec2 e = p.z < 0.0 ? (1.0 - abs(p.yx)) * mix(vec2(-1.0), vec2(1.0), greaterThanEqual(p.xy, vec2(0.0))) : p.xy;
    const float kMax = float((1u << kOctahedralBits) - 1u);
    uvec2 q = uvec2(round((clamp(e, -1.0, 1.0) * 0.5 + 0.5) * kMax));
    return q.x | (q.y << kOctahedralBits);
}

// The primitive a closest hit is shaded with: primitives[hit.primitive], or
// on an instance the prototype's triangle in world space (its vertices and
// vertex normals transformed), with the instance's material and object id.
Primitive hitPrimitive(Hit hit) {
    Primitive p = primitives[hit.primitive];
    if (!kSceneHasInstances || hit.instance == kNoInstance) return p;
    uint k = hit.instance;
    p.a.xyz = instancePoint(k, p.a.xyz);
    p.b.xyz = instancePoint(k, p.b.xyz);
    p.c.xyz = instancePoint(k, p.c.xyz);
    if (triangleSmooth(p)) {
        uvec3 normals = triangleNormals(p);
        p.a.w = uintBitsToFloat(encodeOctahedral(instanceNormal(k, decodeOctahedral(normals.x))));
        p.b.w = uintBitsToFloat(encodeOctahedral(instanceNormal(k, decodeOctahedral(normals.y))));
        p.c.w = uintBitsToFloat(encodeOctahedral(instanceNormal(k, decodeOctahedral(normals.z))));
    }
    p.material = instanceMaterial(k, hit.primitive);
    p.extra1 = instanceRecords[k].object;
    return p;
}

#endif
