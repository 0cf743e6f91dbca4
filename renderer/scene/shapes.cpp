#include "renderer/scene/shapes.h"

#include <cmath>
#include <utility>

namespace tex::render {

namespace {

// Flips the winding and the normals of a mesh (for shapes seen from inside).
void turnInsideOut(MeshPrimitive& mesh) {
  for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) std::swap(mesh.indices[i + 1], mesh.indices[i + 2]);
  for (Vec3& n : mesh.normals) n = -n;
}

}  // namespace

MeshPrimitive makeSphere(const Vec3& center, float radius, int segments, int rings, bool inward) {
  MeshPrimitive mesh;
  // Vertex (ring r, segment s) for r in [0, rings], s in [0, segments]: the seam column is
  // duplicated so uv runs 0..1 without wrapping.
  const int columns = segments + 1;
  for (int r = 0; r <= rings; ++r) {
    const float v = float(r) / float(rings);
    const float theta = v * kPi;  // from +y (north pole) down
    for (int s = 0; s <= segments; ++s) {
      const float u = float(s) / float(segments);
      const float phi = u * 2.0f * kPi;
      const Vec3 n(std::sin(theta) * std::sin(phi), std::cos(theta), std::sin(theta) * std::cos(phi));
      mesh.positions.push_back(center + radius * n);
      mesh.normals.push_back(n);
      mesh.uv0.push_back(Vec2(u, v));
    }
  }
  auto vertex = [&](int r, int s) { return uint32_t(r * columns + s); };
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const uint32_t a = vertex(r, s), b = vertex(r + 1, s), c = vertex(r + 1, s + 1), d = vertex(r, s + 1);
      // Counter-clockwise seen from outside; the pole rows need only one triangle per cell.
      if (r != 0) mesh.indices.insert(mesh.indices.end(), {a, b, d});
      if (r != rings - 1) mesh.indices.insert(mesh.indices.end(), {b, c, d});
    }
  if (inward) turnInsideOut(mesh);
  return mesh;
}

MeshPrimitive makeQuad(const Vec3& corner, const Vec3& edge1, const Vec3& edge2) {
  MeshPrimitive mesh;
  Vec3 n = glm::normalize(glm::cross(edge1, edge2));
  // Edges beyond about 4e9 (or below 1e-19) overflowed (underflowed) the float square: NaN.
  if (!std::isfinite(n.x + n.y + n.z)) {
    float crossLength = 0.0f;
    n = triangleUnitNormal(edge1, edge2, crossLength);
  }
  mesh.positions = {corner, corner + edge1, corner + edge1 + edge2, corner + edge2};
  mesh.normals = {n, n, n, n};
  mesh.uv0 = {Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)};
  mesh.indices = {0, 1, 2, 0, 2, 3};
  return mesh;
}

MeshPrimitive makeBox(const Vec3& center, const Vec3& size, bool inward) {
  MeshPrimitive mesh;
  const Vec3 h = 0.5f * size;
  // Each face: outward normal n and two in-face axes with u x v = n.
  const Vec3 faces[6][3] = {
      {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}}, {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
      {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}}, {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
      {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},  {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}},
  };
  for (const auto& face : faces) {
    const Vec3 n = face[0], u = face[1], v = face[2];
    const uint32_t base = uint32_t(mesh.positions.size());
    const float su[4] = {-1, 1, 1, -1}, sv[4] = {-1, -1, 1, 1};
    for (int k = 0; k < 4; ++k) {
      mesh.positions.push_back(center + h * (n + su[k] * u + sv[k] * v));
      mesh.normals.push_back(n);
      mesh.uv0.push_back(Vec2(0.5f * (su[k] + 1), 0.5f * (sv[k] + 1)));
    }
    mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  }
  if (inward) turnInsideOut(mesh);
  return mesh;
}

}  // namespace tex::render
