// The scene JSON format (docs/scene-format.md): glTF files with transforms, inline shapes,
// .tex material bindings, cameras, lights and render settings. Errors name the scene file
// with line:column and say what is wrong.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "renderer/scene/scene_description.h"

namespace tex::render {

std::optional<SceneDescription> loadSceneJson(const std::string& path, std::vector<std::string>& errors);

// The same from text already in memory; relative paths resolve against `baseDirectory`,
// messages name `displayName`.
std::optional<SceneDescription> parseSceneJson(const std::string& text, const std::string& displayName,
                                               const std::string& baseDirectory, std::vector<std::string>& errors);

}  // namespace tex::render
