// The path tracer against scenes whose answer is known:
//  - a closed cavity whose walls emit Le and reflect diffusely with albedo rho has radiance
//    Le / (1 - rho) everywhere, whatever its shape (uniform radiance L gives irradiance pi L);
//  - a point light of intensity I at the centre of a diffuse sphere of radius R and albedo rho
//    gives radiance rho I / (pi R^2 (1 - rho)) everywhere (radiosity of a sphere's interior);
//  - white furnace: a lossless object under a uniform sky has the sky's radiance everywhere,
//    including a dispersive glass (hero-wavelength termination is unbiased);
// and determinism: 1 and 2 threads give bit-identical films.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <tuple>

#include <glm/gtc/matrix_transform.hpp>

#include "renderer/color/wavelengths.h"
#include "renderer/film/film_sink.h"
#include "renderer/integrators/path_tracer.h"
#include "renderer/integrators/render_scene.h"
#include "renderer/scene/shapes.h"
#include "tests/renderer/radiance_estimate.h"
#include "tests/renderer/scene_fixtures.h"
#include "runtime/stream.h"

namespace tex::render {
namespace {

using test::constantSky;
using test::Estimate;
using test::estimateRadiance;
using test::oneObjectScene;
using test::writeTexModule;

TEST(PathTracer, EmittingDiffuseCavityHasRadianceLeOverOneMinusAlbedo) {
  // Walls: 0.5 diffuse + 0.5 emission -> L = 0.5 / (1 - 0.5) = 1 (exact for any closed shape).
  const std::string file = writeTexModule(
      "cavity", "export fn wall(h: Hit) -> Material = mix_material(diffuse(spectrum(1.0)), emission(spectrum(1.0)), 0.5)\n");
  const SceneDescription scene = oneObjectScene(makeSphere(Vec3(0.0f), 1.0f, 48, 24, true), file, "wall", Vec3(0.0f));
  for (sampling::SamplerKind sampler : {sampling::SamplerKind::Sobol, sampling::SamplerKind::Random})
    for (int wavelengths : {4, 8}) {
      const Estimate e = estimateRadiance(scene, 60, wavelengths, 1 << 16, sampler);
      EXPECT_NEAR(e.mean, 1.0, 4 * e.standardError + 1e-6) << wavelengths << " wavelengths, " << samplerName(sampler);
      EXPECT_EQ(e.nonFinite, 0u);
    }
}

// Russian roulette trades work for noise, never the answer: starting it after the first
// scattering event or not before the depth limit both give the cavity's exact radiance, and
// the later it starts, the more rays a path traces.
TEST(PathTracer, RouletteDepthChangesTheWorkNotTheAnswer) {
  const std::string file = writeTexModule(
      "cavity_rr", "export fn wall(h: Hit) -> Material = mix_material(diffuse(spectrum(1.0)), emission(spectrum(1.0)), 0.5)\n");
  // Flat facets: interpolated shading normals on a polyhedron lose the directions that would
  // cross the geometric surface (a deliberate leak guard), about 0.1% here, which only the
  // roulette-free run is precise enough to see.
  MeshPrimitive sphere = makeSphere(Vec3(0.0f), 1.0f, 48, 24, true);
  sphere.normals.clear();
  const SceneDescription scene = oneObjectScene(std::move(sphere), file, "wall", Vec3(0.0f));
  uint64_t previousRays = 0;
  for (int rouletteDepth : {1, 3, 5, 40}) {
    const Estimate e = estimateRadiance(scene, 40, 4, 1 << 15, sampling::SamplerKind::Sobol, rouletteDepth);
    // Without roulette the depth limit cuts 0.5^40 of the radiance: far below the noise.
    EXPECT_NEAR(e.mean, 1.0, 4 * e.standardError + 1e-6) << "roulette after " << rouletteDepth;
    EXPECT_GT(e.rays, previousRays) << "roulette after " << rouletteDepth;
    previousRays = e.rays;
  }
}

TEST(PathTracer, PointLightInsideDiffuseSphereGivesRadianceOne) {
  const std::string file = writeTexModule("sphere_wall", "export fn wall(h: Hit) -> Material = diffuse(spectrum(0.5))\n");
  SceneDescription scene = oneObjectScene(makeSphere(Vec3(0.0f), 1.0f, 128, 64, true), file, "wall", Vec3(0.0f, 0.0f, 0.3f));
  LightDesc light;
  light.kind = LightDesc::Kind::Point;
  light.position = Vec3(0.0f);
  light.emission.kind = SpectrumDesc::Kind::Constant;
  light.emission.value = 1.0f;
  light.intensity = kPi;  // rho I / (pi R^2 (1 - rho)) = 1 for rho = 0.5, R = 1
  scene.lights.push_back(light);
  // The sphere is a 128 x 64 polyhedron: its facets are up to (pi/64)^2 / 2 = 0.12% closer to
  // the light than the sphere, hence the 0.3% allowance on top of the noise.
  for (sampling::SamplerKind sampler : {sampling::SamplerKind::Sobol, sampling::SamplerKind::Random}) {
    const Estimate e = estimateRadiance(scene, 60, 4, 1 << 16, sampler);
    EXPECT_NEAR(e.mean, 1.0, 4 * e.standardError + 0.003) << samplerName(sampler);
    EXPECT_EQ(e.nonFinite, 0u);
  }
}

// Far from the origin the cavity still gives Le / (1 - rho): ray origins move off a surface by
// its points' float error, not by a fixed fraction of |p| (at 1e-4 |p| they were 1.5 units away
// here, outside the unit sphere: 0.90 instead of 1). At 3e4 the sphere's float precision itself
// (ulp 0.004) costs about 1 %.
TEST(PathTracer, ClosedCavityFarFromTheOriginKeepsItsRadiance) {
  const std::string file = writeTexModule(
      "cavity_far", "export fn wall(h: Hit) -> Material = mix_material(diffuse(spectrum(1.0)), emission(spectrum(1.0)), 0.5)\n");
  const Vec3 centre(1.0e4f, -5.0e3f, 1.5e4f);
  // Flat facets: vertex normals computed at these coordinates are off by their float error,
  // which the shading-normal leak guard would turn into a loss (as in the roulette test).
  MeshPrimitive sphere = makeSphere(centre, 1.0f, 48, 24, true);
  sphere.normals.clear();
  const SceneDescription scene = oneObjectScene(std::move(sphere), file, "wall", centre);
  const Estimate e = estimateRadiance(scene, 60, 4, 1 << 15);
  EXPECT_NEAR(e.mean, 1.0, 4 * e.standardError + 1e-6);
  EXPECT_EQ(e.nonFinite, 0u);
}

// A diffuse floor (material "floor", a 100 x 100 quad at z = 0 facing +z in a local frame)
// seen straight down by `camera` (local: cameraLookingDownZ or its orthographic variant), the
// whole scene moved rigidly by `toWorld`: tilted, so that no surface is axis-aligned, and far
// from the origin. The tests add lights in the local frame through toWorld.
struct FarFloor {
  Mat4 toWorld;
  Vec3 world(const Vec3& p) const { return Vec3(toWorld * Vec4(p, 1.0f)); }
  Vec3 worldVector(const Vec3& v) const { return Vec3(toWorld * Vec4(v, 0.0f)); }
  SceneDescription scene(const std::string& texFile, CameraDesc camera) const {
    SceneDescription s;
    MeshPrimitive floor = makeQuad(world(Vec3(-50.0f, -50.0f, 0.0f)), worldVector(Vec3(100.0f, 0.0f, 0.0f)),
                                   worldVector(Vec3(0.0f, 100.0f, 0.0f)));
    floor.material = 0;
    s.primitives = {floor};
    s.instances = {MeshInstance{0, Mat4(1.0f), "floor"}};
    s.materials.resize(1);
    s.materials[0].name = "floor";
    test::bindEntriesByMaterialName(s, texFile, {"floor"});
    camera.cameraToWorld = toWorld * camera.cameraToWorld;
    s.cameras.push_back(camera);
    return s;
  }
};

// A small lamp lighting a floor patch at a grazing angle (cosines about 0.13 at both ends),
// the scene tilted and placed thousands of units from the origin: the direct light (depth 1)
// is the lamp's irradiance integrated numerically, rho / pi x E. Shadow rays aim from their
// offset origin at the offset point on the lamp; along wi from the offset origin they crossed
// the lamp's own plane short of their end and the lamp shadowed itself (the patch came out
// black).
TEST(PathTracer, GrazingAreaLightFarFromTheOriginGivesTheAnalyticDirectLight) {
  const std::string file = writeTexModule("grazing",
                                          "export fn floor(h: Hit) -> Material = diffuse(spectrum(0.5))\n"
                                          "export fn lamp(h: Hit) -> Material = emission(spectrum(2000.0))\n");
  // Built in a local frame (floor z = 0 facing +z, lamp above it facing down, camera looking
  // down at the floor), then moved rigidly: a tilt, so that no surface is axis-aligned, and an
  // offset of thousands of units.
  const FarFloor frame{glm::rotate(glm::translate(Mat4(1.0f), Vec3(3000.0f, 1000.0f, -2000.0f)), 0.5f,
                                  glm::normalize(Vec3(1.0f, 1.0f, 0.3f)))};
  constexpr float kLampDistance = 20.0f, kLampHeight = 2.6f, kLampSize = 0.3f, kEyeHeight = 1.0f, kFov = 0.9f;
  SceneDescription scene = frame.scene(file, test::cameraLookingDownZ(Vec3(0.0f, 0.0f, kEyeHeight), kFov));
  const Vec3 lampCorner(-kLampDistance, -0.5f * kLampSize, kLampHeight);
  const Vec3 lampEdge1(0.0f, kLampSize, 0.0f), lampEdge2(kLampSize, 0.0f, 0.0f);  // facing -z, down
  MeshPrimitive lamp = makeQuad(frame.world(lampCorner), frame.worldVector(lampEdge1), frame.worldVector(lampEdge2));
  lamp.material = 1;
  scene.primitives.push_back(lamp);
  scene.instances.push_back(MeshInstance{1, Mat4(1.0f), "lamp"});
  scene.materials.resize(2);
  scene.materials[1].name = "lamp";
  test::bindEntriesByMaterialName(scene, file, {"lamp"});

  // The camera sees the square patch |x|, |y| <= h tan(fov / 2) of the floor, uniformly.
  const float half = kEyeHeight * std::tan(0.5f * kFov);
  double expected = 0;
  constexpr int kPatch = 24, kLamp = 24;
  for (int i = 0; i < kPatch; ++i)
    for (int j = 0; j < kPatch; ++j) {
      const Vec3 p(half * (2.0f * (i + 0.5f) / kPatch - 1.0f), half * (2.0f * (j + 0.5f) / kPatch - 1.0f), 0.0f);
      double irradiance = 0;
      for (int a = 0; a < kLamp; ++a)
        for (int b = 0; b < kLamp; ++b) {
          const Vec3 q = lampCorner + lampEdge1 * ((a + 0.5f) / kLamp) + lampEdge2 * ((b + 0.5f) / kLamp);
          const Vec3 d = q - p;
          const double dist2 = double(dot3(d, d)), cosine = double(d.z) / std::sqrt(dist2);  // both ends: d.z / |d|
          irradiance += 2000.0 * cosine * cosine / dist2 * (kLampSize * kLampSize) / (kLamp * kLamp);
        }
      expected += 0.5 / kPi * irradiance / (kPatch * kPatch);
    }
  const Estimate e = estimateRadiance(scene, 1, 4, 1 << 16);
  EXPECT_NEAR(e.mean, expected, 4 * e.standardError + 0.002 * expected) << "expected " << expected;
  EXPECT_GT(expected, 1e-3);
}

// Point, spot and directional lights over a diffuse floor, the scene tilted and thousands of
// units from the origin, seen straight down by an orthographic camera (every pixel a floor
// point, uniformly): the direct light (depth 1) is rho / pi times the analytic irradiance,
// averaged over the patch the camera sees (spot: glTF's quadratic falloff between the cones).
TEST(PathTracer, PunctualLightsFarFromTheOriginGiveTheAnalyticDirectLight) {
  const std::string file = writeTexModule("punctual", "export fn floor(h: Hit) -> Material = diffuse(spectrum(0.5))\n");
  const FarFloor frame{glm::rotate(glm::translate(Mat4(1.0f), Vec3(5000.0f, -2000.0f, 3000.0f)), 0.7f,
                                  glm::normalize(Vec3(0.2f, 1.0f, 0.5f)))};
  constexpr float kHalf = 0.5f;  // the camera sees |x|, |y| <= kHalf of the floor z = 0 (local frame)
  const float cosInner = std::cos(0.3f), cosOuter = std::cos(0.6f);
  CameraDesc camera = test::cameraLookingDownZ(Vec3(0.0f, 0.0f, 1.0f), 0.9f);
  camera.orthoHalfHeight = kHalf;
  for (const LightDesc::Kind kind : {LightDesc::Kind::Point, LightDesc::Kind::Spot, LightDesc::Kind::Directional}) {
    SceneDescription scene = frame.scene(file, camera);
    LightDesc light;
    light.kind = kind;
    light.emission.kind = SpectrumDesc::Kind::Constant;
    light.emission.value = 1.0f;
    const Vec3 position(0.4f, -0.3f, 0.8f), spotAxis = glm::normalize(Vec3(-0.2f, 0.1f, -1.0f));
    const Vec3 travel = glm::normalize(Vec3(0.5f, -0.3f, -1.0f));
    light.position = frame.world(position);
    light.direction = frame.worldVector(kind == LightDesc::Kind::Spot ? spotAxis : travel);
    light.intensity = kind == LightDesc::Kind::Directional ? 2.0f : 3.0f;
    light.innerConeRadians = 0.3f;
    light.outerConeRadians = 0.6f;
    scene.lights.push_back(light);

    double expected = 0;
    constexpr int kGrid = 64;
    for (int i = 0; i < kGrid; ++i)
      for (int j = 0; j < kGrid; ++j) {
        const Vec3 p(kHalf * (2.0f * (i + 0.5f) / kGrid - 1.0f), kHalf * (2.0f * (j + 0.5f) / kGrid - 1.0f), 0.0f);
        double irradiance;
        if (kind == LightDesc::Kind::Directional) {
          irradiance = light.intensity * std::max(0.0f, -travel.z);
        } else {
          const Vec3 d = position - p;
          const double dist2 = double(dot3(d, d)), cosine = double(d.z) / std::sqrt(dist2);
          double falloff = 1;
          if (kind == LightDesc::Kind::Spot) {
            const double t = std::clamp((double(dot3(-d, spotAxis)) / std::sqrt(dist2) - cosOuter) / (cosInner - cosOuter), 0.0, 1.0);
            falloff = t * t;
          }
          irradiance = light.intensity * falloff * cosine / dist2;
        }
        expected += 0.5 / kPi * irradiance / (kGrid * kGrid);
      }
    const Estimate e = estimateRadiance(scene, 1, 4, 1 << 15);
    EXPECT_NEAR(e.mean, expected, 4 * e.standardError + 0.003 * expected) << "light kind " << int(kind);
    EXPECT_GT(expected, 0.05);
  }
}

// Radiometry does not depend on the scene's scale: a floor on the plane z = 0 under a directional
// light, every length times S, written into the vertices or given by the instance's transform.
// Edges beyond about 4e9 had overflowed the float cross product (a zero normal: black), a
// transform's float determinant past a scale of 7e12 had dropped the instance, and at S = 1e-8
// the floor's shadow rays hit the floor (an offset that underflowed in Embree's test).
TEST(PathTracer, ScenesOfAnyScaleAreLitAlike) {
  const std::string file = writeTexModule("scaled", "export fn floor(h: Hit) -> Material = diffuse(spectrum(0.5))\n");
  const Vec3 travel = glm::normalize(Vec3(0.3f, -0.2f, -1.0f));
  const double expected = 0.5 / kPi * 2.0 * double(-travel.z);
  for (const bool viaTransform : {false, true})
    for (const float s : {1.0f, 1e10f, 1e13f, 1e-8f}) {
      if (!viaTransform && s > 1e12f) continue;  // vertices stay below the 1e15 coordinate limit
      SceneDescription scene;
      MeshPrimitive floor = viaTransform ? makeQuad(Vec3(-1.0f, -1.0f, 0.0f), Vec3(2.0f, 0.0f, 0.0f), Vec3(0.0f, 2.0f, 0.0f))
                                         : makeQuad(Vec3(-s, -s, 0.0f), Vec3(2.0f * s, 0.0f, 0.0f), Vec3(0.0f, 2.0f * s, 0.0f));
      floor.material = 0;
      scene.primitives = {floor};
      scene.instances = {MeshInstance{0, viaTransform ? glm::scale(Mat4(1.0f), Vec3(s)) : Mat4(1.0f), "floor"}};
      scene.materials.resize(1);
      scene.materials[0].name = "floor";
      test::bindEntriesByMaterialName(scene, file, {"floor"});
      CameraDesc camera = test::cameraLookingDownZ(Vec3(0.0f, 0.0f, s), 0.9f);
      camera.orthoHalfHeight = 0.5f * s;
      scene.cameras.push_back(camera);
      LightDesc sun;
      sun.kind = LightDesc::Kind::Directional;
      sun.direction = travel;
      sun.emission.kind = SpectrumDesc::Kind::Constant;
      sun.emission.value = 1.0f;
      sun.intensity = 2.0f;
      scene.lights.push_back(sun);
      const Estimate e = estimateRadiance(scene, 1, 4, 1 << 13);
      EXPECT_NEAR(e.mean, expected, 4 * e.standardError + 0.003 * expected) << "scale " << s << (viaTransform ? " (transform)" : "");
    }
}

TEST(PathTracer, WhiteFurnaceForLosslessMaterials) {
  const std::string file = writeTexModule("furnace",
                                          "import std.spectra.{cauchy}\n"
                                          "export fn white(h: Hit) -> Material = diffuse(spectrum(1.0))\n"
                                          "export fn glass(h: Hit) -> Material = dielectric(1.5)\n"
                                          "export fn flint(h: Hit) -> Material = dielectric(cauchy(1.6, 15000.0))\n"
                                          "export fn dense(h: Hit) -> Material = dielectric(1.7)\n"
                                          "export fn weak(h: Hit) -> Material = dielectric(cauchy(1.6, 10.0))\n"
                                          "export fn blend(h: Hit) -> Material = mix_material(diffuse(spectrum(1.0)), dielectric(1.33), 0.4)\n");
  for (const char* entry : {"white", "glass", "dense", "weak", "flint", "blend"}) {
    // Flat facets: interpolated shading normals make refraction lose the directions that
    // would cross the geometric surface the wrong way (a deliberate leak guard), which is
    // energy loss a furnace would rightly flag but which is not what this test is about.
    MeshPrimitive sphere = makeSphere(Vec3(0.0f), 1.0f, 48, 24, false);
    sphere.normals.clear();
    SceneDescription scene = oneObjectScene(std::move(sphere), file, entry, Vec3(0.0f, 0.0f, 3.0f));
    scene.lights.push_back(constantSky(1.0f));
    // A faceted sphere can trap light by total internal reflection for many bounces, so the
    // depth limit (energy it cuts off is real, not noise) must be far beyond typical paths.
    const Estimate e = estimateRadiance(scene, 5000, 4, 1 << 17);
    EXPECT_NEAR(e.mean, 1.0, 4 * e.standardError + 1e-6) << entry;
    EXPECT_EQ(e.nonFinite, 0u) << entry;
  }
}

// Inside dense glass radiance carries 1 / eta^2, a change of units that Russian roulette must
// not read as a loss (pbrt-v4's etaScale). It did: a lossless IOR-10 ball in a white furnace
// ended its paths inside with probability 0.99 and the survivors carried 100, so single
// samples ranged over 0..100 around the right mean; now every sample is about 1.
TEST(PathTracer, RouletteSeesThroughTheUnitsOfRadianceInsideDenseGlass) {
  const std::string file = writeTexModule("dense_glass", "export fn glass(h: Hit) -> Material = dielectric(10.0)\n");
  MeshPrimitive sphere = makeSphere(Vec3(0.0f), 1.0f, 48, 24, false);
  sphere.normals.clear();  // flat facets, as in the white furnace above
  SceneDescription scene = oneObjectScene(std::move(sphere), file, "glass", Vec3(0.0f, 0.0f, 3.0f));
  scene.lights.push_back(constantSky(1.0f));
  constexpr uint64_t kSamples = 1 << 14;
  const Estimate e = estimateRadiance(scene, 5000, 4, kSamples, sampling::SamplerKind::Sobol, 1);
  EXPECT_NEAR(e.mean, 1.0, 4 * e.standardError + 1e-6);
  const double sampleDeviation = e.standardError * std::sqrt(double(kSamples));
  EXPECT_LT(sampleDeviation, 0.05);
}

// A grey floor (albedo 0.5) at z = 0 under a smooth thin wall at z = 1 (a window: IOR 1.5,
// transmission tint 0.5), seen from above through the wall and lit from above by a sun
// (irradiance pi) or a point light, which no BSDF sample can hit: shadow rays pass the wall
// with its (1 - R') tint. They had stopped at it: the floor was black.
TEST(PathTracer, PointAndDirectionalLightsShineThroughSmoothThinWalls) {
  const std::string file = writeTexModule("window", "export fn pane(h: Hit) -> Material = thin_dielectric(1.5, 0.0, 0.5)\n"
                                                    "export fn floor(h: Hit) -> Material = diffuse(spectrum(0.5))\n");
  const float wallR = 2.0f * 0.04f / 1.04f, wallT = (1.0f - wallR) * 0.5f;
  for (const bool sun : {true, false}) {
    SceneDescription scene;
    for (const auto& [name, z, size] : {std::tuple{"pane", 1.0f, 4.0f}, std::tuple{"floor", 0.0f, 10.0f}})
      test::addNamedMesh(scene, name, makeQuad(Vec3(-size / 2, -size / 2, z), Vec3(size, 0, 0), Vec3(0, size, 0)));
    test::bindEntriesByMaterialName(scene, file, {"pane", "floor"});
    scene.cameras.push_back(test::cameraLookingDownZ(Vec3(0.0f, 0.0f, 3.0f), 0.05f));
    LightDesc light;
    light.kind = sun ? LightDesc::Kind::Directional : LightDesc::Kind::Point;
    light.position = Vec3(0.0f, 0.0f, 2.0f);
    light.direction = Vec3(0.0f, 0.0f, -1.0f);
    light.emission.kind = SpectrumDesc::Kind::Constant;
    light.emission.value = 1.0f;
    light.intensity = sun ? float(M_PI) : 4.0f * float(M_PI);  // irradiance pi on the floor either way (r = 2)
    scene.lights.push_back(light);
    // Depth 3: the wall, the floor, and the wall its light passes (walls count as bounces for
    // shadow rays as for BSDF samples). The camera sees the floor through the wall (a fraction
    // wallT of its paths, or R' reflected to nothing): 0.5 wallT x wallT. At depth 2 the light
    // would take a third bounce: black.
    const Estimate e = estimateRadiance(scene, 3, 4, 1 << 14);
    EXPECT_EQ(estimateRadiance(scene, 2, 4, 1 << 10).mean, 0.0);
    EXPECT_NEAR(e.mean, 0.5 * wallT * wallT, 4 * e.standardError + 0.01 * 0.5 * wallT * wallT) << (sun ? "sun" : "point");
  }
}

// A scene built for a square image of `size` pixels, without the JIT's disk cache.
std::unique_ptr<RenderScene> buildSquare(const SceneDescription& scene, int size) {
  RenderSceneOptions o;
  o.width = o.height = size;
  o.useCache = false;
  std::string error;
  std::unique_ptr<RenderScene> rs = RenderScene::build(scene, o, error);
  EXPECT_TRUE(rs) << error;
  return rs;
}

struct FilmOptions {
  int width = 32, height = 32;
  FilterKind filter = FilterKind::Tent;
  uint64_t seed = 11;
  PathTracerSettings settings;
};

// Renders through the stream runtime into a film with the given thread count.
FilmAccumulator renderFilm(const RenderScene& rs, int threads, uint64_t samples, const FilmOptions& f = {}) {
  const PathTracer tracer(rs, sampling::Sampler(sampling::SamplerKind::Sobol, f.seed), f.settings);
  FilmSettings fs;
  fs.width = f.width;
  fs.height = f.height;
  fs.filter = f.filter;
  FilmSink sink(fs);
  std::vector<runtime::Sink<SampleRecord>*> sinks = {&sink};
  runtime::SchedulerOptions options;
  options.threads = threads;
  options.chunkSize = 1000;
  runtime::runStream<SampleRecord>({0, samples}, options, tracer, std::span<runtime::Sink<SampleRecord>* const>(sinks));
  FilmAccumulator film(fs);
  film.merge(sink.film());
  return film;
}

// A sky of linear sRGB (1, 1, 1) as an illuminant (D65 of luminance 1).
LightDesc whiteRgbSky() {
  LightDesc sky;
  sky.kind = LightDesc::Kind::ConstantEnvironment;
  sky.emission.kind = SpectrumDesc::Kind::Rgb;
  sky.emission.rgb = Vec3(1.0f);
  return sky;
}

// The image mean of one channel and its standard error (from the film's variance channel).
Estimate channelMean(const DevelopedImage& img, int channel) {
  double sum = 0, var = 0;
  for (int p = 0; p < img.width * img.height; ++p) {
    sum += img.rgb[size_t(p) * 3 + size_t(channel)];
    var += img.variance[size_t(p) * 3 + size_t(channel)];
  }
  const double n = double(img.width * img.height);
  Estimate e;
  e.mean = sum / n;
  e.standardError = std::sqrt(var) / n;
  return e;
}

// A 2x2 quad in z = 0 (u along +x) of glTF material `material` filling an 8x8 orthographic
// view head-on, lit by `light`, 256 spp, box filter (an empty image if the scene does not build).
// GGX reflection's albedo with F = 1 seen head-on (Kulla & Conty's E(1, alpha)): the integral of
// D(m) cos(theta_m) G2 over the half vectors that reflect above the horizon (theta_m < 45
// degrees; wi = 2 theta_m), by midpoint quadrature. Independent of the renderer's lobe code.
float ggxSingleScatterAlbedoHeadOn(double alpha) {
  const int n = 20000;
  const double step = (M_PI / 4) / n, a2 = alpha * alpha;
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const double theta = (i + 0.5) * step, tanT = std::tan(theta), cosT = std::cos(theta);
    const double d = a2 / (M_PI * std::pow(cosT, 4) * (a2 + tanT * tanT) * (a2 + tanT * tanT));
    const double tanI = std::tan(2 * theta);
    const double lambdaI = 0.5 * (std::sqrt(1 + a2 * tanI * tanI) - 1);
    sum += d * cosT / (1 + lambdaI) * 2 * M_PI * std::sin(theta) * step;
  }
  return float(sum);
}

DevelopedImage renderGltfQuadHeadOn(const GltfMaterial& material, int maxDepth, const LightDesc& light,
                                    const std::vector<ImageData>& images = {}) {
  SceneDescription scene;
  scene.images = images;
  MeshPrimitive quad = makeQuad(Vec3(-1.0f, -1.0f, 0.0f), Vec3(2.0f, 0.0f, 0.0f), Vec3(0.0f, 2.0f, 0.0f));
  quad.material = 0;
  scene.primitives.push_back(std::move(quad));
  scene.instances.push_back(MeshInstance{0, Mat4(1.0f), "quad"});
  scene.materials.push_back(material);
  CameraDesc camera = test::cameraLookingDownZ(Vec3(0.0f, 0.0f, 3.0f), 0.5f);
  camera.orthoHalfHeight = 0.5f;
  scene.cameras.push_back(camera);
  scene.lights.push_back(light);
  const std::unique_ptr<RenderScene> rs = buildSquare(scene, 8);
  if (!rs) return DevelopedImage();
  FilmOptions f;
  f.width = f.height = 8;
  f.filter = FilterKind::Box;
  f.settings.maxDepth = maxDepth;
  return renderFilm(*rs, 2, 8 * 8 * 256, f).develop();
}

// glTF 2.0 (Appendix B): a metal's Fresnel term is baseColor at normal incidence. A mirror-smooth
// metal seen head-on by an orthographic camera under a white (RGB (1,1,1)) sky therefore develops
// to its base colour. Gold's base colour had come out (0.46, 0.80, 0.31) when the conductor's
// complex IOR was fitted per RGB channel instead of per wavelength.
TEST(PathTracer, SmoothGltfMetalsReflectTheirBaseColourAtNormalIncidence) {
  const Vec3 colours[] = {Vec3(1.0f, 0.766f, 0.336f), Vec3(0.955f, 0.638f, 0.538f), Vec3(0.1f, 0.8f, 0.2f),
                          Vec3(0.2f, 0.3f, 0.9f), Vec3(0.5f), Vec3(1.0f)};
  for (const Vec3& base : colours) {
    GltfMaterial metal;
    metal.name = "metal";
    metal.baseColorFactor = Vec4(base, 1.0f);
    metal.metallicFactor = 1.0f;
    metal.roughnessFactor = 0.0f;
    const DevelopedImage img = renderGltfQuadHeadOn(metal, 2, whiteRgbSky());
    ASSERT_GT(img.width, 0);
    for (int c = 0; c < 3; ++c) {
      const Estimate e = channelMean(img, c);
      // 3e-3: the RGB upsampling round trip (Gulbrandsen's IOR clamps reflectance at 0.9999).
      EXPECT_NEAR(e.mean, base[c], 4 * e.standardError + 3e-3)
          << "base (" << base.x << ", " << base.y << ", " << base.z << ") channel " << c;
    }
  }
}

// A normal map tilts the normal the light's cosine is taken with. A rough white glTF quad lit
// by a directional light 45 degrees off its face, seen head-on: with a flat map it receives
// cos 45; with a map tilted 45 degrees toward the light, cos 0. The coated BSDF is reciprocal
// and the two cases are each other's swapped pair (wo, wi) in the shading frame, so the ratio
// is sqrt 2 exactly. (The cosine had used the mesh normal: ratio 1.)
TEST(PathTracer, NormalMapsTiltTheCosineOfTheLight) {
  LightDesc sun;
  sun.kind = LightDesc::Kind::Directional;
  sun.emission.kind = SpectrumDesc::Kind::Constant;
  sun.emission.value = 1.0f;
  sun.direction = glm::normalize(Vec3(-1.0f, 0.0f, -1.0f));  // travelling down from +x
  double mean[2] = {0, 0};
  for (int tilted = 0; tilted < 2; ++tilted) {
    ImageData map;
    map.width = map.height = 1;
    map.channels = 3;
    const float c = 0.5f + 0.5f * std::sqrt(0.5f);  // (2c - 1) = 0.7071: 45 degrees toward +u
    map.pixels = tilted ? std::vector<float>{c, 0.5f, c} : std::vector<float>{0.5f, 0.5f, 1.0f};
    GltfMaterial m;
    m.name = "bumpy";
    m.metallicFactor = 0.0f;
    m.roughnessFactor = 1.0f;
    m.normalTexture.image = 0;
    const DevelopedImage img = renderGltfQuadHeadOn(m, 1, sun, {map});
    ASSERT_GT(img.width, 0);
    mean[tilted] = channelMean(img, 1).mean;
  }
  ASSERT_GT(mean[0], 0.0);
  EXPECT_NEAR(mean[1] / mean[0], std::sqrt(2.0), 0.01);
}

// glTF transmission: a material of thickness 0 is a thin wall (no refraction: a single-quad
// window under a white sky passes it all, where a solid's 1/eta^2 gave 0.47), and the base
// colour tints the transmitted light only: red glass reflects the sky's white in green and
// blue, where its reflection had been tinted red too. What it reflects is the wall's (both
// interfaces): R' = 2 F(0) / (1 + F(0)) = 0.0769 head-on, where a single interface's 0.04 had
// been taken.
TEST(PathTracer, GltfThinWallsPassLightUnbentAndTintOnlyTheTransmission) {
  struct Case {
    Vec3 base;
    float transmission;
    Vec3 expected;
  };
  // Half transmissive white: half plastic (a white base under a smooth coat reflects all) and
  // half wall, with one coat between them (a second coat had failed the material).
  // A rough white wall (roughness 0.4, GGX alpha 0.16) reflects and transmits what GGX
  // reflection with F = 1 does head-on: 0.968, the rest lost to masking and to facets steeper
  // than 45 degrees. It had refracted as a solid: 0.47.
  const float roughWall = ggxSingleScatterAlbedoHeadOn(0.16f);
  const float wallR = 2.0f * 0.04f / 1.04f;
  for (const Case c : {Case{Vec3(1.0f), 1.0f, Vec3(1.0f)}, Case{Vec3(1.0f, 0.0f, 0.0f), 1.0f, Vec3(1.0f, wallR, wallR)},
                       Case{Vec3(1.0f), 0.5f, Vec3(1.0f)}, Case{Vec3(1.0f), 1.0f, Vec3(roughWall)}}) {
    const bool rough = c.expected.x < 1.0f;
    GltfMaterial window;
    window.name = "window";
    window.baseColorFactor = Vec4(c.base, 1.0f);
    window.metallicFactor = 0.0f;
    window.roughnessFactor = rough ? 0.4f : 0.0f;
    window.transmissionFactor = c.transmission;
    window.thinWalled = true;
    const DevelopedImage img = renderGltfQuadHeadOn(window, 4, whiteRgbSky());
    ASSERT_GT(img.width, 0);
    for (int ch = 0; ch < 3; ++ch) {
      const Estimate e = channelMean(img, ch);
      EXPECT_NEAR(e.mean, c.expected[ch], 4 * e.standardError + 4e-3)
          << "base " << c.base.y << " transmission " << c.transmission << " rough " << rough << " channel " << ch;
    }
  }
}

// glTF dielectrics seen head-on under a white sky: over a black base the Fresnel coat still
// reflects F(0) = ((ior - 1) / (ior + 1))^2 (its base lobe, of weight 0, was dropped and the
// path stopped at an "empty" Bsdf: black glossy materials reflected nothing), and an ior of 1
// (KHR_materials_ior: no specular reflection) leaves the base alone (it was replaced by 1.5).
TEST(PathTracer, GltfCoatsReflectFresnelOverBlackAndNothingAtIorOne) {
  struct Case {
    Vec3 base;
    float ior, expected;
  };
  for (const Case c : {Case{Vec3(0.0f), 1.5f, 0.04f}, Case{Vec3(0.0f), 2.0f, 1.0f / 9.0f}, Case{Vec3(0.5f), 1.0f, 0.5f}}) {
    GltfMaterial m;
    m.name = "coated";
    m.baseColorFactor = Vec4(c.base, 1.0f);
    m.metallicFactor = 0.0f;
    m.roughnessFactor = 0.0f;
    m.ior = c.ior;
    const DevelopedImage img = renderGltfQuadHeadOn(m, 3, whiteRgbSky());
    ASSERT_GT(img.width, 0);
    for (int ch = 0; ch < 3; ++ch) {
      const Estimate e = channelMean(img, ch);
      EXPECT_NEAR(e.mean, c.expected, 4 * e.standardError + 2e-3) << "ior " << c.ior << " channel " << ch;
    }
  }
}

// An 8 x 8 box-filtered render at 4096 spp with maximum depth 1: light reaching a surface
// directly, through next-event estimation (with MIS) or through rays alone.
DevelopedImage renderDepthOne(const RenderScene& rs, bool nextEventEstimation) {
  FilmOptions f;
  f.width = f.height = 8;
  f.filter = FilterKind::Box;
  f.settings.maxDepth = 1;
  f.settings.nextEventEstimation = nextEventEstimation;
  return renderFilm(rs, 2, 8 * 8 * 4096, f).develop();
}

// An emitter whose radiance reads its Hit (here its shading normal and uv) must give light
// samples the emission a ray hitting the same point sees: MIS weighs the two techniques, so
// any difference biases the image. A lamp quad whose vertex normals lean away from its face
// normal lights a diffuse floor; next-event estimation with MIS must agree with BSDF sampling
// alone. (Light samples had seen the flat face normal and read 1.04x instead of 1.8x.)
TEST(PathTracer, HitDependentEmittersLookTheSameToLightSamplesAndToRays) {
  const std::string file = writeTexModule(
      "hit_emitter",
      "export fn floor(h: Hit) -> Material = diffuse(spectrum(0.5))\n"
      "export fn lamp(h: Hit) -> Material = emission(rgb(1.0 + h.n.x, 1.0, 1.0) * (0.5 + h.uv.x))\n");
  SceneDescription scene;
  MeshPrimitive floor = makeQuad(Vec3(-1.0f, -1.0f, 0.0f), Vec3(2.0f, 0.0f, 0.0f), Vec3(0.0f, 2.0f, 0.0f));
  floor.material = 0;
  MeshPrimitive lamp = makeQuad(Vec3(-0.5f, -0.5f, 1.0f), Vec3(0.0f, 1.0f, 0.0f), Vec3(1.0f, 0.0f, 0.0f));  // faces -z
  for (Vec3& n : lamp.normals) n = glm::normalize(Vec3(0.6f, 0.0f, -0.8f));
  lamp.material = 1;
  scene.primitives = {floor, lamp};
  scene.instances = {MeshInstance{0, Mat4(1.0f), "floor"}, MeshInstance{1, Mat4(1.0f), "lamp"}};
  GltfMaterial floorMaterial, lampMaterial;
  floorMaterial.name = "floor";
  lampMaterial.name = "lamp";
  scene.materials = {floorMaterial, lampMaterial};
  test::bindEntriesByMaterialName(scene, file, {"floor", "lamp"});
  CameraDesc camera = test::cameraLookingDownZ(Vec3(0.0f, 0.0f, 0.5f), 0.5f);
  camera.orthoHalfHeight = 0.8f;
  scene.cameras.push_back(camera);
  const std::unique_ptr<RenderScene> rs = buildSquare(scene, 8);
  ASSERT_TRUE(rs);
  Estimate withLightSamples[3], raysOnly[3];
  for (bool nee : {true, false}) {
    const DevelopedImage img = renderDepthOne(*rs, nee);
    for (int c = 0; c < 3; ++c) (nee ? withLightSamples : raysOnly)[c] = channelMean(img, c);
  }
  for (int c = 0; c < 3; ++c) {
    const double a = withLightSamples[c].mean, b = raysOnly[c].mean;
    const double se = std::hypot(withLightSamples[c].standardError, raysOnly[c].standardError);
    EXPECT_GT(b, 0.01) << "channel " << c;  // the floor is lit
    EXPECT_NEAR(a, b, 4 * se + 1e-3 * b) << "channel " << c;
  }
}

// glTF emitters with an alphaMode light the scene as much through light samples as through rays:
// rays pass cut-out parts (MASK) and blended ones with probability 1 - alpha (BLEND), and
// light samples now multiply by that coverage (they lit the floor through the cut-outs: a
// fully cut-out lamp still gave 0.037 of its 0.048, a BLEND lamp of alpha 0.3 0.84 of it).
TEST(PathTracer, CutOutAndBlendedEmittersLightAlikeThroughLightSamplesAndRays) {
  struct Case {
    GltfMaterial::AlphaMode mode;
    float alpha;
    float expectedShare;  // of the opaque lamp's light
  };
  double opaque = 0.0;
  for (const Case c : {Case{GltfMaterial::AlphaMode::Opaque, 1.0f, 1.0f}, Case{GltfMaterial::AlphaMode::Mask, 0.2f, 0.0f},
                       Case{GltfMaterial::AlphaMode::Blend, 0.3f, 0.3f}}) {
    SceneDescription scene;
    MeshPrimitive floor = makeQuad(Vec3(-1.0f, -1.0f, 0.0f), Vec3(2.0f, 0.0f, 0.0f), Vec3(0.0f, 2.0f, 0.0f));
    floor.material = 0;
    MeshPrimitive lamp = makeQuad(Vec3(-0.5f, -0.5f, 1.0f), Vec3(0.0f, 1.0f, 0.0f), Vec3(1.0f, 0.0f, 0.0f));  // faces -z
    lamp.material = 1;
    scene.primitives = {floor, lamp};
    scene.instances = {MeshInstance{0, Mat4(1.0f), "floor"}, MeshInstance{1, Mat4(1.0f), "lamp"}};
    GltfMaterial floorMaterial, lampMaterial;
    floorMaterial.name = "floor";
    floorMaterial.baseColorFactor = Vec4(0.8f, 0.8f, 0.8f, 1.0f);
    floorMaterial.metallicFactor = 0.0f;
    floorMaterial.roughnessFactor = 1.0f;
    lampMaterial.name = "lamp";
    lampMaterial.baseColorFactor = Vec4(0.0f, 0.0f, 0.0f, c.alpha);
    lampMaterial.metallicFactor = 0.0f;
    lampMaterial.emissiveFactor = Vec3(1.0f);
    lampMaterial.alphaMode = c.mode;
    scene.materials = {floorMaterial, lampMaterial};
    CameraDesc camera = test::cameraLookingDownZ(Vec3(0.0f, 0.0f, 0.5f), 0.5f);
    camera.orthoHalfHeight = 0.8f;
    scene.cameras.push_back(camera);
    const std::unique_ptr<RenderScene> rs = buildSquare(scene, 8);
    ASSERT_TRUE(rs);
    const Estimate withLightSamples = channelMean(renderDepthOne(*rs, true), 1);
    const Estimate raysOnly = channelMean(renderDepthOne(*rs, false), 1);
    const double se = std::hypot(withLightSamples.standardError, raysOnly.standardError);
    EXPECT_NEAR(withLightSamples.mean, raysOnly.mean, 4 * se + 1e-3 * raysOnly.mean) << int(c.mode);
    if (c.mode == GltfMaterial::AlphaMode::Opaque) {
      opaque = withLightSamples.mean;
      EXPECT_GT(opaque, 0.01);  // the floor is lit
    } else {
      EXPECT_NEAR(withLightSamples.mean, c.expectedShare * opaque, 4 * withLightSamples.standardError + 2e-3 * opaque)
          << int(c.mode);
    }
  }
}

// Light selection by power sees where a Hit-dependent emitter is bright: each triangle's power
// comes from its own radiance (plus a tenth of the material's average, so that none is left
// out). Here the emission grows with u, and the quad's two triangles cover u on average 1/3 and
// 2/3: their selection probabilities differ (they were equal, from the material's average).
TEST(PathTracer, TrianglesOfAPatternedEmitterAreChosenByTheirOwnPower) {
  const std::string file =
      writeTexModule("patterned_emitter", "export fn lamp(h: Hit) -> Material = emission(rgb(h.uv.x * 4.0))\n");
  SceneDescription scene = oneObjectScene(makeQuad(Vec3(-1.0f, -1.0f, 0.0f), Vec3(2.0f, 0.0f, 0.0f), Vec3(0.0f, 2.0f, 0.0f)),
                                          file, "lamp", Vec3(0.0f, 0.0f, 3.0f));
  const std::unique_ptr<RenderScene> rs = buildSquare(scene, 8);
  ASSERT_TRUE(rs);
  ASSERT_EQ(rs->lightSampler().size(), 2);
  const float a = rs->lightSampler().pmfPower(0), b = rs->lightSampler().pmfPower(1);
  const float ratio = std::max(a, b) / std::min(a, b);
  // Expected (0.9 * 2/3 + 0.1 * 1/2) / (0.9 * 1/3 + 0.1 * 1/2) = 1.857 (four interior points).
  EXPECT_NEAR(ratio, 1.857f, 0.05f);
}

TEST(PathTracer, SpectralFurnaceDevelopsToTheIlluminantsColourAndIsThreadCountIndependent) {
  // An albedo-1 diffuse sphere under a D65 sky of luminance 1 (RGB (1,1,1) as an illuminant)
  // develops to linear sRGB (1,1,1); 1 and 2 threads give the same fixed-point film sums.
  const std::string file = writeTexModule("spectral_furnace", "export fn white(h: Hit) -> Material = diffuse(spectrum(1.0))\n");
  SceneDescription scene = oneObjectScene(makeSphere(Vec3(0.0f), 1.0f, 48, 24, false), file, "white", Vec3(0.0f, 0.0f, 3.0f));
  scene.lights.push_back(whiteRgbSky());
  const std::unique_ptr<RenderScene> rs = buildSquare(scene, 32);
  ASSERT_TRUE(rs);
  const FilmAccumulator one = renderFilm(*rs, 1, 32 * 32 * 64);
  const FilmAccumulator two = renderFilm(*rs, 2, 32 * 32 * 64);
  EXPECT_TRUE(one.sums() == two.sums());
  const DevelopedImage img = one.develop();
  for (int c = 0; c < 3; ++c) {
    const Estimate e = channelMean(img, c);
    EXPECT_NEAR(e.mean, 1.0, 4 * e.standardError + 2e-3) << "channel " << c;  // 2e-3: RGB upsampling round trip
  }
}

}  // namespace
}  // namespace tex::render

