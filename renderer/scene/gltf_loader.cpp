// glTF 2.0 loading: file and extensions, meshes, the node tree, cameras and punctual lights.
// Accessors are read through gltf_accessor.h, materials through gltf_material.cpp.
#include "renderer/scene/gltf_loader.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <optional>
#include <set>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "renderer/scene/gltf_accessor.h"
#include "renderer/scene/gltf_data_uris.h"
#include "renderer/scene/gltf_images.h"
#include "renderer/scene/gltf_import.h"
#include "renderer/scene/gltf_pose.h"
#include "renderer/scene/gltf_tangents.h"

namespace tex::render {

namespace {

// Extensions whose absence would change the picture and which we implement (extensionsRequired).
const std::set<std::string> kSupportedExtensions = {
    "KHR_texture_transform",       "KHR_materials_emissive_strength", "KHR_materials_transmission",
    "KHR_materials_ior",           "KHR_materials_dispersion",        "KHR_materials_volume",
    "KHR_lights_punctual",         "KHR_mesh_quantization",           "KHR_materials_clearcoat",
    "KHR_materials_sheen",         "KHR_materials_specular",          "KHR_materials_unlit",
    "KHR_materials_anisotropy",
};

constexpr int kMaxNodeDepth = 1024;

std::string directoryOf(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string(".") : path.substr(0, slash);
}

struct MeshImport {
  std::vector<int> primitives;  // scene primitive indices (skipped glTF primitives left out)
  std::vector<size_t> gltfPrimitives;  // the glTF primitive each came from
  bool done = false;
};

// A mesh as nodes use it: its index and the morph target weights it is posed with (empty when
// all are zero, so unposed uses share one import).
using MeshKey = std::pair<int, std::vector<double>>;

class Importer {
 public:
  Importer(GltfImport& import, const Mat4& transform, std::vector<std::string>& errors)
      : in_(import), model_(import.model), transform_(transform), errors_(errors) {}

  bool run() {
    if (!importSceneNodes()) return false;
    return errors_.size() == errorCountAtStart_;
  }

 private:
  void fail(const std::string& message) { errors_.push_back(in_.file + ": " + message); }

  // ---- meshes ---------------------------------------------------------------------------
  // Component types: floats, and KHR_mesh_quantization's integers (`allowed`).
  bool readVec3s(int accessor, std::vector<Vec3>& out, const std::string& what, unsigned allowed) {
    std::vector<float> f;
    std::string err = readFloatAccessor(model_, accessor, TINYGLTF_TYPE_VEC3, allowed, f);
    if (!err.empty()) return fail(what + ": " + err), false;
    out.resize(f.size() / 3);
    for (size_t i = 0; i < out.size(); ++i) out[i] = Vec3(f[3 * i], f[3 * i + 1], f[3 * i + 2]);
    return true;
  }
  bool readVec2s(int accessor, std::vector<Vec2>& out, const std::string& what) {
    std::vector<float> f;
    std::string err = readFloatAccessor(model_, accessor, TINYGLTF_TYPE_VEC2, kQuantizedCoordinates, f);
    if (!err.empty()) return fail(what + ": " + err), false;
    out.resize(f.size() / 2);
    for (size_t i = 0; i < out.size(); ++i) out[i] = Vec2(f[2 * i], f[2 * i + 1]);
    return true;
  }
  bool readVec4s(int accessor, std::vector<Vec4>& out, const std::string& what) {
    std::vector<float> f;
    std::string err = readFloatAccessor(model_, accessor, TINYGLTF_TYPE_VEC4, kQuantizedDirections, f);
    if (!err.empty()) return fail(what + ": " + err), false;
    out.resize(f.size() / 4);
    for (size_t i = 0; i < out.size(); ++i) out[i] = Vec4(f[4 * i], f[4 * i + 1], f[4 * i + 2], f[4 * i + 3]);
    return true;
  }

  // COLOR_0: RGB or RGBA, float or normalized unsigned byte / short (glTF 2.0 3.7.2.1).
  bool readColors(int accessor, std::vector<Vec4>& out, const std::string& what) {
    const bool rgb = accessor >= 0 && size_t(accessor) < model_.accessors.size() &&
                     model_.accessors[size_t(accessor)].type == TINYGLTF_TYPE_VEC3;
    std::vector<float> f;
    std::string err = readFloatAccessor(model_, accessor, rgb ? TINYGLTF_TYPE_VEC3 : TINYGLTF_TYPE_VEC4,
                                        kFloatComponents | kNormalizedUint8 | kNormalizedUint16, f);
    if (!err.empty()) return fail(what + ": " + err), false;
    const size_t n = rgb ? 3 : 4;
    out.resize(f.size() / n);
    for (size_t i = 0; i < out.size(); ++i)
      out[i] = Vec4(f[n * i], f[n * i + 1], f[n * i + 2], rgb ? 1.0f : f[n * i + 3]);
    return true;
  }

