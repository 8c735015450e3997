#ifndef WHITTED_CSG_GLSL
#define WHITTED_CSG_GLSL
#include "../scene.glsl"
#include "sphere.glsl"
#include "cylinder.glsl"
#include "box.glsl"

// Leaf primitive i of a csg object (a sphere, cylinder or box): the first
// crossing of its surface after tMin, by the shape's own function.
bool intersectCsgLeaf(uint i, Ray ray, float tMin, inout float tHit, out vec3 normal) {
    Primitive p = primitives[i];
    if (p.shape == kShapeSphere) return intersectSphere(sphereCenter(p), sphereRadius(p), ray, tMin, tHit, normal);
    if (p.shape == kShapeCylinder)
        return intersectCylinder(cylinderBase(p), cylinderAxis(p), cylinderRadius(p), cylinderHeight(p), ray, tMin,
                                 tHit, normal);
    return intersectBox(boxMin(p), boxMax(p), ray, tMin, tHit, normal);
}

// Whether a point inside exactly the leaves of the bit set `inside` is in
// the solid: the object's postfix program (device_types.h) run on a stack of
// one bit per entry, at most kCsgStackSize deep (the loader's depth limit).
bool csgContains(uint firstNode, uint nodeCount, uint inside) {
    uint stack = 0u;
    int top = 0;
    for (uint k = 0u; k < nodeCount; ++k) {
        uvec2 node = uvec2(csgNodes[firstNode + k].op, csgNodes[firstNode + k].leaf);
        if (node.x == kCsgLeaf) {
            stack = bitfieldInsert(stack, (inside >> node.y) & 1u, top, 1);
            ++top;
        } else {
            --top;
            bool b = ((stack >> top) & 1u) != 0u;
            bool a = ((stack >> (top - 1)) & 1u) != 0u;
            bool r = node.x == kCsgUnion ? (a || b) : (node.x == kCsgIntersection ? (a && b) : (a && !b));
            stack = bitfieldInsert(stack, r ? 1u : 0u, top - 1, 1);
        }
    }
    return (stack & 1u) != 0u;
}

// Ray/CSG object by ray classification (Roth, "Ray Casting for Modeling
// Solids", Computer Graphics and Image Processing 18(2), 1982): each leaf, a
// convex solid, classifies the ray into one span inside it, [tIn, tOut]
// (its entry by the shape's function from t = -inf, its exit as the entry
// of the reversed ray). Roth combines the span lists of the children at
// every node of the tree; here the leaves' span ends are merged along the
// ray once instead, and each stretch between two consecutive ends is
// classified by evaluating the tree's boolean function (Roth's combine
// rules: union = or, intersection = and, difference = and not) on the set
// of leaves it lies inside. The first end after tMin where the
// classification changes is where the ray crosses the object's surface.
// Only fixed-size state: kCsgMaxLeaves spans, 32-bit leaf sets and the
// bit stack of csgContains.
//
// Primitive i is the csg object. Updates tHit and returns true at a
// crossing in (tMin, tHit); leaf is then the leaf primitive struck (its
// material and UVs serve shading) and normal is the object's outward normal
// there: the leaf's outward normal, turned round on a surface that bounds
// a subtracted child (it faces into the removed volume).
bool intersectCsg(uint i, Ray ray, float tMin, inout float tHit, out vec3 normal, out uint leaf) {
    normal = vec3(0.0);
    leaf = i;
    Primitive object = primitives[i];
    uvec2 program = csgProgram(object);
    // The object's bounds first: most rays that reach here miss it.
    vec3 d = mix(ray.dir, vec3(1e-30), lessThan(abs(ray.dir), vec3(1e-30)));
    vec3 t0 = (csgBoundsMin(object) - ray.origin) / d, t1 = (csgBoundsMax(object) - ray.origin) / d;
    vec3 tNear = min(t0, t1), tFar = max(t0, t1);
    if (max(max(tNear.x, tNear.y), tNear.z) > min(min(tFar.x, tFar.y), min(tFar.z, tHit)) ||
        min(min(tFar.x, tFar.y), tFar.z) <= tMin)
        return false;

    const float kFar = 3.0e38;
    uint firstLeaf = csgLeaves(object).x, leafCount = csgLeaves(object).y;
    Ray back = Ray(ray.origin, -ray.dir);
    float tIn[kCsgMaxLeaves], tOut[kCsgMaxLeaves];
    uint inside = 0u;  // the leaves the ray is inside just after tMin
    for (uint j = 0u; j < leafCount; ++j) {
        float enter = kFar, exit = kFar;
        vec3 n;
        tIn[j] = kFar;
        tOut[j] = kFar;
        if (intersectCsgLeaf(firstLeaf + j, ray, -kFar, enter, n) &&
            intersectCsgLeaf(firstLeaf + j, back, -kFar, exit, n)) {
            tIn[j] = enter;
            tOut[j] = -exit;
        }
        if (tIn[j] <= tMin && tMin < tOut[j]) inside |= 1u << j;
    }
    bool solid = csgContains(program.x, program.y, inside);

    float t = tMin;
    for (uint step = 0u; step < 2u * kCsgMaxLeaves; ++step) {
        // The next span end after t (the first leaf's when several coincide).
        float tNext = kFar;
        uint next = 0u;
        for (uint j = 0u; j < leafCount; ++j) {
            if (tIn[j] > t && tIn[j] < tNext) {
                tNext = tIn[j];
                next = j;
            }
            if (tOut[j] > t && tOut[j] < tNext) {
                tNext = tOut[j];
                next = j;
            }
        }
        if (!(tNext < tHit)) return false;
        inside = 0u;
        for (uint j = 0u; j < leafCount; ++j)
            if (tIn[j] <= tNext && tNext < tOut[j]) inside |= 1u << j;
        bool solidNext = csgContains(program.x, program.y, inside);
        if (solidNext != solid) {
            // The struck leaf's outward normal at that end, from the same
            // call that found it; entering the solid it faces the ray.
            float tLeaf = kFar;
            vec3 n = vec3(0.0);
            if (tIn[next] == tNext) intersectCsgLeaf(firstLeaf + next, ray, -kFar, tLeaf, n);
            else intersectCsgLeaf(firstLeaf + next, back, -kFar, tLeaf, n);
            normal = (dot(n, ray.dir) < 0.0) == solidNext ? n : -n;
            tHit = tNext;
            leaf = firstLeaf + next;
            return true;
        }
        t = tNext;
    }
    return false;
}

#endif
