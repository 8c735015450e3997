// Edits and questions about a shape that do not depend on where they come
// from: the window's editor panel (view/editor_panel.h) and the Python
// module (python/scene_api.cpp) both move shapes and anchor checkers
// through these.
#pragma once

#include "scene/scene.h"

namespace whitted {

// Moves a shape by `delta` (every point of it).
void translateShape(Shape& shape, const glm::dvec3& delta);
// The point the panel shows as an object's position (sphere centre,
// cylinder base, plane point, box min corner, first vertex otherwise).
glm::dvec3 shapeReferencePoint(const Shape& shape);

// Where a checker switched on starts its cells: where the loader anchors
// them, the object's <position> (a model file's placement, the reference
// point of every other shape), so the saved file reloads it.
glm::dvec3 checkerAnchor(const Shape& shape);

// "sphere", "cylinder", "plane", "triangle", "box", "mesh" or "csg".
const char* shapeName(const Shape& shape);

}  // namespace whitted