  // Converts strips and fans to triangle lists (glTF 2.0 section 3.7.2.1 gives the orders).
  static std::vector<uint32_t> toTriangleList(const std::vector<uint32_t>& in, int mode) {
    std::vector<uint32_t> out;
    for (size_t i = 2; i < in.size(); ++i) {
      if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        if (i % 2 == 0) out.insert(out.end(), {in[i - 2], in[i - 1], in[i]});
        else out.insert(out.end(), {in[i - 1], in[i - 2], in[i]});
      } else {
        out.insert(out.end(), {in[i - 1], in[i], in[0]});
      }
    }
    return out;
  }

  // One glTF primitive -> MeshPrimitive; false with an error when broken, true with
  // `skipped` when it is valid but not triangles.
  bool convertPrimitive(const tinygltf::Mesh& mesh, int meshIndex, size_t primIndex, const std::vector<double>& weights,
                        MeshPrimitive& out,
                        bool& skipped) {
    const tinygltf::Primitive& prim = mesh.primitives[primIndex];
    const std::string where = "mesh " + std::to_string(meshIndex) + (mesh.name.empty() ? "" : " \"" + mesh.name + "\"") +
                              " primitive " + std::to_string(primIndex);
    skipped = false;
    const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      in_.warnOnce("mode/" + std::to_string(mode), where + " has mode " + std::to_string(mode) +
                                                       " (points or lines); such primitives are skipped");
      skipped = true;
      return true;
    }
    auto attribute = [&](const char* name) {
      auto it = prim.attributes.find(name);
      return it == prim.attributes.end() ? -1 : it->second;
    };
    out.meshName = mesh.name;
    const int position = attribute("POSITION");
    if (position < 0) return fail(where + " has no POSITION attribute"), false;
    if (!readVec3s(position, out.positions, where + " POSITION", kQuantizedCoordinates)) return false;
    const size_t vertexCount = out.positions.size();
    auto sameCount = [&](size_t n, const char* name) {
      if (n == vertexCount) return true;
      fail(where + " " + name + " has " + std::to_string(n) + " elements but POSITION has " +
           std::to_string(vertexCount));
      return false;
    };
    if (int a = attribute("NORMAL"); a >= 0)
      if (!readVec3s(a, out.normals, where + " NORMAL", kQuantizedDirections) || !sameCount(out.normals.size(), "NORMAL"))
        return false;
    if (int a = attribute("TEXCOORD_0"); a >= 0)
      if (!readVec2s(a, out.uv0, where + " TEXCOORD_0") || !sameCount(out.uv0.size(), "TEXCOORD_0")) return false;
    if (int a = attribute("TEXCOORD_1"); a >= 0)
      if (!readVec2s(a, out.uv1, where + " TEXCOORD_1") || !sameCount(out.uv1.size(), "TEXCOORD_1")) return false;
    if (int a = attribute("TANGENT"); a >= 0) {
      if (!readVec4s(a, out.tangents, where + " TANGENT") || !sameCount(out.tangents.size(), "TANGENT")) return false;
      // glTF 2.0 3.7.2.1: without normals (flat shading) the given tangents MUST be ignored.
      if (out.normals.empty()) {
        in_.warn(where + " has TANGENT but no NORMAL; the tangents are ignored (flat shading)");
        out.tangents.clear();
      }
    }
    if (int a = attribute("COLOR_0"); a >= 0)
      if (!readColors(a, out.colors, where + " COLOR_0") || !sameCount(out.colors.size(), "COLOR_0")) return false;
    if (!weights.empty()) {
      std::vector<std::string> ignored;
      const std::string err = applyMorphTargets(model_, prim, weights, out, ignored);
      if (!err.empty()) return fail(where + " " + err), false;
      for (const std::string& name : ignored)
        in_.warnOnce("morph/" + name, where + ": morph target attribute " + name + " is not applied (only POSITION, NORMAL and TANGENT are)");
    }

    std::vector<uint32_t> indices;
    if (prim.indices >= 0) {
      std::string err = readIndexAccessor(model_, prim.indices, indices);
      if (!err.empty()) return fail(where + " indices: " + err), false;
      for (size_t i = 0; i < indices.size(); ++i)
        if (indices[i] >= vertexCount)
          return fail(where + " index " + std::to_string(i) + " is " + std::to_string(indices[i]) +
                      ", but there are only " + std::to_string(vertexCount) + " vertices"),
                 false;
    } else {
      if (vertexCount > UINT32_MAX) return fail(where + " has too many vertices"), false;
      indices.resize(vertexCount);
      for (size_t i = 0; i < vertexCount; ++i) indices[i] = uint32_t(i);
    }
    if (mode != TINYGLTF_MODE_TRIANGLES) indices = toTriangleList(indices, mode);
    else if (indices.size() % 3 != 0)
      return fail(where + " has " + std::to_string(indices.size()) + " indices, not a multiple of 3"), false;
    out.indices = std::move(indices);

