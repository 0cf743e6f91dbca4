#include "renderer/scene/gltf_pose.h"

#include <cmath>

#include <glm/gtc/type_ptr.hpp>

#include "renderer/scene/gltf_accessor.h"

namespace tex::render {

namespace {

// A VEC3 displacement accessor (float, or the integers KHR_mesh_quantization allows) with one
// element per vertex.
std::string readDisplacements(const tinygltf::Model& model, int accessor, size_t vertices, std::vector<float>& out) {
  std::string err = readFloatAccessor(model, accessor, TINYGLTF_TYPE_VEC3, kQuantizedCoordinates, out);
  if (!err.empty()) return err;
  if (out.size() != vertices * 3)
    return "has " + std::to_string(out.size() / 3) + " elements but POSITION has " + std::to_string(vertices);
  return "";
}

int attributeOf(const std::map<std::string, int>& attributes, const std::string& name) {
  const auto it = attributes.find(name);
  return it == attributes.end() ? -1 : it->second;
}

}  // namespace

std::string applyMorphTargets(const tinygltf::Model& model, const tinygltf::Primitive& gltfPrimitive,
                              const std::vector<double>& weights, MeshPrimitive& prim, std::vector<std::string>& ignored) {
  const size_t n = prim.positions.size();
  std::vector<float> d;
  for (size_t t = 0; t < gltfPrimitive.targets.size() && t < weights.size(); ++t) {
    const float w = float(weights[t]);
    if (w == 0.0f) continue;
    const std::string where = "morph target " + std::to_string(t);
    for (const auto& [name, accessor] : gltfPrimitive.targets[t]) {
      const bool position = name == "POSITION", normal = name == "NORMAL", tangent = name == "TANGENT";
      if (!position && !normal && !tangent) {
        ignored.push_back(name);
        continue;
      }
      if ((normal && prim.normals.empty()) || (tangent && prim.tangents.empty())) continue;  // nothing to displace
      std::string err = readDisplacements(model, accessor, n, d);
      if (!err.empty()) return where + " " + name + ": " + err;
      for (size_t v = 0; v < n; ++v) {
        const Vec3 delta = w * Vec3(d[3 * v], d[3 * v + 1], d[3 * v + 2]);
        if (position) prim.positions[v] += delta;
        else if (normal) prim.normals[v] += delta;
        else prim.tangents[v] += Vec4(delta, 0.0f);  // w (handedness) is not displaced
      }
    }
  }
  for (const Vec3& p : prim.positions)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      return "morph targets move a vertex to a non-finite position";
  return "";
}

int jointOutsideScene(const tinygltf::Skin& skin, const std::vector<std::optional<Mat4>>& worldOfNode) {
  for (size_t j = 0; j < skin.joints.size(); ++j) {
    const int node = skin.joints[j];
    if (node < 0 || size_t(node) >= worldOfNode.size() || !worldOfNode[size_t(node)]) return int(j);
  }
  return -1;
}

std::string jointMatrices(const tinygltf::Model& model, const tinygltf::Skin& skin,
                          const std::vector<std::optional<Mat4>>& worldOfNode, std::vector<Mat4>& out) {
  if (skin.joints.empty()) return "has no joints";
  if (const int j = jointOutsideScene(skin, worldOfNode); j >= 0)
    return "joint " + std::to_string(j) + " is node " + std::to_string(skin.joints[size_t(j)]) +
           ", which is not in the rendered scene";
  std::vector<float> inverseBind;
  if (skin.inverseBindMatrices >= 0) {
    std::string err = readFloatAccessor(model, skin.inverseBindMatrices, TINYGLTF_TYPE_MAT4, kFloatComponents, inverseBind);
    if (!err.empty()) return "inverseBindMatrices: " + err;
    if (inverseBind.size() != skin.joints.size() * 16)
      return "has " + std::to_string(skin.joints.size()) + " joints but " + std::to_string(inverseBind.size() / 16) +
             " inverse bind matrices";
  }
  out.resize(skin.joints.size());
  for (size_t j = 0; j < skin.joints.size(); ++j) {
    const int node = skin.joints[j];
    const Mat4 bind = inverseBind.empty() ? Mat4(1.0f) : glm::make_mat4(&inverseBind[j * 16]);  // column-major
    out[j] = *worldOfNode[size_t(node)] * bind;
  }
  return "";
}

std::string skinToWorld(const tinygltf::Model& model, const tinygltf::Primitive& gltfPrimitive,
                        const std::vector<Mat4>& joints, const Mat4& fallback, MeshPrimitive& prim) {
  const size_t n = prim.positions.size();
  // Influences from every JOINTS_k / WEIGHTS_k pair (four per set).
  std::vector<Mat4> blended(n, Mat4(0.0f));
  std::vector<float> weightSum(n, 0.0f);
  for (int set = 0;; ++set) {
    const int jointsAccessor = attributeOf(gltfPrimitive.attributes, "JOINTS_" + std::to_string(set));
    const int weightsAccessor = attributeOf(gltfPrimitive.attributes, "WEIGHTS_" + std::to_string(set));
    if (jointsAccessor < 0 && weightsAccessor < 0) break;
    const std::string where = "JOINTS_" + std::to_string(set) + " / WEIGHTS_" + std::to_string(set);
    if (jointsAccessor < 0 || weightsAccessor < 0) return where + ": one without the other";
    std::vector<float> j, w;
    std::string err = readFloatAccessor(model, jointsAccessor, TINYGLTF_TYPE_VEC4, kUnsignedIntegers, j);
    if (!err.empty()) return "JOINTS_" + std::to_string(set) + ": " + err;
    err = readFloatAccessor(model, weightsAccessor, TINYGLTF_TYPE_VEC4,
                            kFloatComponents | kNormalizedUint8 | kNormalizedUint16, w);
    if (!err.empty()) return "WEIGHTS_" + std::to_string(set) + ": " + err;
    if (j.size() != n * 4 || w.size() != n * 4) return where + ": element counts differ from POSITION's";
    for (size_t v = 0; v < n; ++v)
      for (int k = 0; k < 4; ++k) {
        const float weight = w[v * 4 + size_t(k)];
        if (weight == 0.0f) continue;
        if (!(weight > 0.0f) || !std::isfinite(weight)) return where + ": a negative or non-finite weight";
        const float joint = j[v * 4 + size_t(k)];
        if (!(joint < float(joints.size())))
          return where + ": joint " + std::to_string(int64_t(joint)) + " of a skin with " + std::to_string(joints.size());
        blended[v] += weight * joints[size_t(joint)];
        weightSum[v] += weight;
      }
  }
  // Vertices whose skinning matrix mirrors (a negative determinant): their triangles' winding
  // and tangent handedness turn, as under a mirroring node (glTF 2.0 3.7.4); the mesh is then
  // placed with an identity transform, so nothing else would turn them.
  std::vector<bool> mirrored(n, false);
  for (size_t v = 0; v < n; ++v) {
    const Mat4 m = weightSum[v] > 0.0f ? blended[v] * (1.0f / weightSum[v]) : fallback;
    prim.positions[v] = Vec3(m * Vec4(prim.positions[v], 1.0f));
    const glm::mat3 linear(m);
    mirrored[v] = glm::determinant(glm::dmat3(linear)) < 0.0;
    if (!prim.normals.empty()) {
      const glm::mat3 normalMatrix = glm::transpose(glm::inverse(linear));
      const Vec3 nw = normalMatrix * prim.normals[v];
      const float len = glm::length(nw);
      if (len > 0.0f && std::isfinite(len)) prim.normals[v] = nw / len;
    }
    if (!prim.tangents.empty()) {
      const Vec3 t = linear * Vec3(prim.tangents[v]);
      prim.tangents[v] = Vec4(t, mirrored[v] ? -prim.tangents[v].w : prim.tangents[v].w);
    }
    if (!std::isfinite(prim.positions[v].x) || !std::isfinite(prim.positions[v].y) || !std::isfinite(prim.positions[v].z))
      return "skinning moves a vertex to a non-finite position";
  }
  for (size_t t = 0; t + 2 < prim.indices.size(); t += 3) {
    const int votes = int(mirrored[prim.indices[t]]) + int(mirrored[prim.indices[t + 1]]) + int(mirrored[prim.indices[t + 2]]);
    if (votes >= 2) std::swap(prim.indices[t + 1], prim.indices[t + 2]);
  }
  return "";
}

}  // namespace tex::render
