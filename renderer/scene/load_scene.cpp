#include "renderer/scene/load_scene.h"

#include <algorithm>
#include <filesystem>

#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/scene_json.h"

namespace tex::render {

namespace {

std::string lowerExtension(const std::string& path) {
  const size_t dot = path.find_last_of('.');
  const size_t slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

std::string joinLines(const std::vector<std::string>& lines) {
  std::string out;
  for (const std::string& line : lines) out += (out.empty() ? "" : "\n") + line;
  return out;
}

}  // namespace

std::optional<SceneDescription> loadScene(const std::string& path, std::string& error) {
  const std::string ext = lowerExtension(path);
  std::vector<std::string> errors;
  std::optional<SceneDescription> scene;
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    error = path + ": is a directory, not a scene file";
    return std::nullopt;
  }
  if (ext == ".gltf" || ext == ".glb") scene = loadGltf(path, errors);
  else if (ext == ".json") scene = loadSceneJson(path, errors);
  else errors.push_back(path + ": unknown scene file type \"" + ext + "\" (expected .gltf, .glb or .json)");
  if (!scene && errors.empty()) errors.push_back(path + ": could not be loaded");
  if (scene) scene->inputFiles.insert(scene->inputFiles.begin(), path);
  error = joinLines(errors);
  return scene;
}

Bounds3 worldBounds(const SceneDescription& scene) {
  // Per primitive, the object-space corners would over-estimate rotated instances; transform
  // the vertices that triangles use instead (exact, and linear in the instanced size).
  std::vector<std::vector<uint32_t>> used(scene.primitives.size());
  Bounds3 bounds;
  for (const MeshInstance& instance : scene.instances) {
    if (instance.primitive < 0 || size_t(instance.primitive) >= scene.primitives.size()) continue;
    const MeshPrimitive& prim = scene.primitives[size_t(instance.primitive)];
    std::vector<uint32_t>& vertices = used[size_t(instance.primitive)];
    if (vertices.empty()) {
      vertices = prim.indices;
      std::sort(vertices.begin(), vertices.end());
      vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
    }
    for (uint32_t v : vertices)
      if (v < prim.positions.size()) bounds.extend(Vec3(instance.objectToWorld * Vec4(prim.positions[v], 1.0f)));
  }
  return bounds;
}

}  // namespace tex::render
