// Option values the commands share, parsed and checked once here.
#pragma once

#include <string>

#include "render/render_settings.h"
#include "scene/scene.h"
#include "vk/context.h"  // validationFromEnvironment, which the commands use with these

namespace whitted {

// --region "X0,Y0,X1,Y1": four integers, nothing else. Throws
// std::invalid_argument "expected X0,Y0,X1,Y1 (four integers), got '...'".
// Whether the region lies in the image is the renderer's check (it knows
// the image's size).
PixelRegion parsePixelRegion(const std::string& text);

// The scene's warnings on stderr, a "warning: " line each; with `verbose`,
// then the lines they sum up (Scene::warningDetails), indented.
void printSceneWarnings(const Scene& scene, bool verbose);

}  // namespace whitted
