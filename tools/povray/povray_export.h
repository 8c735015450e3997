// Writes a scene as POV-Ray 3.7 scene description language (SDL), for an
// independent cross-check of the renderer against POV-Ray (see tests/README.md
// "Cross-check against POV-Ray" and tests/povray_test.cpp).
//
// What maps exactly (POV-Ray 3.7 source: backend/render/trace.cpp,
// ComputeLightedTexture / ComputeDiffuseColour / ComputePhongColour):
//   ka·Cd·A            finish ambient ka, global ambient_light A
//   kd·Cd·max(N·L,0)   finish diffuse kd (brilliance 1, no albedo, crand 0)
//   ks·max(R·V,0)^n    finish phong ks phong_size n: POV-Ray's highlight has
//                      the LIGHT's colour, so ks·Cs·light is exact only when
//                      Cs is grey (phong ks·Cs); otherwise ks·mean(Cs)
//   kr·Cs·reflected    finish reflection { rgb kr·Cs } (min = max, no
//                      fresnel, falloff 1, exponent 1, not metallic)
//   point lights       light_source without fade: no falloff, like ours
//   inverse square     fade_distance D fade_power 2, colour c/(2 D^2): POV-Ray
//                      gives c/(2 D^2)·2/(1 + (d/D)^2) = c/(D^2 + d^2), with
//                      D = 1e-4 within a relative 1e-8/d^2 of c/d^2
//   directional        parallel, located 1e7 back along the direction (past
//                      every finite object, so all of them cast shadows)
//   spot               POV-Ray's spotlight ramps by a smoothstep 3s^2 - 2s^3
//                      between its falloff and radius cosines, not by our s^2;
//                      exported as 16 spotlights at the same place whose
//                      ramps tile [cos outer, cos inner] (tightness 0), each
//                      weighted by the rise of s^2 over its ramp: within
//                      0.0123 of the light's full strength everywhere, exact
//                      inside the inner cone and outside the outer one
//   area lights        area_light: POV-Ray splits the colour over its grid
//                      of point lights, so the total is one point light's,
//                      as ours (scenes/README.md "Area lights"); a grid of
//                      ceil(sqrt(N))^2 jittered points for <shadow_samples>
//                      N, area_illumination on (each point's own direction,
//                      as ours). A sphere light: the disc of its radius
//                      facing the shaded point (circular orient), where ours
//                      samples the sphere's cone of directions: the same
//                      within (R/d)^2. A rect light: axes u and v; POV-Ray's
//                      shines from both faces, so a one-sided one matches
//                      only where it is seen from the front (a place
//                      povrayInexactMappings names when the scene has one)
//   recursion          max_trace_level D+1 (POV-Ray counts the camera ray
//                      as level 1; we count secondary bounces), adc_bailout 0
//   shadows of glass   pigment { rgbft <Cd, kt·kd, kt·(1-kd)> }: POV-Ray
//                      filters a shadow ray at each surface crossing by
//                      filter·Cd + transmit = kt·mix(white, Cd, kd), as ours
//   thin lens          focal_blur: aperture 4·radius (POV-Ray offsets the eye
//                      by aperture/2 times a point of a disc of radius 1/2,
//                      tracepixel.cpp JitterCameraRay), focal_point on the
//                      view axis at the focus distance (POV-Ray focuses on
//                      the plane at |focal_point - location| along the axis),
//                      blur_samples PovrayExportOptions::blurSamples, all of
//                      them traced (variance 0)
//   environment        what rays that leave the scene see: a colour as
//                      background, a gradient as a sky_sphere pigment
//                      function { y * 0.5 + 0.5 } with the ground, horizon
//                      and zenith colours at 0, 0.5 and 1, an image as a
//                      sky_sphere image_map (map_type 1, rotate y by the
//                      rotation - 90 degrees: its centre along -z). Not its
//                      light (POV-Ray's sky lights nothing without
//                      radiosity), nor <visible>false</visible>, nor an
//                      image's intensity: povrayInexactMappings names them
// What does not: glossy reflection and refraction (roughness): POV-Ray's
// reflection and refraction are always sharp (its blurred reflection needs
// a micro-normal pattern and averaged textures); exported as the mirror.
// What does not: the look of a transparent surface (POV-Ray scales its local
// terms by the pigment's opacity and filters refracted light by the pigment,
// where we weight it by kt alone); exported approximately, with
// interior { ior }. povrayInexactMappings() lists every such place in a
// scene.
#pragma once

#include "scene/scene.h"

#include <string>
#include <vector>

namespace whitted {

struct PovrayExportOptions {
    int width = 0;     // pixels; 0: the scene camera's
    int height = 0;
    int maxDepth = 6;  // secondary bounces, as RenderSettings::maxDepth
    bool shadows = true;  // false: every object gets no_shadow (a control for tests)
    int blurSamples = 64;  // focal blur rays per pixel (a camera with a lens)
};

// POV-Ray SDL for the whole scene. The coordinates are kept as they are
// (POV-Ray is left-handed, we are right-handed): the camera is written with
// explicit direction/right/up vectors computed from our camera frame, which
// POV-Ray uses verbatim, so every pixel gets the same ray as in our
// renderer and the image is not mirrored.
std::string exportPovray(const Scene& scene, const PovrayExportOptions& options);

// One line per object whose material POV-Ray cannot reproduce exactly
// ("FILE:LINE: what"); empty when the export is exact.
std::vector<std::string> povrayInexactMappings(const Scene& scene);

}  // namespace whitted
