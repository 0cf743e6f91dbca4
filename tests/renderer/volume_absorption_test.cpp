// KHR_materials_volume absorption: looking straight through an index-matched (ior 1) cube of
// side d with attenuationColor c and attenuationDistance D under a sky of radiance 1 gives, at
// every wavelength, the transmittance c(lambda)^(d / D) (Beer-Lambert with the glTF extension's
// parametrisation; c upsampled as a reflectance spectrum). Whatever ends a segment inside a
// volume (a surface inside it, a lamp), the segment is absorbed, and so are shadow rays.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <functional>
#include <tuple>

#include "renderer/color/wavelengths.h"
#include "renderer/integrators/path_tracer.h"
#include "renderer/integrators/render_scene.h"
#include "renderer/scene/shapes.h"
#include "renderer/spectra/rgb_spectrum.h"
#include "tests/renderer/radiance_estimate.h"
#include "tests/renderer/scene_fixtures.h"

namespace tex::render {
namespace {

// An index-matched (ior 1) absorbing cube of the given side around the origin, material 0 of
// the scene.
SceneDescription absorbingCube(float side, float distance, const Vec3& colour) {
  SceneDescription scene;
  MeshPrimitive cube = makeBox(Vec3(0.0f), Vec3(side), false);
  cube.material = 0;
  scene.primitives.push_back(cube);
  scene.instances.push_back(MeshInstance{0, Mat4(1.0f), "cube"});
  GltfMaterial volume;
  volume.transmissionFactor = 1.0f;
  volume.metallicFactor = 0.0f;
  volume.ior = 1.0f;
  volume.thicknessFactor = 1.0f;
  volume.attenuationDistance = distance;
  volume.attenuationColor = colour;
  scene.materials.push_back(volume);
  return scene;
}

// Worst difference over samples and wavelengths between the radiance estimate and
// expected(lambda) for the scene's first pixels' samples.
double worstDifference(const SceneDescription& scene, int maxDepth, const std::function<float(const Wavelengths&)>& expected) {
  RenderSceneOptions o;
  o.useCache = false;
  std::string error;
  std::unique_ptr<RenderScene> rs = RenderScene::build(scene, o, error);
  EXPECT_TRUE(rs) << error;
  if (!rs) return 1e30;
  PathTracerSettings settings;
  settings.maxDepth = maxDepth;
  const PathTracer tracer(*rs, sampling::Sampler(sampling::SamplerKind::Sobol, 1), settings);
  double worst = 0;
  for (uint64_t i = 0; i < 2000; ++i) {
    const SampleRecord r = tracer.record(i);
    for (int j = 0; j < r.wavelengthCount; ++j) {
      Wavelengths one;
      one.count = 1;
      one.lambdaNm[0] = r.lambdaNm[j];
      const float measured = r.values[j] * color::visibleWavelengthPdf(r.lambdaNm[j]);
      worst = std::max(worst, double(std::fabs(measured - expected(one))));
    }
  }
  return worst;
}

TEST(VolumeAbsorption, StraightThroughAnIndexMatchedCubeIsCToTheDOverD) {
  const float side = 2.0f, distance = 0.8f;
  const Vec3 colour(0.2f, 0.5f, 0.9f);
  SceneDescription scene = absorbingCube(side, distance, colour);
  scene.lights.push_back(test::constantSky(1.0f));
  // Nearly parallel rays from far away: every path length is the cube's side.
  scene.cameras.push_back(test::cameraLookingDownZ(Vec3(0.0f, 0.0f, 100.0f), 0.005f));
  const double worst = worstDifference(scene, PathTracerSettings().maxDepth, [&](const Wavelengths& one) {
    return std::pow(rgbReflectanceSpectrum(colour, one).v[0], side / distance);
  });
  EXPECT_LT(worst, 2e-4);
}

// An absorbing index-matched cube of side 2 around the origin (material 0) and, inside it, a
// white Lambertian square at z = 0 (a .tex material) lit by a point light at (0, 0, 0.5), seen
// from far above: camera rays cross 1 unit of the volume to the square and shadow rays 0.5.
// Until round 16 only a segment that ended on the back of a volume was absorbed, by that volume
// (here the camera segment ends on the square's front: it was not absorbed at all, and shadow
// rays never were).
// A 0.6 x 0.6 slab whose top face is the square at z = 0.
MeshPrimitive squareAtZ0() { return makeBox(Vec3(0.0f, 0.0f, -0.05f), Vec3(0.6f, 0.6f, 0.1f), false); }

SceneDescription squareInsideAVolume(float distance, const Vec3& colour, bool emissiveSquare) {
  SceneDescription scene = absorbingCube(2.0f, distance, colour);
  test::addNamedMesh(scene, "surface", squareAtZ0());
  TexMaterialBinding b;
  b.file = test::writeTexModule("inside_volume", "export fn white(h: Hit) -> Material = diffuse(spectrum(1.0))\n"
                                                 "export fn glow(h: Hit) -> Material = emission(spectrum(1.0))\n");
  b.entry = emissiveSquare ? "glow" : "white";
  b.matchMaterial = "surface";
  scene.texMaterials.push_back(b);
  scene.cameras.push_back(test::cameraLookingDownZ(Vec3(0.0f, 0.0f, 100.0f), 0.0005f));
  return scene;
}

TEST(VolumeAbsorption, AnEmitterInsideAVolumeIsSeenThroughIt) {
  const Vec3 colour(0.2f, 0.5f, 0.9f);
  const float distance = 0.8f;
  const SceneDescription scene = squareInsideAVolume(distance, colour, true);
  // Depth 1: the index-matched surface is a (straight-through) scattering event.
  const double worst = worstDifference(scene, 1, [&](const Wavelengths& one) {
    return std::pow(rgbReflectanceSpectrum(colour, one).v[0], 1.0f / distance);  // 1 unit to the square
  });
  EXPECT_LT(worst, 2e-4);
}

TEST(VolumeAbsorption, ShadowRaysInsideAVolumeAreAbsorbed) {
  const Vec3 colour(0.3f, 0.6f, 0.8f);
  const float distance = 1.5f, intensity = 2.0f;
  SceneDescription scene = squareInsideAVolume(distance, colour, false);
  LightDesc point;
  point.kind = LightDesc::Kind::Point;
  point.position = Vec3(0.0f, 0.0f, 0.5f);
  point.emission.kind = SpectrumDesc::Kind::Constant;
  point.emission.value = 1.0f;
  point.intensity = intensity;
  scene.lights.push_back(point);
  // Direct light only (depth 2: the cube's surface, then the square): L = (1 / pi) I / r^2 (r = 0.5, normal incidence) through 0.5 units on
  // the way in and 1 unit on the way out. The pixel sees points within 0.025 of the axis:
  // r^2 varies by 0.25 %.
  const double worst = worstDifference(scene, 2, [&](const Wavelengths& one) {
    const float c = rgbReflectanceSpectrum(colour, one).v[0];
    return float(intensity / 0.25 / M_PI) * std::pow(c, 1.5f / distance);
  });
  EXPECT_LT(worst, 0.01 * intensity / 0.25 / M_PI);
}

// Head-on through boxes of glass over a lamp of radiance 1 (seen from far above): what the
// path tracer gives, with boxes given as (centre z, height, material index) and glTF solid
// materials of the IORs given.
double headOnThroughBoxes(const std::vector<std::tuple<float, float, int>>& boxes, const std::vector<float>& iors,
                          float roughness = 0.0f, float attenuationDistance = INFINITY, bool pointLightInside = false) {
  SceneDescription scene;
  for (const float ior : iors) {
    GltfMaterial glass;
    glass.transmissionFactor = 1.0f;
    glass.metallicFactor = 0.0f;
    glass.roughnessFactor = roughness;
    glass.ior = ior;
    glass.thicknessFactor = 1.0f;
    glass.attenuationDistance = attenuationDistance;
    glass.attenuationColor = Vec3(0.1f);
    scene.materials.push_back(glass);
  }
  for (const auto& [z, height, material] : boxes) {
    MeshPrimitive box = makeBox(Vec3(0.0f, 0.0f, z), Vec3(4.0f - height, 4.0f - height, height), false);
    box.material = material;
    scene.primitives.push_back(box);
    scene.instances.push_back(MeshInstance{int(scene.primitives.size()) - 1, Mat4(1.0f), "box"});
  }
  if (pointLightInside) {
    LightDesc point;
    point.kind = LightDesc::Kind::Point;
    point.position = Vec3(0.0f);
    point.emission.kind = SpectrumDesc::Kind::Constant;
    point.emission.value = 1.0f;
    scene.lights.push_back(point);
  } else {
    MeshPrimitive lamp = makeQuad(Vec3(-5.0f, -5.0f, -3.0f), Vec3(10.0f, 0.0f, 0.0f), Vec3(0.0f, 10.0f, 0.0f));
    lamp.material = int(scene.materials.size());
    scene.primitives.push_back(lamp);
    scene.instances.push_back(MeshInstance{int(scene.primitives.size()) - 1, Mat4(1.0f), "lamp"});
    GltfMaterial lampMaterial;
    lampMaterial.name = "lamp";
    scene.materials.push_back(lampMaterial);
    test::bindEntriesByMaterialName(scene, test::writeTexModule("boxes_lamp", "export fn lamp(h: Hit) -> Material = emission(spectrum(1.0))\n"),
                                    {"lamp"});
  }
  scene.cameras.push_back(test::cameraLookingDownZ(Vec3(0.0f, 0.0f, 100.0f), pointLightInside ? 0.02f : 0.0005f));
  return test::estimateRadiance(scene, 100, 4, 1 << 14, sampling::SamplerKind::Sobol, 100).mean;
}

// Incoherent transmittance of a stack of interfaces head-on (reflections between them summed).
double stackTransmittance(const std::vector<std::pair<double, double>>& interfaces) {
  double r = 0.0, t = 1.0;
  for (const auto& [n1, n2] : interfaces) {
    const double ri = (n1 - n2) * (n1 - n2) / ((n1 + n2) * (n1 + n2)), ti = 1.0 - ri;
    const double denominator = 1.0 - r * ri;
    r = r + t * t * ri / denominator;
    t = t * ti / denominator;
  }
  return t;
}

// Surfaces inside a volume meet its medium, not air (Bsdf::immerse): a glass block inside a
// glass block of the same IOR is invisible, as is a block nested in one of its own material,
// and water overlapping glass (the one entered last holds the overlap) has the interfaces air |
// water | glass | air. The inner surfaces had been taken as glass against air.
TEST(VolumeAbsorption, InterfacesInsideAVolumeAreRelativeToItsMedium) {
  const double oneSlab = stackTransmittance({{1.0, 1.5}, {1.5, 1.0}});
  EXPECT_NEAR(headOnThroughBoxes({{0.0f, 2.0f, 0}, {0.0f, 1.0f, 1}}, {1.5f, 1.5f}), oneSlab, 2e-3);
  EXPECT_NEAR(headOnThroughBoxes({{0.0f, 2.0f, 0}, {0.0f, 1.0f, 0}}, {1.5f}), oneSlab, 2e-3);  // the same material
  // Water from z = -0.5 to 1.5 over glass from -1 to 1: entered first, so the glass holds the overlap.
  EXPECT_NEAR(headOnThroughBoxes({{0.0f, 2.0f, 0}, {0.5f, 2.0f, 1}}, {1.5f, 1.33f}),
              stackTransmittance({{1.0, 1.33}, {1.33, 1.5}, {1.5, 1.0}}), 2e-3);
}

// Light sampling from outside an absorbing volume, through its rough surface, to a point light
// inside it is absorbed (it was not: a nearly opaque box glowed at 0.46 of a clear one).
TEST(VolumeAbsorption, LightSamplesIntoAVolumeThroughItsRoughSurfaceAreAbsorbed) {
  const double clear = headOnThroughBoxes({{0.0f, 2.0f, 0}}, {1.5f}, 0.5f, INFINITY, true);
  const double dark = headOnThroughBoxes({{0.0f, 2.0f, 0}}, {1.5f}, 0.5f, 0.05f, true);  // 0.1 per 0.05 units
  EXPECT_GT(clear, 0.01);
  EXPECT_LT(dark, 1e-6 * clear);
}


// A camera inside volumes starts inside them: inside an absorbing cube of side 4 (material 0)
// and a smaller one of side 2 within it (material 1, the innermost), 0.9 above an emitting
// square, its rays are absorbed by the inner cube's medium over those 0.9 units. Paths had
// started in no volume: the camera segment, ending on the square's front, was not absorbed.
// With the inner cube beside the camera instead, only the outer one absorbs.
TEST(VolumeAbsorption, ACameraInsideVolumesStartsInThem) {
  const Vec3 outerColour(0.2f, 0.5f, 0.9f), innerColour(0.7f, 0.4f, 0.3f);
  const float outerDistance = 0.8f, innerDistance = 1.3f;
  for (const bool cameraInInner : {true, false}) {
    SceneDescription scene = absorbingCube(4.0f, outerDistance, outerColour);
    MeshPrimitive inner = makeBox(cameraInInner ? Vec3(0.0f) : Vec3(3.0f, 0.0f, 0.0f), Vec3(2.0f), false);
    inner.material = 1;
    scene.primitives.push_back(inner);
    scene.instances.push_back(MeshInstance{1, Mat4(1.0f), "inner"});
    GltfMaterial innerVolume = scene.materials[0];
    innerVolume.attenuationDistance = innerDistance;
    innerVolume.attenuationColor = innerColour;
    scene.materials.push_back(innerVolume);
    test::addNamedMesh(scene, "glow", squareAtZ0());
    test::bindEntriesByMaterialName(scene, test::writeTexModule("camera_in_volume", "export fn glow(h: Hit) -> Material = emission(spectrum(1.0))\n"),
                                    {"glow"});
    scene.cameras.push_back(test::cameraLookingDownZ(Vec3(0.0f, 0.0f, 0.9f), 0.0005f));
    const double worst = worstDifference(scene, 1, [&](const Wavelengths& one) {
      const float c = rgbReflectanceSpectrum(cameraInInner ? innerColour : outerColour, one).v[0];
      return std::pow(c, 0.9f / (cameraInInner ? innerDistance : outerDistance));
    });
    EXPECT_LT(worst, 2e-4) << (cameraInInner ? "inside the inner cube" : "beside the inner cube");
  }
}

// A sea modelled as an open plane (z = 0, facing up) of absorbing glTF volume over a lamp at
// z = -0.5: a camera above it starts in air (its rays are absorbed over the 0.5 units below the
// surface), one below it in the sea (over the 0.3 units to the lamp). The scene is built with
// z up, then also turned so that y is up (glTF's convention): there, counting crossings had put
// the camera above the plane inside the sea as well (two of the three rays going down cross it
// once).
TEST(VolumeAbsorption, AnOpenSeaHoldsACameraBelowItNotAbove) {
  const Vec3 colour(0.3f, 0.6f, 0.8f);
  const float distance = 0.7f;
  for (const auto& [yUp, below] : {std::pair{false, false}, std::pair{false, true}, std::pair{true, false}, std::pair{true, true}}) {
    SceneDescription scene = absorbingCube(1.0f, distance, colour);
    scene.primitives[0] = makeQuad(Vec3(-50.0f, -50.0f, 0.0f), Vec3(100.0f, 0.0f, 0.0f), Vec3(0.0f, 100.0f, 0.0f));
    scene.primitives[0].material = 0;
    test::addNamedMesh(scene, "glow", makeBox(Vec3(0.0f, 0.0f, -0.55f), Vec3(0.6f, 0.6f, 0.1f), false));  // top face at z = -0.5
    test::bindEntriesByMaterialName(scene, test::writeTexModule("open_sea", "export fn glow(h: Hit) -> Material = emission(spectrum(1.0))\n"),
                                    {"glow"});
    scene.cameras.push_back(test::cameraLookingDownZ(Vec3(0.0f, 0.0f, below ? -0.2f : 1.0f), 0.0005f));
    if (yUp) {  // +z to +y
      const Mat4 turn = glm::rotate(Mat4(1.0f), -float(M_PI) / 2.0f, Vec3(1.0f, 0.0f, 0.0f));
      for (MeshInstance& instance : scene.instances) instance.objectToWorld = turn * instance.objectToWorld;
      scene.cameras.back().cameraToWorld = turn * scene.cameras.back().cameraToWorld;
    }
    const double worst = worstDifference(scene, 2, [&](const Wavelengths& one) {
      return std::pow(rgbReflectanceSpectrum(colour, one).v[0], (below ? 0.3f : 0.5f) / distance);
    });
    EXPECT_LT(worst, 2e-4) << (below ? "below" : "above") << (yUp ? ", y up" : ", z up");
  }
}

// A camera exactly on the top face of an absorbing cube (side 2), looking down at a lamp below
// the cube: looking in (on the top face) its rays cross the 2 units of the cube, c^(2 / D);
// looking out (on the bottom face) none, 1. With the three rays alone, the camera on the top
// face was inside the cube and its rays then entered it again: the whole way to the lamp was
// absorbed (a hunt's finding).
TEST(VolumeAbsorption, ACameraOnAVolumesSurfaceStartsOnTheSideItsRaysCross) {
  const Vec3 colour(0.5f);
  const float distance = 1.0f;
  for (const bool lookingIn : {true, false}) {
    SceneDescription scene = absorbingCube(2.0f, distance, colour);
    test::addNamedMesh(scene, "glow", makeQuad(Vec3(-20.0f, -20.0f, -10.0f), Vec3(40.0f, 0.0f, 0.0f), Vec3(0.0f, 40.0f, 0.0f)));
    test::bindEntriesByMaterialName(scene, test::writeTexModule("on_face", "export fn glow(h: Hit) -> Material = emission(spectrum(1.0))\n"),
                                    {"glow"});
    scene.cameras.push_back(test::cameraLookingDownZ(Vec3(0.0f, 0.0f, lookingIn ? 1.0f : -1.0f), 0.0005f));
    const double worst = worstDifference(scene, 3, [&](const Wavelengths& one) {
      return lookingIn ? std::pow(rgbReflectanceSpectrum(colour, one).v[0], 2.0f / distance) : 1.0f;
    });
    EXPECT_LT(worst, 2e-4) << (lookingIn ? "looking in" : "looking out");
  }
}

}  // namespace
}  // namespace tex::render