    if (prim.material >= 0 && size_t(prim.material) < model_.materials.size()) {
      out.material = prim.material + in_.materialOffset;
    } else {
      if (prim.material >= 0)
        in_.warn(where + " uses material " + std::to_string(prim.material) + ", which does not exist; using the default");
      out.material = in_.defaultMaterialIndex();
    }
    // Normal maps need a tangent frame: generated per vertex when the file has none. Without
    // normals (flat shading) the hit's own triangle frame follows TEXCOORD_0, so a map on
    // TEXCOORD_1 gets tangents generated from it, orthogonalised per hit against the flat
    // normal (its frame had followed TEXCOORD_0, or the map was ignored without one).
    if (out.tangents.empty() && out.material >= 0 && size_t(out.material) < in_.scene.materials.size()) {
      const TextureRef& normalMap = in_.scene.materials[size_t(out.material)].normalTexture;
      const std::vector<Vec2>& uv = normalMap.texCoord == 1 ? out.uv1 : out.uv0;
      if (normalMap.image >= 0 && !uv.empty()) {
        if (!out.normals.empty()) {
          out.tangents = generateTangents(out, uv);
        } else if (normalMap.texCoord == 1) {
          MeshPrimitive withNormals = out;
          withNormals.normals = faceAveragedNormals(out);
          out.tangents = generateTangents(withNormals, uv);
        }
      }
    }
    return true;
  }

  bool importMesh(int meshIndex, const std::vector<double>& weights, const MeshImport*& import) {
    MeshImport& mi = meshes_[MeshKey(meshIndex, weights)];
    import = &mi;
    if (mi.done) return true;
    mi.done = true;
    const tinygltf::Mesh& mesh = model_.meshes[size_t(meshIndex)];
    for (size_t p = 0; p < mesh.primitives.size(); ++p) {
      MeshPrimitive prim;
      bool skipped = false;
      if (!convertPrimitive(mesh, meshIndex, p, weights, prim, skipped)) return false;
      if (skipped) continue;
      mi.primitives.push_back(int(in_.scene.primitives.size()));
      mi.gltfPrimitives.push_back(p);
      in_.scene.primitives.push_back(std::move(prim));
    }
    return true;
  }

  // The morph target weights a node poses its mesh with: node.weights, else mesh.weights;
  // empty when every weight is zero (the mesh as stored).
  static std::vector<double> morphWeights(const tinygltf::Node& node, const tinygltf::Mesh& mesh) {
    std::vector<double> w = node.weights.empty() ? mesh.weights : node.weights;
    bool any = false;
    for (double& x : w) {
      if (!std::isfinite(x)) x = 0.0;
      any = any || x != 0.0;
    }
    return any ? w : std::vector<double>();
  }

  // Skinned meshes, once every node's world transform is known: each primitive is skinned
  // into world space (its own copy, instanced with the identity); the node's own transform
  // only places vertices without influences. A skin whose joints are not all in the scene is
  // rendered unskinned, with a warning.
  bool placeSkinnedMeshes() {
    for (const PendingSkin& pending : pendingSkins_) {
      const tinygltf::Node& node = model_.nodes[size_t(pending.node)];
      const std::string where = "node " + std::to_string(pending.node) + (node.name.empty() ? "" : " \"" + node.name + "\"");
      const tinygltf::Skin& skin = model_.skins[size_t(node.skin)];
      // A joint outside the scene: render unskinned (a warning); a malformed skin: an error.
      const int outside = jointOutsideScene(skin, worldOfNode_);
      std::vector<Mat4> joints;
      if (outside < 0) {
        const std::string jointErr = jointMatrices(model_, skin, worldOfNode_, joints);
        if (!jointErr.empty()) return fail(where + " skin " + std::to_string(node.skin) + " " + jointErr), false;
      }
      for (size_t k = 0; k < pending.mesh->primitives.size(); ++k) {
        const int p = pending.mesh->primitives[k];
        const tinygltf::Primitive& gltfPrim = model_.meshes[size_t(node.mesh)].primitives[pending.mesh->gltfPrimitives[k]];
        const bool influenced = gltfPrim.attributes.count("JOINTS_0") && gltfPrim.attributes.count("WEIGHTS_0");
        if (outside < 0 && influenced) {
          MeshPrimitive skinned = in_.scene.primitives[size_t(p)];
          const std::string skinErr = skinToWorld(model_, gltfPrim, joints, pending.world, skinned);
          if (!skinErr.empty()) return fail(where + " skin " + std::to_string(node.skin) + ": " + skinErr), false;
          in_.scene.instances.push_back(MeshInstance{int(in_.scene.primitives.size()), Mat4(1.0f), node.name});
          in_.scene.primitives.push_back(std::move(skinned));
          continue;
        }
        if (outside < 0)
          in_.warn(where + " has a skin but its mesh's primitive " + std::to_string(k) + " has no JOINTS_0 / WEIGHTS_0; placed by the node");
        in_.scene.instances.push_back(MeshInstance{p, pending.world, node.name});
      }
      if (outside >= 0)
        in_.warn(where + " skin " + std::to_string(node.skin) + " joint " + std::to_string(outside) + " is node " +
                 std::to_string(skin.joints[size_t(outside)]) + ", which is not in the rendered scene; the mesh is placed by its node, unskinned");
    }
    return true;
  }

