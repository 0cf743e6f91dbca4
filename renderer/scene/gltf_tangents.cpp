#include "renderer/scene/gltf_tangents.h"

#include <algorithm>
#include <cmath>

namespace tex::render {

namespace {

float cornerAngle(const Vec3& a, const Vec3& b) {
  const float la = glm::length(a), lb = glm::length(b);
  if (!(la > 0.0f && lb > 0.0f)) return 0.0f;
  return std::acos(std::clamp(glm::dot(a, b) / (la * lb), -1.0f, 1.0f));
}

// Any unit vector orthogonal to n (n unit).
Vec3 orthogonalTo(const Vec3& n) {
  const Vec3 axis = std::fabs(n.x) < 0.9f ? Vec3(1.0f, 0.0f, 0.0f) : Vec3(0.0f, 1.0f, 0.0f);
  return glm::normalize(glm::cross(axis, n));
}

}  // namespace

std::vector<Vec3> faceAveragedNormals(const MeshPrimitive& prim) {
  std::vector<Vec3> normals(prim.positions.size(), Vec3(0.0f));
  for (size_t t = 0; t + 2 < prim.indices.size(); t += 3) {
    const uint32_t v[3] = {prim.indices[t], prim.indices[t + 1], prim.indices[t + 2]};
    const Vec3 n = glm::cross(prim.positions[v[1]] - prim.positions[v[0]], prim.positions[v[2]] - prim.positions[v[0]]);
    if (!std::isfinite(n.x + n.y + n.z)) continue;
    for (uint32_t k : v) normals[k] += n;
  }
  for (Vec3& n : normals) {
    const float l = glm::length(n);
    n = l > 0.0f && std::isfinite(l) ? n / l : Vec3(0.0f, 0.0f, 1.0f);
  }
  return normals;
}

std::vector<Vec4> generateTangents(const MeshPrimitive& prim, const std::vector<Vec2>& uv) {
  const size_t n = prim.positions.size();
  std::vector<Vec3> tangentSum(n, Vec3(0.0f)), bitangentSum(n, Vec3(0.0f));
  for (size_t t = 0; t + 2 < prim.indices.size(); t += 3) {
    const uint32_t v[3] = {prim.indices[t], prim.indices[t + 1], prim.indices[t + 2]};
    const Vec3 e1 = prim.positions[v[1]] - prim.positions[v[0]], e2 = prim.positions[v[2]] - prim.positions[v[0]];
    const Vec2 d1 = uv[v[1]] - uv[v[0]], d2 = uv[v[2]] - uv[v[0]];
    const float det = d1.x * d2.y - d1.y * d2.x;
    if (!(std::fabs(det) > 1e-20f)) continue;
    // dp/du and dp/dv of the triangle's uv parametrisation.
    Vec3 dpdu = (e1 * d2.y - e2 * d1.y) / det, dpdv = (e2 * d1.x - e1 * d2.x) / det;
    const float lu = glm::length(dpdu), lv = glm::length(dpdv);
    if (!(lu > 0.0f && lv > 0.0f) || !std::isfinite(lu) || !std::isfinite(lv)) continue;
    dpdu /= lu;
    dpdv /= lv;
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = prim.positions[v[k]];
      const float angle = cornerAngle(prim.positions[v[(k + 1) % 3]] - p, prim.positions[v[(k + 2) % 3]] - p);
      tangentSum[v[k]] += angle * dpdu;
      bitangentSum[v[k]] += angle * dpdv;
    }
  }
  std::vector<Vec4> tangents(n);
  for (size_t i = 0; i < n; ++i) {
    Vec3 normal = i < prim.normals.size() ? prim.normals[i] : Vec3(0.0f, 0.0f, 1.0f);
    const float nl = glm::length(normal);
    normal = nl > 0.0f && std::isfinite(nl) ? normal / nl : Vec3(0.0f, 0.0f, 1.0f);
    Vec3 t = tangentSum[i] - normal * glm::dot(normal, tangentSum[i]);
    const float tl = glm::length(t);
    t = tl > 1e-12f && std::isfinite(tl) ? t / tl : orthogonalTo(normal);
    // glTF: bitangent = cross(normal, tangent) * w, pointing toward decreasing v (the uv origin
    // is the image's top-left corner, normal maps have +Y up), as the renderer's per-triangle
    // fallback has it (renderer/material/gltf_material.cpp).
    const float w = glm::dot(glm::cross(normal, t), -bitangentSum[i]) >= 0.0f ? 1.0f : -1.0f;
    tangents[i] = Vec4(t, w);
  }
  return tangents;
}

}  // namespace tex::render
