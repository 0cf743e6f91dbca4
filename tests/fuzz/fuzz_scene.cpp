// libFuzzer target over the scene loaders (renderer/scene/): glTF 2.0 binary and JSON files
// (tinygltf plus our checked accessors, materials, images, cameras, lights) and scene JSON
// files. The first byte picks the format; the rest is written to a file with the matching
// extension and loaded. Any input must give a scene or errors, never a crash, a hang or a
// sanitizer report.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <string>

#include "renderer/scene/load_scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  static const char* kExtensions[] = {".glb", ".gltf", ".json"};
  const std::string path = "/tmp/tex_fuzz_scene_" + std::to_string(::getpid()) + kExtensions[data[0] % 3];
  if (FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(data + 1, 1, size - 1, f);
    std::fclose(f);
  } else {
    return 0;
  }
  std::string error;
  std::optional<tex::render::SceneDescription> scene = tex::render::loadScene(path, error);
  if (scene) (void)tex::render::worldBounds(*scene);
  std::remove(path.c_str());
  return 0;
}