  // ---- nodes ----------------------------------------------------------------------------
  bool localTransform(const tinygltf::Node& node, const std::string& where, Mat4& out) {
    auto finite = [](const std::vector<double>& v) {
      for (double d : v)
        if (!std::isfinite(d)) return false;
      return true;
    };
    if (!finite(node.matrix) || !finite(node.translation) || !finite(node.rotation) || !finite(node.scale))
      return fail(where + " has a non-finite transform"), false;
    if (!node.matrix.empty()) {
      if (node.matrix.size() != 16) return fail(where + " matrix has " + std::to_string(node.matrix.size()) + " numbers, expected 16"), false;
      float m[16];
      for (int i = 0; i < 16; ++i) m[i] = float(node.matrix[size_t(i)]);  // column-major, as GLM
      out = glm::make_mat4(m);
      // glTF 2.0 3.5.3: a matrix MUST be decomposable to TRS, so its last row is (0, 0, 0, 1).
      if (m[3] != 0.0f || m[7] != 0.0f || m[11] != 0.0f || m[15] != 1.0f) {
        in_.warn(where + " matrix is not affine (its last row is not 0 0 0 1); the row is ignored");
        out[0][3] = out[1][3] = out[2][3] = 0.0f;
        out[3][3] = 1.0f;
      }
      return true;
    }
    if (!node.translation.empty() && node.translation.size() != 3) return fail(where + " translation needs 3 numbers"), false;
    if (!node.rotation.empty() && node.rotation.size() != 4) return fail(where + " rotation needs 4 numbers"), false;
    if (!node.scale.empty() && node.scale.size() != 3) return fail(where + " scale needs 3 numbers"), false;
    Mat4 t(1.0f), r(1.0f), s(1.0f);
    if (!node.translation.empty())
      t = glm::translate(Mat4(1.0f), Vec3(float(node.translation[0]), float(node.translation[1]), float(node.translation[2])));
    if (!node.rotation.empty()) {
      // glTF quaternions are (x, y, z, w); GLM's constructor takes w first.
      glm::quat q(float(node.rotation[3]), float(node.rotation[0]), float(node.rotation[1]), float(node.rotation[2]));
      const float len = glm::length(q);
      if (!(len > 0.0f)) return fail(where + " rotation is a zero quaternion"), false;
      r = glm::mat4_cast(q / len);
    }
    if (!node.scale.empty()) s = glm::scale(Mat4(1.0f), Vec3(float(node.scale[0]), float(node.scale[1]), float(node.scale[2])));
    out = t * r * s;
    return true;
  }

  void addCamera(const tinygltf::Node& node, int nodeIndex, const Mat4& world) {
    const std::string where = "node " + std::to_string(nodeIndex);
    if (size_t(node.camera) >= model_.cameras.size()) {
      in_.warn(where + " uses camera " + std::to_string(node.camera) + ", which does not exist; ignored");
      return;
    }
    const tinygltf::Camera& cam = model_.cameras[size_t(node.camera)];
    CameraDesc desc;
    if (cam.type == "orthographic") {
      // glTF's xmag / ymag: half the film's width and height in world units.
      const double xmag = cam.orthographic.xmag, ymag = cam.orthographic.ymag;
      if (!(ymag > 0.0 && std::isfinite(ymag))) {
        in_.warn("camera " + std::to_string(node.camera) + " has ymag " + std::to_string(ymag) + ", not positive; ignored");
        return;
      }
      desc.orthoHalfHeight = float(ymag);
      desc.aspect = std::isfinite(xmag) && xmag > 0.0 ? float(xmag / ymag) : 0.0f;
    } else if (cam.type != "perspective") {
      in_.warnOnce("camera/" + cam.type, "camera " + std::to_string(node.camera) + " is of type \"" + cam.type +
                                             "\" (perspective or orthographic); ignored");
      return;
    }
    const double yfov = cam.perspective.yfov;
    if (cam.type == "perspective" && !(yfov > 0.0 && yfov < double(kPi))) {
      in_.warn("camera " + std::to_string(node.camera) + " has yfov " + std::to_string(yfov) + ", outside (0, pi); ignored");
      return;
    }
    desc.name = cam.name.empty() ? node.name : cam.name;
    // Cameras are rigid: drop any scale in the node chain (glTF says it should have none).
    desc.cameraToWorld = world;
    for (int c = 0; c < 3; ++c) {
      Vec3 axis(world[c]);
      const float len = glm::length(axis);
      if (len > 0.0f) desc.cameraToWorld[c] = Vec4(axis / len, 0.0f);
    }
    if (cam.type == "perspective") {
      desc.yFovRadians = float(yfov);
      const double aspect = cam.perspective.aspectRatio;
      desc.aspect = std::isfinite(aspect) && aspect > 0.0 ? float(aspect) : 0.0f;
    }
    in_.scene.cameras.push_back(desc);
  }

