// One entry point for scene files: glTF (.gltf, .glb) or scene JSON (.json), by extension.
#pragma once
#include <optional>
#include <string>

#include "renderer/scene/scene_description.h"

namespace tex::render {

// Loads a scene; on failure returns nullopt and `error` holds every message, one per line,
// each naming the file (and line:column for JSON).
std::optional<SceneDescription> loadScene(const std::string& path, std::string& error);

struct Bounds3 {
  Vec3 lower{kInfinity}, upper{-kInfinity};
  bool empty() const { return !(lower.x <= upper.x && lower.y <= upper.y && lower.z <= upper.z); }
  void extend(const Vec3& p) {
    lower = glm::min(lower, p);
    upper = glm::max(upper, p);
  }
};

// World-space axis-aligned bounds of every instance's vertices that triangles use (empty
// bounds for a scene without geometry).
Bounds3 worldBounds(const SceneDescription& scene);

}  // namespace tex::render
