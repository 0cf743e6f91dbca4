// Generated vertex tangents (renderer/scene/gltf_tangents.h) for normal-mapped glTF meshes
// without TANGENT: on a smooth cylinder patch they are unit, orthogonal to the vertex normals,
// follow the direction u grows in, with the handedness the renderer's per-triangle fallback
// gives (bitangent toward decreasing v), flip with a mirrored u, and are one per vertex, so
// adjacent triangles share them (the fallback's frame jumped at every edge).
#include <gtest/gtest.h>

#include <cmath>

#include "renderer/scene/gltf_tangents.h"

namespace tex::render {
namespace {

// A quarter cylinder of radius 1 around y: `columns` x `rows` quads, shared vertices, smooth
// normals, u along the arc (or against it), v along y (downward in glTF's image convention).
MeshPrimitive cylinderPatch(int columns, int rows, bool mirrorU) {
  MeshPrimitive m;
  for (int r = 0; r <= rows; ++r)
    for (int c = 0; c <= columns; ++c) {
      const float phi = 0.5f * float(M_PI) * float(c) / float(columns);
      const Vec3 n(std::cos(phi), 0.0f, std::sin(phi));
      m.positions.push_back(n + Vec3(0.0f, float(r) / float(rows), 0.0f));
      m.normals.push_back(n);
      const float u = float(c) / float(columns);
      m.uv0.push_back(Vec2(mirrorU ? 1.0f - u : u, 1.0f - float(r) / float(rows)));
    }
  const auto at = [&](int r, int c) { return uint32_t(r * (columns + 1) + c); };
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < columns; ++c)
      m.indices.insert(m.indices.end(), {at(r, c), at(r, c + 1), at(r + 1, c + 1), at(r, c), at(r + 1, c + 1), at(r + 1, c)});
  return m;
}

TEST(GltfTangents, SmoothFollowUAndHaveTheFallbacksHandedness) {
  for (const bool mirror : {false, true}) {
    const MeshPrimitive m = cylinderPatch(12, 3, mirror);
    const std::vector<Vec4> tangents = generateTangents(m, m.uv0);
    ASSERT_EQ(tangents.size(), m.positions.size());
    for (size_t v = 0; v < tangents.size(); ++v) {
      const Vec3 t(tangents[v]);
      EXPECT_NEAR(glm::length(t), 1.0f, 1e-5f) << v;
      EXPECT_NEAR(glm::dot(t, m.normals[v]), 0.0f, 1e-5f) << v;
      // The arc direction at this vertex: d/dphi of (cos, 0, sin) = (-sin, 0, cos).
      const Vec3 arc(-m.normals[v].z, 0.0f, m.normals[v].x);
      EXPECT_NEAR(glm::dot(t, arc), mirror ? -1.0f : 1.0f, 1e-4f) << v;
      // The fallback's rule: cross(n, t) * w points toward decreasing v, which is +y here.
      const Vec3 bitangent = glm::cross(m.normals[v], t) * tangents[v].w;
      EXPECT_NEAR(bitangent.y, 1.0f, 1e-4f) << v;
    }
  }
}

TEST(GltfTangents, DegenerateUvGivesSomeOrthogonalUnitTangent) {
  MeshPrimitive m = cylinderPatch(2, 1, false);
  std::vector<Vec2> flat(m.positions.size(), Vec2(0.5f));
  const std::vector<Vec4> tangents = generateTangents(m, flat);
  for (size_t v = 0; v < tangents.size(); ++v) {
    EXPECT_NEAR(glm::length(Vec3(tangents[v])), 1.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(Vec3(tangents[v]), m.normals[v]), 0.0f, 1e-5f);
    EXPECT_TRUE(tangents[v].w == 1.0f || tangents[v].w == -1.0f);
  }
}

}  // namespace
}  // namespace tex::render