  // The light's own JSON object in the file's KHR_lights_punctual extension, if tinygltf kept it.
  const tinygltf::Value* rawLight(int index) const {
    const auto ext = model_.extensions.find("KHR_lights_punctual");
    if (ext == model_.extensions.end() || !ext->second.IsObject() || !ext->second.Has("lights")) return nullptr;
    const tinygltf::Value& lights = ext->second.Get("lights");
    if (!lights.IsArray() || index < 0 || size_t(index) >= lights.ArrayLen()) return nullptr;
    const tinygltf::Value& light = lights.Get(index);
    return light.IsObject() ? &light : nullptr;
  }

  void addLight(const tinygltf::Node& node, int nodeIndex, const Mat4& world) {
    auto ext = node.extensions.find("KHR_lights_punctual");
    if (ext == node.extensions.end()) return;
    const std::string where = "node " + std::to_string(nodeIndex);
    const tinygltf::Value& value = ext->second;
    if (!value.IsObject() || !value.Has("light") || !value.Get("light").IsInt()) {
      in_.warn(where + ": KHR_lights_punctual has no integer \"light\"; ignored");
      return;
    }
    const int index = value.Get("light").GetNumberAsInt();
    if (index < 0 || size_t(index) >= model_.lights.size()) {
      in_.warn(where + " uses light " + std::to_string(index) + ", which does not exist; ignored");
      return;
    }
    const tinygltf::Light& light = model_.lights[size_t(index)];
    LightDesc desc;
    desc.name = light.name.empty() ? node.name : light.name;
    if (light.type == "point") desc.kind = LightDesc::Kind::Point;
    else if (light.type == "spot") desc.kind = LightDesc::Kind::Spot;
    else if (light.type == "directional") desc.kind = LightDesc::Kind::Directional;
    else {
      in_.warn("light " + std::to_string(index) + " has unknown type \"" + light.type + "\"; ignored");
      return;
    }
    const std::string lightName = "light " + std::to_string(index);
    // tinygltf drops a malformed colour or intensity without a word (a colour of four numbers
    // rendered white, an intensity "10" rendered at 1): the raw extension says what was there.
    const tinygltf::Value* raw = rawLight(index);
    if (raw && raw->Has("intensity") && !raw->Get("intensity").IsNumber() && !raw->Get("intensity").IsInt())
      in_.warn(lightName + " has an intensity that is not a number; 1 is used");
    const bool colorGiven = raw ? raw->Has("color") : !light.color.empty();
    desc.emission.kind = SpectrumDesc::Kind::Rgb;
    desc.emission.rgb = Vec3(1.0f);
    if (light.color.size() == 3 && std::isfinite(light.color[0]) && std::isfinite(light.color[1]) &&
        std::isfinite(light.color[2])) {
      const double largest = std::max({light.color[0], light.color[1], light.color[2]});
      if (largest > double(std::numeric_limits<float>::max())) {
        in_.warn(lightName + " has a colour beyond the range of a 32-bit float; ignored");
        return;
      }
      desc.emission.rgb = Vec3(float(light.color[0]), float(light.color[1]), float(light.color[2]));
      if (std::min({desc.emission.rgb.x, desc.emission.rgb.y, desc.emission.rgb.z}) < 0.0f) {
        in_.warn(lightName + " has a negative colour component; clamped to 0");
        desc.emission.rgb = glm::max(desc.emission.rgb, Vec3(0.0f));
      }
    } else if (colorGiven) {
      in_.warn(lightName + " has a colour that is not three finite numbers; white is used");
    }
    if (!std::isfinite(light.intensity) || light.intensity > double(std::numeric_limits<float>::max())) {
      in_.warn(lightName + " has intensity " + std::to_string(light.intensity) +
               (std::isfinite(light.intensity) ? ", beyond the range of a 32-bit float" : "") + "; ignored");
      return;
    }
    // Negative: clamped to a dark light, which is kept (dropped, it let the renderer light a
    // scene that has a light with its default sky).
    double intensity = light.intensity;
    if (intensity < 0.0) {
      in_.warn("light " + std::to_string(index) + " has negative intensity " + std::to_string(intensity) + "; clamped to 0");
      intensity = 0.0;
    }
    desc.intensity = float(intensity);  // cd (or lux) taken as W/sr (W/m^2): docs/scene-format.md
    desc.position = Vec3(world * Vec4(0, 0, 0, 1));
    const Vec3 forward = Vec3(world * Vec4(0, 0, -1, 0));  // lights shine down local -z
    if (glm::length(forward) > 0.0f) desc.direction = glm::normalize(forward);
    if (desc.kind == LightDesc::Kind::Spot) {
      float inner = float(light.spot.innerConeAngle), outer = float(light.spot.outerConeAngle);
      if (!(outer > 0.0f && outer <= 0.5f * kPi + 1e-6f && inner >= 0.0f && inner < outer)) {
        in_.warn("light " + std::to_string(index) + " has cone angles inner " + std::to_string(inner) + ", outer " +
                 std::to_string(outer) + " (need 0 <= inner < outer <= pi/2); clamped");
        outer = std::fmin(std::fmax(std::isfinite(outer) ? outer : 0.7853982f, 1e-4f), 0.5f * kPi);
        inner = std::fmin(std::fmax(std::isfinite(inner) ? inner : 0.0f, 0.0f), outer * 0.999f);
      }
      desc.innerConeRadians = inner;
      desc.outerConeRadians = outer;
    }
    in_.scene.lights.push_back(desc);
  }