namespace tex::render {
namespace {

TEST(PathTracer, FirstHitCarriesThePixelFootprint) {
  // A quad of side 2 facing a camera 4 away: one pixel of a 100-pixel film with a 0.5 rad field
  // of view spans 2 * 4 * tan(0.25) / 100 in x, i.e. half that in u. The material emits its
  // Hit's duvdx.x (and -duvdy.y: v grows along edge2 = +y while film y grows downwards).
  const std::string file = writeTexModule(
      "footprint",
      "export fn dudx(h: Hit) -> Material = emission(spectrum(h.duvdx.x))\n"
      "export fn dvdy(h: Hit) -> Material = emission(spectrum(0.0 - h.duvdy.y))\n");
  for (const char* entry : {"dudx", "dvdy"}) {
    SceneDescription scene = oneObjectScene(makeQuad(Vec3(-1, -1, 0), Vec3(2, 0, 0), Vec3(0, 2, 0)), file, entry,
                                            Vec3(0.0f, 0.0f, 4.0f));
    scene.cameras[0].yFovRadians = 0.5f;
    RenderSceneOptions o;
    o.width = o.height = 100;
    o.useCache = false;
    std::string error;
    std::unique_ptr<RenderScene> rs = RenderScene::build(scene, o, error);
    ASSERT_TRUE(rs) << error;
    PathTracerSettings settings;
    settings.filmWidth = settings.filmHeight = 100;
    const PathTracer tracer(*rs, sampling::Sampler(sampling::SamplerKind::Sobol, 1), settings);
    const double expected = 2.0 * 4.0 * std::tan(0.25) / 100.0 / 2.0;
    int hits = 0;
    for (uint64_t i = 0; i < 4000; ++i) {
      const SampleRecord r = tracer.record(i);
      const double L = r.values[0] * color::visibleWavelengthPdf(r.lambdaNm[0]);
      if (L == 0.0) continue;  // off the quad
      ++hits;
      EXPECT_NEAR(L, expected, 0.02 * std::fabs(expected)) << entry;  // perspective: a few % across the view
    }
    EXPECT_GT(hits, 1000);
  }
}

// A crop window (PathTracerSettings::crop) renders the whole image's pixels: its film covers the
// window and the camera sees the window's part of its image. Compared pixel by pixel with the
// whole image rendered at the same samples per pixel (box filter, so a pixel's samples are the
// same in both; per-pixel Z-test on the variance channels).
TEST(PathTracer, CropWindowRendersTheWholeImagesPixels) {
  const std::string file = writeTexModule("crop_window", "export fn red(h: Hit) -> Material = diffuse(rgb(0.8, 0.2, 0.1))\n");
  SceneDescription scene = oneObjectScene(makeSphere(Vec3(0.3f, 0.1f, 0.0f), 1.0f, 48, 24, false), file, "red", Vec3(0.0f, 0.0f, 3.0f));
  LightDesc sun;
  sun.kind = LightDesc::Kind::Directional;
  sun.direction = glm::normalize(Vec3(-1.0f, -1.0f, -0.5f));
  scene.lights.push_back(sun);
  scene.lights.push_back(constantSky(0.3f));
  const std::unique_ptr<RenderScene> rs = buildSquare(scene, 32);
  ASSERT_TRUE(rs);
  constexpr int kSpp = 64, kX = 6, kY = 10, kW = 20, kH = 12;
  FilmOptions f;
  f.filter = FilterKind::Box;
  f.seed = 5;
  f.settings.filmWidth = f.settings.filmHeight = 32;
  const DevelopedImage whole = renderFilm(*rs, 2, 32 * 32 * kSpp, f).develop();
  f.width = kW;
  f.height = kH;
  f.settings.crop = {kX / 32.0f, kY / 32.0f, (kX + kW) / 32.0f, (kY + kH) / 32.0f};
  const DevelopedImage window = renderFilm(*rs, 2, uint64_t(kW) * kH * kSpp, f).develop();
  ASSERT_EQ(window.width, kW);
  ASSERT_EQ(window.height, kH);
  double sumZ2 = 0;
  int tested = 0, outliers = 0;
  double meanWhole = 0, meanWindow = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      for (int c = 0; c < 3; ++c) {
        const size_t a = (size_t(y + kY) * 32 + size_t(x + kX)) * 3 + size_t(c), b = (size_t(y) * kW + size_t(x)) * 3 + size_t(c);
        meanWhole += whole.rgb[a];
        meanWindow += window.rgb[b];
        const double variance = double(whole.variance[a]) + double(window.variance[b]);
        if (!(variance > 0.0)) {
          EXPECT_EQ(whole.rgb[a], window.rgb[b]);  // no noise (the sky alone): the same value
          continue;
        }
        const double z = (double(whole.rgb[a]) - double(window.rgb[b])) / std::sqrt(variance);
        sumZ2 += z * z;
        outliers += std::fabs(z) > 4.0;
        ++tested;
      }
  ASSERT_GT(tested, kW * kH);  // the sphere's lit and shadowed pixels are noisy
  EXPECT_LT(sumZ2 / tested, 1.5) << "mean z^2 over " << tested << " pixel channels";
  EXPECT_LE(outliers, tested / 200);
  EXPECT_NEAR(meanWindow / meanWhole, 1.0, 0.02);
}

}  // namespace
}  // namespace tex::render
