#include "renderer/lights/light_factory.h"

#include "renderer/lights/constant_environment.h"
#include "renderer/lights/directional_light.h"
#include "renderer/lights/image_environment.h"
#include "renderer/lights/point_light.h"
#include "renderer/lights/spot_light.h"
#include "renderer/spectra/spectrum_desc.h"

namespace tex::render {

std::unique_ptr<Light> makeLight(const LightDesc& desc, std::string& error) {
  error.clear();
  SpectrumDesc emission = desc.emission;
  emission.scale *= desc.intensity;
  SpectrumSource spectrum;
  try {
    spectrum = SpectrumSource(emission, SpectrumUse::Illuminant);
  } catch (const std::exception& e) {
    error = "light '" + desc.name + "': " + e.what();
    return nullptr;
  }
  switch (desc.kind) {
    case LightDesc::Kind::Point:
      return makePointLight(desc.position, spectrum);
    case LightDesc::Kind::Spot:
      return makeSpotLight(desc.position, desc.direction, spectrum, desc.innerConeRadians, desc.outerConeRadians);
    case LightDesc::Kind::Directional:
      return makeDirectionalLight(desc.direction, spectrum);
    case LightDesc::Kind::ConstantEnvironment:
      return makeConstantEnvironment(spectrum);
    case LightDesc::Kind::ImageEnvironment: {
      std::unique_ptr<Light> light = loadImageEnvironment(desc.imagePath, desc.environmentToWorld, desc.intensity, error);
      if (!light) error = "light '" + desc.name + "': " + error;
      return light;
    }
  }
  error = "light '" + desc.name + "': unknown kind";
  return nullptr;
}

}  // namespace tex::render