  bool visitNode(int nodeIndex, const Mat4& parent, int depth) {
    if (nodeIndex < 0 || size_t(nodeIndex) >= model_.nodes.size())
      return fail("node " + std::to_string(nodeIndex) + " does not exist (the file has " +
                  std::to_string(model_.nodes.size()) + " nodes)"),
             false;
    if (depth > kMaxNodeDepth) return fail("the node tree is deeper than " + std::to_string(kMaxNodeDepth)), false;
    if (!visited_.insert(nodeIndex).second)
      return fail("node " + std::to_string(nodeIndex) + " is reached twice (the node graph must be a tree)"), false;
    const tinygltf::Node& node = model_.nodes[size_t(nodeIndex)];
    const std::string where = "node " + std::to_string(nodeIndex) + (node.name.empty() ? "" : " \"" + node.name + "\"");
    Mat4 local;
    if (!localTransform(node, where, local)) return false;
    const Mat4 world = parent * local;
    worldOfNode_[size_t(nodeIndex)] = world;
    if (node.mesh >= 0) {
      if (size_t(node.mesh) >= model_.meshes.size())
        return fail(where + " uses mesh " + std::to_string(node.mesh) + ", which does not exist"), false;
      const MeshImport* mesh = nullptr;
      if (!importMesh(node.mesh, morphWeights(node, model_.meshes[size_t(node.mesh)]), mesh)) return false;
      if (node.skin >= 0) {
        if (size_t(node.skin) >= model_.skins.size())
          return fail(where + " uses skin " + std::to_string(node.skin) + ", which does not exist"), false;
        pendingSkins_.push_back(PendingSkin{nodeIndex, world, mesh});
      } else {
        for (int p : mesh->primitives) in_.scene.instances.push_back(MeshInstance{p, world, node.name});
      }
    }
    if (node.camera >= 0) addCamera(node, nodeIndex, world);
    addLight(node, nodeIndex, world);
    for (int child : node.children)
      if (!visitNode(child, world, depth + 1)) return false;
    return true;
  }

  bool importSceneNodes() {
    std::vector<int> roots;
    if (!model_.scenes.empty()) {
      int sceneIndex = model_.defaultScene;
      if (sceneIndex < 0 || size_t(sceneIndex) >= model_.scenes.size()) {
        if (sceneIndex >= 0) in_.warn("default scene " + std::to_string(sceneIndex) + " does not exist; using scene 0");
        sceneIndex = 0;
      }
      roots = model_.scenes[size_t(sceneIndex)].nodes;
    } else if (!model_.nodes.empty()) {
      // No scenes: every node that is nobody's child is a root.
      std::vector<bool> isChild(model_.nodes.size(), false);
      for (const auto& node : model_.nodes)
        for (int c : node.children)
          if (c >= 0 && size_t(c) < isChild.size()) isChild[size_t(c)] = true;
      for (size_t i = 0; i < model_.nodes.size(); ++i)
        if (!isChild[i]) roots.push_back(int(i));
      in_.warn("the file has no scenes; rendering every root node");
    }
    worldOfNode_.assign(model_.nodes.size(), std::nullopt);
    for (int root : roots)
      if (!visitNode(root, transform_, 0)) return false;
    if (model_.scenes.empty()) {
      // Every node is below a root unless the children form a cycle with no way in.
      for (size_t i = 0; i < model_.nodes.size(); ++i)
        if (!visited_.count(int(i)))
          return fail("node " + std::to_string(i) + " is reached from no root: the children links form a cycle (the node graph must be a tree)"), false;
    }
    return placeSkinnedMeshes();
  }

