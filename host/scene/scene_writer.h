// Writes the CPU scene model back as a scene file that scene_loader reads
// again to an equal Scene (up to the last bit of directions the loader
// renormalises and of box corners it re-adds). Every number is written with
// 17 significant digits so that doubles survive the text round trip.
#pragma once

#include <filesystem>
#include <string>

#include "scene/scene.h"

namespace whitted {

// The scene as XML text (this project's schema: the seed's elements plus
// the extensions of scenes/README.md "Scene files"). A mesh read from a model file is
// written as its <file> (with <scale> and <rotation>), the path relative to
// the folder of `destination`, the file the text is for (absolute without).
std::string sceneXml(const Scene& scene, const std::filesystem::path& destination = {});

// A number as the writer writes it: 17 significant digits (%.17g), which
// the loader reads back to the same double.
std::string xmlNumber(double v);
// Text with & < > " escaped, for an element's text or an attribute.
std::string escapedXml(const std::string& text);

// The <camera> element alone, indented by `indent` spaces.
std::string sceneCameraXml(const Camera& camera, int indent = 0);

// Textures without a file of their own (a .glb's images, base64 in a
// .gltf, a Python array's, one made on the host) have no path the scene file
// could name: each is written beside `output` (the scene file to be written)
// as OUT.LABEL.SLOT.png/.jpg/.exr, LABEL the object's name (its characters
// outside [A-Za-z0-9_-] as _) or objectK, SLOT diffuse_texture, normal_map
// or emission_texture, and its TextureRef::written set to that file (an
// absolute path), so that writeSceneFile names it. Encoded bytes are
// written as they are (the same texels decode again); a texture made on the
// host without them (an MTL height map turned into a normal map) as EXR,
// its full-resolution level as the half floats it holds (its coarser levels,
// built again from those, can then differ in the last bits). One file per
// texture however many objects use it. Throws std::runtime_error naming a
// file that cannot be written.
void writeFilelessTextures(Scene& scene, const std::filesystem::path& output);

// Writes sceneXml(scene) to `path` atomically (temporary file + rename).
void writeSceneFile(const Scene& scene, const std::filesystem::path& path);

}  // namespace whitted
