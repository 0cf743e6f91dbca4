// Vertex tangents for normal-mapped glTF meshes that do not carry a TANGENT attribute. The
// spec asks for MikkTSpace; without it a hit's tangent was its triangle's uv direction, which
// jumps from triangle to triangle, so normal-mapped curved surfaces shaded as facets. These
// are per-vertex tangents in MikkTSpace's spirit (each corner's uv tangent, weighted by the
// corner's angle, made orthogonal to the vertex normal; handedness from the uv bitangent), not
// its exact vertex splitting: smooth across triangles, equal to it on meshes whose uv layout
// has no mirrored seams through shared vertices.
#pragma once
#include <vector>

#include "renderer/scene/scene_description.h"

namespace tex::render {

// One tangent per vertex of `prim` (xyz unit, orthogonal to the vertex normal; w = +-1, the
// bitangent being cross(normal, tangent) * w and pointing toward decreasing v, as the
// renderer reads glTF's TANGENT), from the texture
// coordinates `uv` (one per vertex). Needs normals; vertices of degenerate uv get any unit
// vector orthogonal to their normal.
std::vector<Vec4> generateTangents(const MeshPrimitive& prim, const std::vector<Vec2>& uv);

// Per-vertex normals as the area-weighted sum of the faces around each vertex (unit; +z where
// that vanishes): a frame to generate tangents in for meshes without NORMAL.
std::vector<Vec3> faceAveragedNormals(const MeshPrimitive& prim);

}  // namespace tex::render
