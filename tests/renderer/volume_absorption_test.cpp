// KHR_materials_volume absorption: looking straight through an index-matched (ior 1) cube of
// side d with attenuationColor c and attenuationDistance D under a sky of radiance 1 gives, at
// every wavelength, the transmittance c(lambda)^(d / D) (Beer-Lambert with the glTF extension's
// parametrisation; c upsampled as a reflectance spectrum).
#include <gtest/gtest.h>

#include <cmath>

#include "renderer/color/wavelengths.h"
#include "renderer/integrators/path_tracer.h"
#include "renderer/integrators/render_scene.h"
#include "renderer/scene/shapes.h"
#include "renderer/spectra/rgb_spectrum.h"
#include "tests/renderer/scene_fixtures.h"

namespace tex::render {
namespace {

TEST(VolumeAbsorption, StraightThroughAnIndexMatchedCubeIsCToTheDOverD) {
  const float side = 2.0f, distance = 0.8f;
  const Vec3 colour(0.2f, 0.5f, 0.9f);
  SceneDescription scene;
  MeshPrimitive cube = makeBox(Vec3(0.0f), Vec3(side), false);
  cube.material = 0;
  scene.primitives.push_back(cube);
  scene.instances.push_back(MeshInstance{0, Mat4(1.0f), "cube"});
  GltfMaterial m;
  m.transmissionFactor = 1.0f;
  m.metallicFactor = 0.0f;
  m.ior = 1.0f;
  m.thicknessFactor = 1.0f;
  m.attenuationDistance = distance;
  m.attenuationColor = colour;
  scene.materials.push_back(m);
  scene.lights.push_back(test::constantSky(1.0f));
  // Nearly parallel rays from far away: every path length is the cube's side.
  scene.cameras.push_back(test::cameraLookingDownZ(Vec3(0.0f, 0.0f, 100.0f), 0.005f));

  RenderSceneOptions o;
  std::string error;
  std::unique_ptr<RenderScene> rs = RenderScene::build(scene, o, error);
  ASSERT_TRUE(rs) << error;
  const PathTracer tracer(*rs, sampling::Sampler(sampling::SamplerKind::Sobol, 1), PathTracerSettings{});
  double worst = 0;
  for (uint64_t i = 0; i < 2000; ++i) {
    const SampleRecord r = tracer.record(i);
    for (int j = 0; j < r.wavelengthCount; ++j) {
      Wavelengths one;
      one.count = 1;
      one.lambdaNm[0] = r.lambdaNm[j];
      const float expected = std::pow(rgbReflectanceSpectrum(colour, one).v[0], side / distance);
      const float measured = r.values[j] * color::visibleWavelengthPdf(r.lambdaNm[j]);
      worst = std::max(worst, double(std::fabs(measured - expected)));
    }
  }
  EXPECT_LT(worst, 2e-4);
}

}  // namespace
}  // namespace tex::render