  GltfImport& in_;
  const tinygltf::Model& model_;
  Mat4 transform_;
  std::vector<std::string>& errors_;
  size_t errorCountAtStart_ = errors_.size();
  std::map<MeshKey, MeshImport> meshes_;
  std::set<int> visited_;
  // World transforms of the scene's nodes (none: not in the scene), for skins' joints.
  std::vector<std::optional<Mat4>> worldOfNode_;
  struct PendingSkin {
    int node;
    Mat4 world;
    const MeshImport* mesh;
  };
  std::vector<PendingSkin> pendingSkins_;
};

// tinygltf messages are several lines; keep each as its own message.
void splitLines(const std::string& text, const std::string& prefix, std::vector<std::string>& out) {
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    if (end > start) out.push_back(prefix + text.substr(start, end - start));
    start = end + 1;
  }
}

// The deepest nesting of arrays and objects in JSON text (outside strings). tinygltf parses
// recursively, so a file nested a million deep (2 MB of brackets) overflowed the stack.
int jsonNestingDepth(const unsigned char* text, size_t size) {
  int depth = 0, deepest = 0;
  bool inString = false, escaped = false;
  for (size_t i = 0; i < size; ++i) {
    const unsigned char c = text[i];
    if (inString) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') inString = false;
    } else if (c == '"') {
      inString = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return deepest;
}
constexpr int kMaxJsonNesting = 256;

// Files a glTF refers to (buffers, images) must be regular files: a FIFO blocked the loader
// forever and a directory threw bad_alloc. Others count as missing (an error for a buffer, a
// warning for an image, as a missing file is).
bool regularFileExists(const std::string& absolutePath, void*) {
  std::error_code ec;
  return std::filesystem::is_regular_file(absolutePath, ec);
}

// tinygltf's file reader, noting each file it reads (buffers, images) as an input of the scene.
bool readAndNoteFile(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* inputFiles) {
  const bool ok = tinygltf::ReadWholeFile(out, err, path, nullptr);
  if (ok && inputFiles) static_cast<std::vector<std::string>*>(inputFiles)->push_back(path);
  return ok;
}

bool parseFile(const std::string& path, tinygltf::Model& model, DecodedImages& decoded,
               std::vector<std::string>& warnings, std::vector<std::string>& errors, std::vector<std::string>& inputFiles) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return errors.push_back(path + ": cannot open the file"), false;
  // One read of the whole file where its size is known (a character at a time had been 5 % of
  // loading large files); streams without a size (a FIFO is refused earlier) read to the end.
  std::vector<unsigned char> bytes;
  file.seekg(0, std::ios::end);
  const std::streamoff size = file.tellg();
  file.seekg(0, std::ios::beg);
  if (size > 0 && file) {
    bytes.resize(size_t(size));
    file.read(reinterpret_cast<char*>(bytes.data()), size);
    bytes.resize(size_t(file.gcount()));
  } else {
    file.clear();
    bytes.assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
  }
  if (file.bad()) return errors.push_back(path + ": read error"), false;
  if (bytes.size() >= 0xFFFFFFFFull) return errors.push_back(path + ": files of 4 GiB or more are not supported"), false;
  const bool binary = bytes.size() >= 4 && bytes[0] == 'g' && bytes[1] == 'l' && bytes[2] == 'T' && bytes[3] == 'F';
  const std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : "";
  if (ext == ".glb" && !binary)
    return errors.push_back(path + ": not a binary glTF file (no 'glTF' magic at the start)"), false;

  // The JSON text: the whole file, or a GLB's first chunk (checked again by tinygltf).
  size_t jsonStart = 0, jsonSize = bytes.size();
  if (binary && bytes.size() >= 12) {
    uint32_t container = 0;
    std::memcpy(&container, bytes.data() + 4, 4);
    if (container != 2) return errors.push_back(path + ": GLB container version " + std::to_string(container) + " (only 2 is glTF 2.0)"), false;
  }
  if (binary && bytes.size() >= 20) {
    uint32_t chunkLength = 0;
    std::memcpy(&chunkLength, bytes.data() + 12, 4);
    jsonStart = 20;
    jsonSize = std::min<size_t>(chunkLength, bytes.size() - 20);
  }
  if (jsonNestingDepth(bytes.data() + jsonStart, jsonSize) > kMaxJsonNesting)
    return errors.push_back(path + ": the JSON nests arrays and objects more than " + std::to_string(kMaxJsonNesting) +
                            " levels deep"), false;

  const std::vector<int> undecodable = replaceUndecodableImageUris(bytes, binary);
  for (int i : undecodable) decoded.failures[i] = "its data URI does not decode: not base64, or empty";

  tinygltf::TinyGLTF loader;
  tinygltf::FsCallbacks fs{&regularFileExists, &tinygltf::ExpandFilePath, &readAndNoteFile, &tinygltf::WriteWholeFile,
                           &inputFiles};
  loader.SetFsCallbacks(fs);
  decoded.model = &model;
  loader.SetImageLoader(&decodeGltfImage, &decoded);
  std::string err, warn;
  bool ok = false;
  try {
    if (binary)
      ok = loader.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(), unsigned(bytes.size()), directoryOf(path));
    else
      ok = loader.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(bytes.data()),
                                      unsigned(bytes.size()), directoryOf(path));
  } catch (const std::exception& e) {
    err += std::string("tinygltf threw: ") + e.what();
    ok = false;
  }
  // tinygltf's own words about the replaced URIs (a file not found) would only mislead.
  std::vector<std::string> tinyWarnings;
  splitLines(warn, path + ": ", tinyWarnings);
  for (const std::string& w : tinyWarnings) {
    bool aboutReplaced = w.find(kUndecodableDataUri) != std::string::npos;
    for (int i : undecodable) aboutReplaced = aboutReplaced || w.find("image[" + std::to_string(i) + "]") != std::string::npos;
    if (!aboutReplaced) warnings.push_back(w);
  }
  if (!ok) {
    if (err.empty()) err = "tinygltf could not parse it";
    splitLines(err, path + ": ", errors);
    return false;
  }
  // On success tinygltf's errors are fields it dropped (a baseColorFactor of three numbers lost
  // the whole pbrMetallicRoughness, and the material turned into a grey metal): say so.
  splitLines(err, path + ": ", warnings);
  return true;
}

}  // namespace

