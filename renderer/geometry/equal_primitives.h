// Primitives whose triangles are the same data. glTF files give meshes that differ only in
// material their own primitives over the same accessors (MetalRoughSpheresNoTextures: 98
// spheres of 10.6 k triangles, one accessor set); SceneGeometry builds such triangles once and
// instances them, as it does for a primitive that several nodes use.
#pragma once
#include <vector>

#include "renderer/scene/scene_description.h"

namespace tex::render {

// For each primitive, the first primitive with equal vertex attributes (positions, normals,
// both uv sets, tangents, colours) and indices; itself when there is none. `eligible[p]` false keeps
// p to itself (a cut-out material's alpha test belongs to its own geometry).
std::vector<int> firstEqualPrimitive(const SceneDescription& scene, const std::vector<bool>& eligible);

}  // namespace tex::render
