// Edits and questions about a shape that do not depend on where they come
// from: the window's editor panel (view/editor_panel.h) and the Python
// module (python/object_api.cpp) both move shapes and anchor checkers
// through these.
#pragma once

#include "scene/scene.h"

namespace whitted {

// Moves a shape by `delta` (every point of it).
void translateShape(Shape& shape, const glm::dvec3& delta);
// Moves a shape by the affine map `m` (every point p to m·(p, 1)): a
// triangle's or inline mesh's vertices (normals through m's inverse
// transpose, tangents through m, the winding turned over where m mirrors),
// a plane's point and normal, a sphere's centre and a cylinder's base and
// axis where m's 3x3 part is a rotation times a uniform scale s (the radius,
// and a cylinder's height, times s), a box's corners where that part is
// diagonal and positive. Anything else (a sphere scaled unevenly, a turned
// box, a mesh read from a model file, csg) throws std::invalid_argument
// saying why; the shape is then unchanged.
void transformShape(Shape& shape, const glm::dmat4& m);

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