bool appendGltf(const std::string& path, const Mat4& transform, SceneDescription& scene,
                std::vector<std::string>& errors) {
  tinygltf::Model model;
  DecodedImages decoded;
  std::vector<std::string> warnings;
  scene.inputFiles.push_back(path);
  if (!parseFile(path, model, decoded, warnings, errors, scene.inputFiles)) return false;
  // glTF 2.x only: a major version change would mean a format this loader does not know.
  if (model.asset.version.rfind("2.", 0) != 0)
    return errors.push_back(path + ": asset.version \"" + model.asset.version + "\" is not glTF 2.x"), false;
  // Accessors without a bufferView are zeros of any count the file claims: bound their total
  // so that a small file cannot make the loader allocate gigabytes (each is also bounded).
  uint64_t unbackedElements = 0;
  for (const tinygltf::Accessor& a : model.accessors)
    if (a.bufferView < 0) unbackedElements += uint64_t(a.count);
  if (unbackedElements > (uint64_t(1) << 23))
    return errors.push_back(path + ": accessors without a bufferView claim " + std::to_string(unbackedElements) +
                            " elements in all, more than 8388608"), false;
  const size_t errorsBefore = errors.size();
  for (const std::string& required : model.extensionsRequired)
    if (!kSupportedExtensions.count(required))
      errors.push_back(path + ": the file requires extension " + required + ", which is not supported");
  if (errors.size() != errorsBefore) return false;

  // On failure, cut every array back to where it was, so `scene` is unchanged.
  const size_t sizes[] = {scene.primitives.size(), scene.instances.size(), scene.images.size(),
                          scene.materials.size(),  scene.cameras.size(),   scene.lights.size(),
                          scene.warnings.size()};
  scene.warnings.insert(scene.warnings.end(), warnings.begin(), warnings.end());
  GltfImport import{model, path, scene, {}, 0, {}};
  importImages(import, decoded);
  importMaterials(import);
  Importer importer(import, transform, errors);
  if (importer.run() && errors.size() == errorsBefore) return true;
  scene.primitives.resize(sizes[0]);
  scene.instances.resize(sizes[1]);
  scene.images.resize(sizes[2]);
  scene.materials.resize(sizes[3]);
  scene.cameras.resize(sizes[4]);
  scene.lights.resize(sizes[5]);
  scene.warnings.resize(sizes[6]);
  return false;
}

std::optional<SceneDescription> loadGltf(const std::string& path, std::vector<std::string>& errors) {
  SceneDescription scene;
  scene.sourcePath = path;
  if (!appendGltf(path, Mat4(1.0f), scene, errors)) return std::nullopt;
  return scene;
}

}  // namespace tex::render
