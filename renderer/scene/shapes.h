// Inline geometry for scene JSON files: a UV sphere with smooth normals, a quad and a box, as
// MeshPrimitives in object space (transforms go on the instance).
#pragma once
#include "renderer/scene/scene_description.h"

namespace tex::render {

// UV sphere: `segments` around the y axis, `rings` from pole to pole (pole rows are fans, so
// there are 2 * segments * (rings - 1) triangles). Normals point out, or in when `inward`.
MeshPrimitive makeSphere(const Vec3& center, float radius, int segments, int rings, bool inward);

// Quad spanning corner + s * edge1 + t * edge2 for s, t in [0,1]; normal along edge1 x edge2.
MeshPrimitive makeQuad(const Vec3& corner, const Vec3& edge1, const Vec3& edge2);

// Axis-aligned box of the given size around `center`: 12 triangles, 24 vertices with face
// normals pointing out (or in when `inward`).
MeshPrimitive makeBox(const Vec3& center, const Vec3& size, bool inward);

}  // namespace tex::render
