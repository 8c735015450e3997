// Colour as a display shows it: clamped to [0, 1] and sRGB-encoded
// (IEC 61966-2-1), as io/image_io.cpp writes PNG files. The live window
// shows it (display.comp) and adaptive anti-aliasing compares colours there
// (whitted.comp), since differences in it are what a viewer sees.
#ifndef WHITTED_COLOR_GLSL
#define WHITTED_COLOR_GLSL

vec3 linearToSrgb(vec3 c) {
    c = clamp(c, 0.0, 1.0);
    return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, greaterThan(c, vec3(0.0031308)));
}

#endif
