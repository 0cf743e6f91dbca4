// glTF 2.0 (.gltf, .glb) to SceneDescription, through tinygltf 2.7 plus our own validation:
// a broken or hostile file gives error messages naming the file and the problem, never a
// crash; recoverable problems (a missing image, an unsupported extension) become warnings in
// SceneDescription::warnings. See docs/scene-format.md for units and conventions.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "renderer/scene/scene_description.h"

namespace tex::render {

// Loads one glTF file: the default scene's (or scene 0's) node tree becomes instances of
// shared primitives, with its materials, images, perspective cameras and punctual lights.
std::optional<SceneDescription> loadGltf(const std::string& path, std::vector<std::string>& errors);

// Appends a glTF file to `scene` with every node placed under `transform` (scene JSON files
// combine several). On error returns false and leaves `scene` unchanged.
bool appendGltf(const std::string& path, const Mat4& transform, SceneDescription& scene,
                std::vector<std::string>& errors);

}  // namespace tex::render
