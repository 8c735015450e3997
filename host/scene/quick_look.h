// Quick looks: `whitted render MODEL.obj` and `whitted view MODEL.glb` give a
// model file where a scene file is expected. A scene is built in memory: the
// model as a mesh object with no colour of its own (as an XML mesh without
// <diffuse_color>), a camera framing it from a 3/4 view, a key and a fill
// light, and a floor just under it (scenes/README.md "Quick looks").
#pragma once

#include "scene/scene.h"

#include <filesystem>
#include <string>

namespace whitted {

// A path names a scene file when its extension is .xml (any case); any
// other is taken for a model file (the formats Assimp reads).
bool isSceneFile(const std::filesystem::path& path);

// Where a quick look's scene is written (the window's Ctrl+S): beside the
// model, its whole file name followed by .whitted.xml (bunny.obj ->
// bunny.obj.whitted.xml), so that it never overwrites the model and two
// models of one name in different formats do not share it.
std::filesystem::path quickLookScenePath(const std::filesystem::path& model);

// The quick-look scene of `model`; its sourcePath is quickLookScenePath.
// A model that cannot be used throws SceneError(model, 0, reason).
Scene quickLookScene(const std::filesystem::path& model);

// loadScene for a scene file; a glTF file, or an OBJ file with MTL
// materials, as authored (scene/authored_scene.h) with the quick look's
// camera only when the file has none and its lights and floor only when it
// has no lights; quickLookScene for any other model. `camera` is
// --camera INDEX|NAME (empty: the file's first camera); a choice that
// names no camera throws SceneError.
Scene loadSceneOrModel(const std::filesystem::path& path, const std::string& camera = "");

}  // namespace whitted
