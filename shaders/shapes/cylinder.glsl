#ifndef WHITTED_CYLINDER_GLSL
#define WHITTED_CYLINDER_GLSL
#include "../ray.glsl"

// Ray/capped cylinder of any axis. The side is the quadratic
// |op + t dp|^2 = r^2 in the plane perpendicular to the axis, with the
// discriminant written as a r^2 - |dp x op|^2 (Lagrange's identity) to avoid
// cancellation; a side root counts only between the caps, a cap root only
// inside the radius. Each candidate is tested on its own and the nearest wins,
// so a ray never takes a cap's plane for the cap (the seed's phantom-shadow
// bug) and the normal comes from the part that was hit, not guessed from the
// point afterwards. Where side and cap meet, the side's height test and the
// cap's radius test round differently, so a ray through the rim could fail
// both and slip into the cylinder (a crack along the rim): both tests are
// widened by a slack of a few float ulps of the numbers involved, so the
// parts overlap by that much instead (as watertight triangle tests make
// shared edges count for both triangles).
bool intersectCylinder(vec3 base, vec3 axis, float radius, float height, Ray ray, float tMin,
                       inout float tHit, out vec3 normal) {
    vec3 o = ray.origin - base;
    float oa = dot(o, axis);
    float da = dot(ray.dir, axis);
    vec3 op = o - oa * axis;
    vec3 dp = ray.dir - da * axis;
    float r2 = radius * radius;
    float slack = 1e-6 * (length(o) + radius + height);
    float capR2 = (radius + slack) * (radius + slack);
    bool found = false;

    // Side.
    float a = dot(dp, dp);
    if (a > 1e-12) {
        float b = dot(op, dp);
        vec3 cr = cross(dp, op);
        float disc = a * r2 - dot(cr, cr);
        if (disc >= 0.0) {
            float q = -(b + (b >= 0.0 ? 1.0 : -1.0) * sqrt(disc));
            float c = dot(op, op) - r2;
            float roots[2] = float[2](q / a, c / q);
            for (int i = 0; i < 2; ++i) {
                float t = roots[i];
                float h = oa + t * da;
                if (t > tMin && t < tHit && h >= -slack && h <= height + slack) {
                    tHit = t;
                    vec3 radial = op + t * dp;
                    normal = radial / radius;
                    found = true;
                }
            }
        }
    }

    // Caps: bottom at h = 0 (normal -axis), top at h = height (normal +axis).
    if (abs(da) > 1e-12) {
        for (int i = 0; i < 2; ++i) {
            float h = i == 0 ? 0.0 : height;
            float t = (h - oa) / da;
            vec3 radial = op + t * dp;
            if (t > tMin && t < tHit && dot(radial, radial) <= capR2) {
                tHit = t;
                normal = i == 0 ? -axis : axis;
                found = true;
            }
        }
    }
    return found;
}

// Side: u the angle about the axis over 2 pi (from planarTangent(axis)
// towards axis x planarTangent(axis): from +x towards +z for a y axis), v the
// height over the cylinder's height. Caps (told apart by the geometric
// normal n): the cap's disc fills the unit square, u along planarTangent
// and v along axis x planarTangent(axis) on the top cap (for a y axis: u +x,
// v -z), u mirrored on the bottom one, so both read unmirrored from outside.
SurfaceUv cylinderUv(vec3 base, vec3 axis, float radius, float height, vec3 n, vec3 p) {
    const float kPi = 3.14159265358979;
    vec3 e1 = planarTangent(axis);
    vec3 e2 = cross(axis, e1);
    vec3 o = p - base;
    float h = dot(o, axis);
    vec3 r = o - h * axis;
    SurfaceUv s;
    s.tangent = vec3(0.0);
    float capSide = dot(n, axis);
    if (abs(capSide) > 0.5) {
        float mirror = capSide > 0.0 ? 1.0 : -1.0;
        s.uv = vec2(0.5 + mirror * dot(r, e1) / (2.0 * radius), 0.5 + dot(r, e2) / (2.0 * radius));
        s.dpdu = mirror * 2.0 * radius * e1;
        s.dpdv = 2.0 * radius * e2;
        return s;
    }
    float angle = atan(dot(r, -e2), dot(r, e1));
    float u = angle / (2.0 * kPi);
    s.uv = vec2(u < 0.0 ? u + 1.0 : u, h / height);
    s.dpdu = 2.0 * kPi * radius * (-sin(angle) * e1 - cos(angle) * e2);
    s.dpdv = height * axis;
    return s;
}

// Signed curvature at p where the geometric normal is n: +-1/r on the side,
// signed as on a sphere (negative where n points towards the axis), 0 on the
// caps (told apart by n).
float cylinderCurvature(vec3 base, vec3 axis, float radius, vec3 n, vec3 p) {
    if (abs(dot(n, axis)) > 0.5) return 0.0;  // a cap
    vec3 radial = p - base;
    radial -= dot(radial, axis) * axis;
    return (dot(n, radial) < 0.0 ? -1.0 : 1.0) / radius;
}

#endif
