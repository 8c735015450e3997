#ifndef WHITTED_SPHERE_GLSL
#define WHITTED_SPHERE_GLSL
#include "../ray.glsl"

// Ray/sphere with the cancellation-free discriminant r^2 - |f - (f.d)d|^2 and
// the stable root pair q, c/q: "Precision Improvements for Ray/Sphere
// Intersection", Haines et al., Ray Tracing Gems ch. 7 (2019).
// Updates tHit/normal and returns true if a root lies in (tMin, tHit).
bool intersectSphere(vec3 center, float radius, Ray ray, float tMin, inout float tHit, out vec3 normal) {
    vec3 f = ray.origin - center;
    float b = dot(f, ray.dir);
    vec3 l = f - b * ray.dir;
    float disc = radius * radius - dot(l, l);
    if (disc < 0.0) return false;
    float c = dot(f, f) - radius * radius;
    float q = -(b + (b >= 0.0 ? 1.0 : -1.0) * sqrt(disc));
    float t0 = c / q;
    float t1 = q;
    if (t0 > t1) { float s = t0; t0 = t1; t1 = s; }
    float t = t0 > tMin ? t0 : t1;
    if (!(t > tMin && t < tHit)) return false;
    tHit = t;
    normal = (ray.origin + t * ray.dir - center) / radius;
    return true;
}

// Longitude/latitude mapping, POV-Ray's spherical map (map_type 1): u the
// angle about +y from +x towards +z over 2 pi, v = 1/2 + latitude / pi (0 at
// the -y pole, 1 at the +y pole). The seam is the half plane z = 0, x > 0.
SurfaceUv sphereUv(vec3 center, float radius, vec3 p) {
    vec3 d = (p - center) / radius;
    const float kPi = 3.14159265358979;
    float longitude = atan(d.z, d.x);
    float latitude = asin(clamp(d.y, -1.0, 1.0));
    float u = longitude / (2.0 * kPi);
    SurfaceUv s;
    s.tangent = vec3(0.0);
    s.uv = vec2(u < 0.0 ? u + 1.0 : u, 0.5 + latitude / kPi);
    float c = cos(latitude), sl = sin(latitude);
    s.dpdu = 2.0 * kPi * radius * c * vec3(-sin(longitude), 0.0, cos(longitude));
    s.dpdv = kPi * radius * vec3(-sl * cos(longitude), c, -sl * sin(longitude));
    return s;
}

// Signed curvature at p where the geometric normal is n: 1/r where n points
// away from the centre (convex towards n), -1/r where it points towards it
// (a sphere subtracted by CSG, whose surface faces into the removed volume).
float sphereCurvature(vec3 center, float radius, vec3 n, vec3 p) {
    return (dot(n, p - center) < 0.0 ? -1.0 : 1.0) / radius;
}

#endif
