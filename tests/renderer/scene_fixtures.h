// Small scenes built in code for the renderer tests: .tex modules written to a temporary
// folder, one object with a bound .tex material, a camera looking down -z, a constant sky.
#pragma once
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "renderer/scene/scene_description.h"

namespace tex::render::test {

// Writes `text` as <temp>/tex_renderer_tests_<pid>/<stem>.tex and returns its path (a module
// name, so the stem must be an identifier).
inline std::string writeTexModule(const std::string& stem, const std::string& text) {
  const auto dir = std::filesystem::temp_directory_path() / ("tex_renderer_tests_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto path = dir / (stem + ".tex");
  std::ofstream(path) << text;
  return path.string();
}

// Adds `mesh` with one instance and a glTF material of its own named `name` (for
// bindEntriesByMaterialName).
inline void addNamedMesh(SceneDescription& scene, const std::string& name, MeshPrimitive mesh) {
  mesh.material = int(scene.materials.size());
  scene.primitives.push_back(std::move(mesh));
  scene.instances.push_back(MeshInstance{int(scene.primitives.size()) - 1, Mat4(1.0f), name});
  GltfMaterial m;
  m.name = name;
  scene.materials.push_back(m);
}

// Binds each entry of `texFile` to the glTF material of the same name.
inline void bindEntriesByMaterialName(SceneDescription& scene, const std::string& texFile,
                                      const std::vector<std::string>& entries) {
  for (const std::string& e : entries) {
    TexMaterialBinding b;
    b.file = texFile;
    b.entry = e;
    b.matchMaterial = e;
    scene.texMaterials.push_back(b);
  }
}

// A square-film camera at `eye` looking down -z.
inline CameraDesc cameraLookingDownZ(Vec3 eye, float yFovRadians) {
  CameraDesc c;
  c.cameraToWorld = Mat4(1.0f);
  c.cameraToWorld[3] = Vec4(eye, 1.0f);
  c.yFovRadians = yFovRadians;
  c.aspect = 1.0f;
  return c;
}

// One primitive whose material ("surface") is the .tex entry, seen by cameraLookingDownZ(eye).
inline SceneDescription oneObjectScene(MeshPrimitive prim, const std::string& texFile, const std::string& entry, Vec3 eye,
                                       float yFovRadians = 0.9f) {
  SceneDescription s;
  prim.material = 0;
  s.primitives.push_back(std::move(prim));
  s.instances.push_back(MeshInstance{0, Mat4(1.0f), "object"});
  GltfMaterial m;
  m.name = "surface";
  s.materials.push_back(m);
  TexMaterialBinding b;
  b.file = texFile;
  b.entry = entry;
  b.matchMaterial = "surface";
  s.texMaterials.push_back(b);
  s.cameras.push_back(cameraLookingDownZ(eye, yFovRadians));
  return s;
}

// A constant environment of radiance `value` at every wavelength.
inline LightDesc constantSky(float value) {
  LightDesc sky;
  sky.kind = LightDesc::Kind::ConstantEnvironment;
  sky.emission.kind = SpectrumDesc::Kind::Constant;
  sky.emission.value = value;
  return sky;
}

}  // namespace tex::render::test
