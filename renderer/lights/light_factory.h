// Lights from a scene file's LightDesc (punctual and environment lights; emissive triangles
// come from meshes, see triangle_light.h).
#pragma once
#include <memory>
#include <string>

#include "renderer/lights/light.h"
#include "renderer/scene/scene_description.h"

namespace tex::render {

// The emission spectrum is desc.emission (upsampled as an illuminant) times desc.intensity:
// W/sr for point and spot lights, irradiance for directional lights, radiance for the constant
// environment. An image environment is its EXR's pixels times desc.intensity. On failure
// (unreadable EXR) returns nullptr and an error that names the light and the file.
std::unique_ptr<Light> makeLight(const LightDesc& desc, std::string& error);

}  // namespace tex::render
