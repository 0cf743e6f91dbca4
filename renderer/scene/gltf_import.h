// Internal to the glTF loader: the state of importing one glTF file into a SceneDescription
// (index maps from the file's arrays to the scene's, warnings prefixed with the file name).
#pragma once
#include <map>
#include <set>
#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "renderer/scene/scene_description.h"

namespace tex::render {

// Images decoded by the tinygltf image callback, by glTF image index (see gltf_images.h).
struct DecodedImages {
  const tinygltf::Model* model = nullptr;  // buffer views are parsed before images
  std::map<int, ImageData> byIndex;
  std::map<int, std::string> failures;  // why an image has no pixels
};

struct GltfImport {
  const tinygltf::Model& model;
  std::string file;  // as given, for messages
  SceneDescription& scene;
  std::vector<int> sceneImage;     // glTF image -> scene image, -1 when it has no pixels
  int materialOffset = 0;          // glTF material m -> scene material m + materialOffset
  std::set<std::string> warnedOnce;
  int defaultMaterial = -1;        // the spec's default material, added on first need (last: the
                                   // loader brace-initialises the members above)

  // glTF 2.0 section 3.9.6: a primitive without a material (or, after a warning, with one that
  // does not exist) has "a material with no properties specified": base colour 1, metallic 1,
  // roughness 1 (a rough white metal that COLOR_0 tints), as GltfMaterial's defaults are.
  int defaultMaterialIndex() {
    if (defaultMaterial < 0) {
      GltfMaterial m;
      m.name = "(glTF default material)";
      defaultMaterial = int(scene.materials.size());
      scene.materials.push_back(m);
    }
    return defaultMaterial;
  }

  void warn(const std::string& message) { scene.warnings.push_back(file + ": " + message); }
  void warnOnce(const std::string& key, const std::string& message) {
    if (warnedOnce.insert(key).second) warn(message);
  }
};

// Moves decoded images into the scene and fills import.sceneImage.
void importImages(GltfImport& import, DecodedImages& decoded);

// Appends the file's materials (pbrMetallicRoughness and the extensions we read) to the scene.
void importMaterials(GltfImport& import);

}  // namespace tex::render
