#include "renderer/lights/light_factory.h"

#include <cmath>

#include "renderer/lights/constant_environment.h"
#include "renderer/lights/directional_light.h"
#include "renderer/lights/image_environment.h"
#include "renderer/lights/point_light.h"
#include "renderer/lights/spot_light.h"
#include "renderer/spectra/spectrum_desc.h"

namespace tex::render {

std::unique_ptr<Light> makeLight(const LightDesc& desc, std::string& error) {
  error.clear();
  // Where the light is: the scene file's line and column when it came from one.
  const std::string what = (desc.origin.empty() ? std::string() : desc.origin + ": ") + "light" +
                           (desc.name.empty() ? std::string() : " '" + desc.name + "'");
  SpectrumDesc emission = desc.emission;
  emission.scale *= desc.intensity;
  SpectrumSource spectrum;
  try {
    spectrum = SpectrumSource(emission, SpectrumUse::Illuminant);
  } catch (const std::exception& e) {
    error = what + ": " + e.what();
    return nullptr;
  }
  // The radiance must stay a float at every wavelength: beyond it every sample of the light
  // was infinite and zeroed (a black image, exit 0).
  bool finite = std::isfinite(spectrum.luminance());
  for (float lambdaNm = 360.0f; finite && lambdaNm <= 830.0f; lambdaNm += 1.0f) finite = std::isfinite(spectrum.at(lambdaNm));
  if (!finite) {
    error = what + ": its intensity times its emission overflows a 32-bit float";
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
      if (!light) error = what + ": " + error;
      return light;
    }
  }
  error = what + ": unknown kind";
  return nullptr;
}

}  // namespace tex::render
