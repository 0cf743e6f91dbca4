// Lights: sampled directions follow the claimed densities (chi-square, 1M samples), emitted
// rays too, the triangle light's next-event estimate equals the analytic irradiance, the spot
// falloff is glTF's, the light sampler picks by power, an environment map sampled by its own
// luminance has a constant L / pdf, and nothing returns NaN at grazing angles.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <unistd.h>

#include <glm/gtc/matrix_transform.hpp>

#include "renderer/core/warp.h"
#include "renderer/image/image_io.h"
#include "renderer/lights/constant_environment.h"
#include "renderer/lights/directional_light.h"
#include "renderer/lights/image_environment.h"
#include "renderer/lights/light_factory.h"
#include "renderer/lights/light_sampler.h"
#include "renderer/lights/point_light.h"
#include "renderer/lights/spot_light.h"
#include "renderer/lights/triangle_light.h"
#include "renderer/sampling/pcg.h"
#include "renderer/spectra/spectrum_desc.h"
#include "tests/renderer/chi_square.h"
#include "tests/renderer/constant_emission.h"

namespace tex::render {
namespace {

const Wavelengths kLambda = color::sampleWavelengthGroup(0.37f, 4);

Vec2 next2(sampling::Pcg32& rng) { return Vec2(rng.nextFloat(), rng.nextFloat()); }

struct MeanError {
  double sum = 0, sum2 = 0;
  int n = 0;
  void add(double x) { sum += x, sum2 += x * x, ++n; }
  double mean() const { return sum / n; }
  double error() const { return std::sqrt(std::max(0.0, sum2 / n - mean() * mean()) / n); }
};

// Emission 1 + (the point's barycentric of the second vertex) on every wavelength: an emission
// that reads its Hit, so that tests can check the point's place on the triangle it is given.
class PlacedEmission final : public EmissionSource {
 public:
  explicit PlacedEmission(float scale) : scale_(scale) {}
  Spectrum radiance(const EmitterPoint& p, const Wavelengths& lambda) const override {
    Spectrum s;
    for (int i = 0; i < lambda.count; ++i) s[i] = p.instance == 7 ? scale_ * (1.0f + p.b12.x) : -1.0f;
    return s;
  }
  float averageRadiance() const override { return scale_ * (4.0f / 3.0f); }
  bool readsHit() const override { return true; }

 private:
  float scale_;
};

using ::tex::test::ConstantEmission;

// Ray-triangle intersection (Moller-Trumbore, in double): the hit point, if any.
std::optional<Vec3> intersectTriangle(const Vec3& o, const Vec3& d, const Vec3& p0, const Vec3& p1, const Vec3& p2) {
  const glm::dvec3 e1 = glm::dvec3(p1 - p0), e2 = glm::dvec3(p2 - p0), dd(d);
  const glm::dvec3 pv = glm::cross(dd, e2);
  const double det = glm::dot(e1, pv);
  if (std::fabs(det) < 1e-15) return std::nullopt;
  const glm::dvec3 tv = glm::dvec3(o - p0);
  const double b1 = glm::dot(tv, pv) / det;
  const glm::dvec3 qv = glm::cross(tv, e1);
  const double b2 = glm::dot(dd, qv) / det;
  const double t = glm::dot(e2, qv) / det;
  if (b1 < 0 || b2 < 0 || b1 + b2 > 1 || t <= 0) return std::nullopt;
  return Vec3(glm::dvec3(o) + dd * t);
}

TriangleLightDesc testTriangle() {
  TriangleLightDesc t;
  t.p0 = Vec3(1.0f, -0.6f, -0.5f);
  t.p1 = Vec3(1.2f, 0.7f, -0.3f);
  t.p2 = Vec3(0.9f, 0.0f, 0.6f);
  t.normal = Vec3(-1.0f, 0.0f, 0.0f);  // facing the origin
  t.instance = 7;  // where PlacedEmission expects its points
  return t;
}

// Chi-square of sampleLi's directions from `ref` against pdfLi, binned on the sphere in the
// triangle's frame (its normal is the bins' z axis, so directions nearly in its plane spread
// over many fine cos(theta) bins). The density jumps at the triangle's edge, and near grazing
// its far edge runs along a bin row where the density is steepest, so a cell's expected count
// is integrated on an 8 x 8 grid, refined to 64 x 64 where the grid sees the edge. Half the
// samples come from a uniform sphere (and half the density), so no cell whose corner the
// triangle barely touches has an expected count of 0.
test::ChiSquareResult chiSquareTriangleLi(const TriangleLight& light, const TriangleLightDesc& t, const Vec3& ref) {
  const Frame frame = Frame::fromNormal(light.normal());
  constexpr int kCosBins = 400, kPhiBins = 100, kSamples = 1000000;
  auto cellOf = [&](const Vec3& wLocal) {
    const int ct = std::clamp(int((wLocal.z + 1.0f) * 0.5f * kCosBins), 0, kCosBins - 1);
    double phi = std::atan2(double(wLocal.y), double(wLocal.x));
    if (phi < 0) phi += 2 * M_PI;
    return ct * kPhiBins + std::clamp(int(phi / (2 * M_PI) * kPhiBins), 0, kPhiBins - 1);
  };
  std::vector<double> observed(kCosBins * kPhiBins + 1, 0.0), expected(observed.size(), 0.0);
  sampling::Pcg32 rng(21, 8);
  for (int i = 0; i < kSamples; ++i) {
    const Vec2 u = next2(rng);
    if (rng.nextFloat() < 0.5f) {
      observed[size_t(cellOf(sampleUniformSphere(u)))] += 1;
    } else if (const std::optional<LightLiSample> s = light.sampleLi(ref, u, kLambda)) {
      observed[size_t(cellOf(frame.toLocal(s->wi)))] += 1;
    } else {
      observed.back() += 1;  // no sample
    }
  }
  // Mean density over a cell on an n x n grid; `mixed` tells whether the grid saw the edge.
  auto cellMean = [&](int ct, int pb, int n, bool& mixed) {
    double sum = 0;
    int hits = 0;
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) {
        const double z = -1.0 + (ct + (a + 0.5) / n) * 2.0 / kCosBins;
        const double phi = (pb + (b + 0.5) / n) * 2 * M_PI / kPhiBins;
        const double r = std::sqrt(std::max(0.0, 1 - z * z));
        const Vec3 w = frame.toWorld(Vec3(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)));
        sum += 0.5 * kUniformSpherePdfW;
        if (const std::optional<Vec3> hit = intersectTriangle(ref, w, t.p0, t.p1, t.p2)) {
          EmitterPoint e;
          e.p = *hit;
          e.n = light.normal();
          sum += 0.5 * light.pdfLi(ref, w, &e);
          ++hits;
        }
      }
    mixed = hits > 0 && hits < n * n;
    return sum / (n * n);
  };
  const double cellSolidAngle = (2.0 / kCosBins) * (2 * M_PI / kPhiBins);
  double total = 0;
  for (int ct = 0; ct < kCosBins; ++ct)
    for (int pb = 0; pb < kPhiBins; ++pb) {
      bool mixed = false;
      double mean = cellMean(ct, pb, 8, mixed);
      if (mixed) mean = cellMean(ct, pb, 64, mixed);
      expected[size_t(ct * kPhiBins + pb)] = mean * cellSolidAngle * kSamples;
      total += mean * cellSolidAngle;
    }
  expected.back() = std::max(0.0, 1.0 - total) * kSamples;
  if (expected.back() < 1e-3 * kSamples && observed.back() == 0) expected.back() = 0;
  test::ChiSquareResult r = test::chiSquareTest(observed, expected, 0.01, /*testCount=*/3);
  r.detail += ", density integral " + std::to_string(total);
  return r;
}

TEST(Light, UniformTriangleWarpIsHeitzMapBitForBit) {
  // The branch-free warp against the map's definition, on a grid with ties (u.x == u.y), zeros
  // and values just below one.
  const auto definition = [](Vec2 u) {
    if (u.x < u.y) return Vec2(u.x / 2.0f, u.y - u.x / 2.0f);
    return Vec2(u.x - u.y / 2.0f, u.y / 2.0f);
  };
  const float edge[] = {0.0f, 1e-30f, 0.25f, 0.5f, std::nextafter(1.0f, 0.0f)};
  std::vector<Vec2> us;
  for (float a : edge)
    for (float b : edge) us.push_back(Vec2(a, b));
  sampling::Pcg32 rng(3, 1);
  for (int i = 0; i < 100000; ++i) us.push_back(Vec2(rng.nextFloat(), rng.nextFloat()));
  for (const Vec2 u : us) {
    const Vec2 got = sampleUniformTriangle(u), want = definition(u);
    ASSERT_EQ(std::bit_cast<uint64_t>(got), std::bit_cast<uint64_t>(want)) << u.x << " " << u.y;
  }
}

TEST(Light, TriangleSampleLiDirectionsFollowPdfLi) {
  const TriangleLightDesc t = testTriangle();
  const ConstantEmission emission(1.0f);
  const TriangleLight light(t, &emission);
  // Far, close, and nearly in the triangle's plane: 0.03 in front of it, beyond vertex p1
  // (placed so that no edge is seen at a constant elevation or azimuth, where the cells'
  // quadrature would be least accurate).
  const Vec3 alongEdge = glm::normalize(t.p1 - t.p0);
  const Vec3 sideways = glm::normalize(glm::cross(light.normal(), alongEdge));
  const Vec3 inPlane = t.p1 + alongEdge * 0.5f + sideways * 0.15f + light.normal() * 0.03f;
  for (const Vec3& ref : {Vec3(0.0f), Vec3(0.6f, 0.05f, 0.0f), inPlane}) {
    const test::ChiSquareResult r = chiSquareTriangleLi(light, t, ref);
    EXPECT_TRUE(r.passed) << "ref " << ref.x << " " << ref.y << " " << ref.z << ": " << r.detail;
  }
}

TEST(Light, TriangleSampleLiReturnsTheEmissionAtTheSampledPoint) {
  const TriangleLightDesc t = testTriangle();
  const PlacedEmission emission(2.0f);
  const TriangleLight light(t, &emission);
  sampling::Pcg32 rng(4, 1);
  for (int i = 0; i < 1000; ++i) {
    const std::optional<LightLiSample> s = light.sampleLi(Vec3(0.0f), next2(rng), kLambda);
    ASSERT_TRUE(s);
    // The sampled point's barycentric of p1, from the area of the sub-triangle opposite it.
    const float b1 = 0.5f * glm::length(glm::cross(t.p0 - s->pLight, t.p2 - s->pLight)) / light.area();
    EXPECT_NEAR(s->L[0], 2.0f * (1.0f + b1), 1e-3f);
    EXPECT_EQ(s->L[5], 0.0f);  // lanes past the group's count stay black
    EXPECT_NEAR(s->distance, glm::length(s->pLight), 1e-5f);
    EXPECT_LT(dot3(s->wi, s->nLight), 0.0f);
  }
  // Seen from behind, the triangle emits nothing.
  EXPECT_FALSE(light.sampleLi(Vec3(3.0f, 0.0f, 0.0f), Vec2(0.3f, 0.3f), kLambda));
}

// The path tracer samples area lights with sampleLiDeferred and asks for the radiance only
// when the shadow ray is clear: that must be the very sample and value sampleLi gives.
TEST(Light, TriangleDeferredRadianceIsSampleLisRadiance) {
  const TriangleLightDesc t = testTriangle();
  const PlacedEmission emission(2.0f);
  const TriangleLight light(t, &emission);
  const PointLight point(Vec3(0.0f, 1.0f, 0.0f), SpectrumSource::constant(3.0f));
  sampling::Pcg32 rng(8, 2);
  for (int i = 0; i < 1000; ++i) {
    const Vec2 u = next2(rng);
    const Vec3 ref(rng.nextFloat() - 0.5f, rng.nextFloat() - 0.5f, rng.nextFloat() * 2.0f - 1.0f);
    const std::optional<LightLiSample> full = light.sampleLi(ref, u, kLambda);
    const std::optional<LightLiSample> deferred = light.sampleLiDeferred(ref, u, kLambda);
    ASSERT_EQ(bool(full), bool(deferred));
    if (!full) continue;
    EXPECT_FALSE(full->radianceDeferred);
    EXPECT_TRUE(deferred->radianceDeferred);
    EXPECT_TRUE(deferred->L.isBlack());
    EXPECT_EQ(deferred->pLight, full->pLight);
    EXPECT_EQ(deferred->wi, full->wi);
    EXPECT_EQ(deferred->pdfW, full->pdfW);
    EXPECT_EQ(deferred->distance, full->distance);
    const Spectrum L = light.deferredRadiance(*deferred, kLambda);
    for (int k = 0; k < kLanes; ++k) EXPECT_EQ(L[k], full->L[k]);
    EXPECT_GT(L[0], 2.0f);  // 2 (1 + u) with u > 0 somewhere inside: not a black default
  }
  // Lights without a deferred form give their radiance at once.
  const std::optional<LightLiSample> p = point.sampleLiDeferred(Vec3(0.0f), Vec2(0.5f), kLambda);
  ASSERT_TRUE(p);
  EXPECT_FALSE(p->radianceDeferred);
  EXPECT_EQ(point.deferredRadiance(*p, kLambda)[0], p->L[0]);
  EXPECT_GT(p->L[0], 0.0f);
}

// Lambert's formula for the irradiance from a uniform polygon of radiance L at a point with
// normal n (polygon above the horizon): E = L/2 sum_i angle(r_i, r_i+1) n . unit(r_i x r_i+1).
double polygonIrradiance(const std::vector<Vec3>& vertices, const Vec3& x, const Vec3& n, double L) {
  double sum = 0;
  for (size_t i = 0; i < vertices.size(); ++i) {
    const glm::dvec3 a = glm::normalize(glm::dvec3(vertices[i] - x));
    const glm::dvec3 b = glm::normalize(glm::dvec3(vertices[(i + 1) % vertices.size()] - x));
    sum += std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0)) * glm::dot(glm::dvec3(n), glm::normalize(glm::cross(a, b)));
  }
  return 0.5 * L * std::fabs(sum);
}

TEST(Light, TriangleNextEventEstimateEqualsAnalyticIrradiance) {
  const TriangleLightDesc t = testTriangle();
  const ConstantEmission emission(3.0f);
  const TriangleLight light(t, &emission);
  struct Receiver {
    Vec3 x, n;
  };
  const Receiver receivers[] = {{Vec3(0.0f), Vec3(1, 0, 0)},
                                {Vec3(0.5f, 0.3f, -0.2f), glm::normalize(Vec3(1, -0.4f, 0.2f))},
                                {Vec3(0.85f, -0.2f, 0.1f), glm::normalize(Vec3(1, 0.1f, 0.1f))}};  // the triangle above each horizon
  sampling::Pcg32 rng(6, 2);
  for (const Receiver& rcv : receivers) {
    SCOPED_TRACE(::testing::Message() << "receiver at " << rcv.x.x << " " << rcv.x.y << " " << rcv.x.z);
    for (const Vec3& p : {t.p0, t.p1, t.p2}) ASSERT_GT(dot3(p - rcv.x, rcv.n), 0.0f);
    MeanError estimate;
    for (int i = 0; i < 400000; ++i) {
      const std::optional<LightLiSample> s = light.sampleLi(rcv.x, next2(rng), kLambda);
      estimate.add(s ? double(s->L[0]) * std::max(0.0f, dot3(s->wi, rcv.n)) / s->pdfW : 0.0);
    }
    const double expected = polygonIrradiance({t.p0, t.p1, t.p2}, rcv.x, rcv.n, 3.0);
    EXPECT_NEAR(estimate.mean(), expected, 4.0 * estimate.error());
    EXPECT_LT(estimate.error(), 0.01 * expected);
    // A BSDF-style estimate (uniform hemisphere directions, hits weighted by pdfLi's
    // reciprocal through MIS-free importance) agrees too: E = integral of L cos over hits.
    MeanError hemisphere;
    const Frame frame = Frame::fromNormal(rcv.n);
    for (int i = 0; i < 400000; ++i) {
      const Vec3 w = frame.toWorld(sampleUniformHemisphere(next2(rng)));
      const bool hit = intersectTriangle(rcv.x, w, t.p0, t.p1, t.p2).has_value();
      hemisphere.add(hit ? 3.0 * dot3(w, rcv.n) / kUniformHemispherePdfW : 0.0);
    }
    EXPECT_NEAR(hemisphere.mean(), expected, 4.0 * hemisphere.error());
  }
}

// Chi-square of sampleLe's directions against `pdfW`, checking that pdfLe gives the densities
// sampleLe reports (position: uniform over the area).
template <class DirectionPdf>
test::ChiSquareResult chiSquareTriangleLe(const TriangleLight& light, const DirectionPdf& pdfW) {
  return test::chiSquareDirections(
      [&](Vec2 u, float u3) -> std::optional<Vec3> {
        const std::optional<LightLeSample> s = light.sampleLe(Vec2(u3, 1.0f - u3), u, kLambda);
        if (!s) return std::nullopt;
        float pdfPosA, pdfDirW;
        light.pdfLe(s->ray, s->nLight, pdfPosA, pdfDirW);
        EXPECT_NEAR(pdfDirW, s->pdfDirW, 1e-4f * s->pdfDirW);
        EXPECT_NEAR(pdfPosA, 1.0f / light.area(), 1e-5f);
        return s->ray.direction;
      },
      pdfW);
}

// A two-sided triangle (a double-sided glTF emitter) is sampled from behind as from the front:
// samples follow pdfLi there too, next-event estimates match the analytic irradiance on both
// sides, its power counts both, and sampleLe leaves from either side with half the density.
TEST(Light, TwoSidedTriangleIsSampledFromBothSides) {
  TriangleLightDesc t = testTriangle();
  t.twoSided = true;
  const ConstantEmission emission(3.0f);
  const TriangleLight light(t, &emission);
  TriangleLightDesc oneSided = testTriangle();
  EXPECT_NEAR(light.power(), 2.0f * TriangleLight(oneSided, &emission).power(), 1e-5f);
  const Vec3 behind = Vec3(0.6f, 0.05f, 0.0f) - 1.2f * light.normal();
  const test::ChiSquareResult r = chiSquareTriangleLi(light, t, behind);
  EXPECT_TRUE(r.passed) << r.detail;
  sampling::Pcg32 rng(9, 4);
  for (const float side : {1.0f, -1.0f}) {
    const Vec3 x = Vec3(0.5f, 0.3f, -0.2f) * 0.2f + (t.p0 + t.p1 + t.p2) / 3.0f + side * 0.7f * light.normal();
    const Vec3 n = -side * light.normal();  // the receiver faces the triangle
    MeanError estimate;
    for (int i = 0; i < 200000; ++i) {
      const std::optional<LightLiSample> s = light.sampleLi(x, next2(rng), kLambda);
      if (s) EXPECT_GT(dot3(s->nLight, x - s->pLight), 0.0f);  // the side facing x
      estimate.add(s ? double(s->L[0]) * std::max(0.0f, dot3(s->wi, n)) / s->pdfW : 0.0);
    }
    const double expected = polygonIrradiance({t.p0, t.p1, t.p2}, x, n, 3.0);
    EXPECT_NEAR(estimate.mean(), expected, 4.0 * estimate.error()) << "side " << side;
    EXPECT_LT(estimate.error(), 0.01 * expected);
  }
  const test::ChiSquareResult le = chiSquareTriangleLe(
      light, [&](const Vec3& w) -> double { return 0.5 * cosineHemispherePdfW(std::fabs(dot3(w, light.normal()))); });
  EXPECT_TRUE(le.passed) << le.detail;
}

TEST(Light, TriangleSampleLeIsCosineWeighted) {
  TriangleLightDesc t = testTriangle();
  t.normal = glm::normalize(Vec3(-1.0f, 0.3f, 0.5f));  // flips the face normal to this side
  const ConstantEmission emission(1.0f);
  const TriangleLight light(t, &emission);
  ASSERT_GT(dot3(light.normal(), t.normal), 0.0f);
  const test::ChiSquareResult r =
      chiSquareTriangleLe(light, [&](const Vec3& w) -> double { return cosineHemispherePdfW(dot3(w, light.normal())); });
  EXPECT_TRUE(r.passed) << r.detail;
  EXPECT_NEAR(light.power(), kPi * light.area() * 1.0f, 1e-5f);
}

TEST(Light, PointSampleLeIsUniformOverTheSphere) {
  const PointLight light(Vec3(1, 2, 3), SpectrumSource::constant(2.0f));
  const test::ChiSquareResult r = test::chiSquareDirections(
      [&](Vec2 u, float) -> std::optional<Vec3> {
        const std::optional<LightLeSample> s = light.sampleLe(Vec2(0.5f), u, kLambda);
        if (!s) return std::nullopt;
        EXPECT_EQ(s->ray.origin, Vec3(1, 2, 3));
        return s->ray.direction;
      },
      [](const Vec3&) -> double { return kUniformSpherePdfW; });
  EXPECT_TRUE(r.passed) << r.detail;
  const std::optional<LightLiSample> li = light.sampleLi(Vec3(1, 2, 1), Vec2(0.5f), kLambda);
  ASSERT_TRUE(li);
  EXPECT_TRUE(li->delta);
  EXPECT_NEAR(li->L[0], 2.0f / 4.0f, 1e-6f);  // I / d^2
  EXPECT_NEAR(li->wi.z, 1.0f, 1e-6f);
}

TEST(Light, SpotFalloffIsGltfs) {
  const float inner = 0.3f, outer = 0.6f;
  const SpotLight light(Vec3(0, 5, 0), Vec3(0, -1, 0), SpectrumSource::constant(4.0f), inner, outer);
  auto radianceAt = [&](float angle) -> float {
    const Vec3 ref(5.0f * std::tan(angle), 0.0f, 0.0f);  // on the floor, `angle` off the axis
    const std::optional<LightLiSample> s = light.sampleLi(ref, Vec2(0.5f), kLambda);
    if (!s) return 0.0f;
    return s->L[0] * s->distance * s->distance / 4.0f;  // the falloff factor
  };
  EXPECT_NEAR(radianceAt(0.0f), 1.0f, 1e-5f);
  EXPECT_NEAR(radianceAt(0.29f), 1.0f, 1e-5f);
  for (float angle : {0.35f, 0.45f, 0.55f}) {
    const float t = (std::cos(angle) - std::cos(outer)) / (std::cos(inner) - std::cos(outer));
    EXPECT_NEAR(radianceAt(angle), t * t, 1e-4f) << angle;
  }
  EXPECT_EQ(radianceAt(0.61f), 0.0f);
  EXPECT_FALSE(light.sampleLi(Vec3(0, 6, 0), Vec2(0.5f), kLambda));  // behind the spot
  // Power: the falloff integrated over the sphere (Monte Carlo), times I.
  sampling::Pcg32 rng(8, 3);
  MeanError integral;
  for (int i = 0; i < 400000; ++i) integral.add(light.falloff(sampleUniformSphere(next2(rng))) / kUniformSpherePdfW);
  const float luminance = SpectrumSource::constant(4.0f).luminance();
  EXPECT_NEAR(light.power() / luminance, integral.mean(), 4.0 * integral.error());
  // Emitted rays stay in the outer cone and carry the falloff.
  for (int i = 0; i < 1000; ++i) {
    const std::optional<LightLeSample> s = light.sampleLe(Vec2(0.5f), next2(rng), kLambda);
    if (!s) continue;
    EXPECT_GE(-s->ray.direction.y, std::cos(outer) - 1e-5f);
    EXPECT_NEAR(s->L[0], 4.0f * light.falloff(s->ray.direction), 1e-5f);
    float pdfPosA, pdfDirW;
    light.pdfLe(s->ray, s->nLight, pdfPosA, pdfDirW);
    EXPECT_NEAR(pdfDirW, s->pdfDirW, 1e-4f * pdfDirW);
  }
}

// Narrow spots reach full intensity on their axis and keep glTF's ramp: the spec's pseudocode
// bound cos(inner) - cos(outer) below by 0.001, so a 1-degree spot lit its own axis at 2 % of
// its intensity, and below 0.014 degrees cos(outer) rounded to 1 and the spot went dark.
TEST(Light, NarrowSpotsLightTheirAxisFully) {
  for (const float outerDeg : {1.0f, 0.05f, 0.001f}) {
    const float outer = outerDeg * kPi / 180.0f, inner = 0.5f * outer;
    const SpotLight light(Vec3(0, 2, 0), Vec3(0, -1, 0), SpectrumSource::constant(10.0f), inner, outer);
    auto falloffAt = [&](float angle) -> double {
      const std::optional<LightLiSample> s = light.sampleLi(Vec3(2.0f * std::tan(angle), 0.0f, 0.0f), Vec2(0.5f), kLambda);
      return s ? double(s->L[0]) * s->distance * s->distance / 10.0 : 0.0;
    };
    EXPECT_NEAR(falloffAt(0.0f), 1.0, 1e-5) << outerDeg;
    EXPECT_NEAR(falloffAt(0.4f * outer), 1.0, 1e-5) << outerDeg;
    // Halfway through the band, in 1 - cos (about the squared angle for narrow cones).
    const double a = 0.75 * outer, vIn = 1 - std::cos(double(inner)), vOut = 1 - std::cos(double(outer));
    const double t = (vOut - (1 - std::cos(a))) / (vOut - vIn);
    EXPECT_NEAR(falloffAt(float(a)), t * t, 2e-3) << outerDeg;
    EXPECT_EQ(falloffAt(1.05f * outer), 0.0) << outerDeg;
    // Power: 2 pi I times the falloff integrated over cos, v_inner + (v_outer - v_inner) / 3.
    const double integral = vIn + (vOut - vIn) / 3.0;
    EXPECT_NEAR(light.power() / SpectrumSource::constant(10.0f).luminance(), 2.0 * kPi * integral, 1e-3 * 2.0 * kPi * integral);
  }
}

TEST(Light, DirectionalEmitsParallelRaysThroughTheSceneDisk) {
  DirectionalLight light(glm::normalize(Vec3(1, -2, 0.5f)), SpectrumSource::constant(3.0f));
  SceneSphere sphere{Vec3(1, 2, 3), 4.0f};
  light.preprocess(sphere);
  const Vec3 dir = glm::normalize(Vec3(1, -2, 0.5f));
  const std::optional<LightLiSample> li = light.sampleLi(Vec3(0.0f), Vec2(0.5f), kLambda);
  ASSERT_TRUE(li);
  EXPECT_NEAR(dot3(li->wi, -dir), 1.0f, 1e-6f);
  EXPECT_EQ(li->distance, kInfinity);
  EXPECT_NEAR(li->L[0], 3.0f, 1e-6f);
  sampling::Pcg32 rng(2, 2);
  for (int i = 0; i < 1000; ++i) {
    const std::optional<LightLeSample> s = light.sampleLe(next2(rng), next2(rng), kLambda);
    ASSERT_TRUE(s);
    EXPECT_NEAR(dot3(s->ray.direction, dir), 1.0f, 1e-6f);
    const Vec3 rel = s->ray.origin - sphere.center;
    EXPECT_NEAR(dot3(rel, dir), -sphere.radius, 1e-4f);  // one radius upstream
    EXPECT_LE(glm::length(rel - dir * dot3(rel, dir)), sphere.radius * (1 + 1e-5f));
    EXPECT_NEAR(s->pdfPosA, 1.0f / (kPi * 16.0f), 1e-7f);
  }
  EXPECT_NEAR(light.power(), kPi * 16.0f * SpectrumSource::constant(3.0f).luminance(), 1e-3f);
}

TEST(Light, ConstantEnvironmentSamplesTheSphereUniformly) {
  ConstantEnvironment light(SpectrumSource::constant(0.5f));
  light.preprocess(SceneSphere{Vec3(0.0f), 10.0f});
  const Vec3 ref(1, 2, 3);
  const test::ChiSquareResult r = test::chiSquareDirections(
      [&](Vec2 u, float) -> std::optional<Vec3> {
        const std::optional<LightLiSample> s = light.sampleLi(ref, u, kLambda);
        if (!s) return std::nullopt;
        EXPECT_NEAR(s->L[0], 0.5f, 1e-6f);
        return s->wi;
      },
      [&](const Vec3& w) -> double { return light.pdfLi(ref, w, nullptr); });
  EXPECT_TRUE(r.passed) << r.detail;
  EXPECT_NEAR(light.Le(Ray{ref, Vec3(0, 1, 0)}, kLambda)[2], 0.5f, 1e-6f);
}

// A lat-long map written to a temporary EXR: a soft colour gradient and a bright spot.
struct TempEnvironmentFile {
  std::string path;
  RgbImage image;
  TempEnvironmentFile(const std::string& name, bool grey) {
    path = (std::filesystem::temp_directory_path() / (name + "_" + std::to_string(getpid()) + ".exr")).string();
    image.width = 64, image.height = 32;
    image.rgb.resize(size_t(64 * 32 * 3));
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 64; ++x) {
        Vec3 c(0.2f + 0.3f * x / 64.0f, 0.1f + 0.4f * y / 32.0f, 0.3f);
        if (x >= 40 && x <= 42 && y >= 10 && y <= 11) c = Vec3(40, 30, 20);  // the sun
        if (y == 31) c = Vec3(0.0f);                                         // a black row at the bottom
        if (grey) c = Vec3(c.x + c.y + c.z);
        for (int k = 0; k < 3; ++k) image.rgb[size_t((y * 64 + x) * 3 + k)] = c[k];
      }
    const std::string error = writeRgbImage(path, image);
    EXPECT_EQ(error, "");
  }
  ~TempEnvironmentFile() { std::filesystem::remove(path); }
};

TEST(Light, ImageEnvironmentSampleLiFollowsPdfLi) {
  const TempEnvironmentFile file("tex_light_test_env", false);
  std::string error;
  std::unique_ptr<ImageEnvironment> light = loadImageEnvironment(file.path, Mat4(1.0f), 1.0f, error);
  ASSERT_TRUE(light) << error;
  light->preprocess(SceneSphere{Vec3(0.0f), 5.0f});
  // Binned in the map's own coordinates (u = phi / 2pi, v = theta / pi), 64 x 64 cells on the
  // 64 x 32 pixels, so the density jumps only on cell edges; the density per (u, v) is
  // pdfW * 2 pi^2 sin(theta).
  const Vec3 ref(0.3f, -0.2f, 0.1f);
  int mismatches = 0;
  const test::ChiSquareResult r = test::chiSquarePoints(
      [&](Vec2 u, float) -> std::optional<Vec2> {
        const std::optional<LightLiSample> s = light->sampleLi(ref, u, kLambda);
        if (!s) return std::nullopt;
        // pdfLi and Le of the sampled direction are what sampleLi returned.
        const float pdf = light->pdfLi(ref, s->wi, nullptr);
        const Spectrum le = light->Le(Ray{ref, s->wi}, kLambda);
        if (std::fabs(pdf - s->pdfW) > 1e-5f * s->pdfW || std::fabs(le[1] - s->L[1]) > 1e-5f * s->L[1]) ++mismatches;
        return directionToSphericalYUp(s->wi);
      },
      [&](Vec2 uv) -> double {
        return light->pdfLi(ref, sphericalDirectionYUp(uv.x, uv.y), nullptr) * 2.0 * kPi * kPi * std::sin(kPi * uv.y);
      },
      /*bins=*/64);
  EXPECT_TRUE(r.passed) << r.detail;
  EXPECT_LE(mismatches, 10);  // only directions that round onto a pixel boundary
  EXPECT_EQ(light->pdfLi(ref, sphericalDirectionYUp(0.3f, 31.5f / 32.0f), nullptr), 0.0f);  // the black row
  EXPECT_TRUE(light->Le(Ray{ref, sphericalDirectionYUp(0.3f, 31.5f / 32.0f)}, kLambda).isBlack());
}

TEST(Light, ImageEnvironmentRadianceOverPdfIsConstantWhenSampledByItsLuminance) {
  // A grey map: the spectrum's shape is the same everywhere, so L / pdf is one constant per
  // wavelength, equal to the luminance integral times that shape.
  const TempEnvironmentFile file("tex_light_test_grey_env", true);
  std::string error;
  std::unique_ptr<ImageEnvironment> light = loadImageEnvironment(file.path, Mat4(1.0f), 2.0f, error);
  ASSERT_TRUE(light) << error;
  sampling::Pcg32 rng(12, 4);
  std::optional<Spectrum> first;
  float minPdf = INFINITY, maxPdf = 0;
  for (int i = 0; i < 100000; ++i) {
    const std::optional<LightLiSample> s = light->sampleLi(Vec3(0.0f), next2(rng), kLambda);
    ASSERT_TRUE(s);
    ASSERT_GT(s->pdfW, 0.0f);
    minPdf = std::min(minPdf, s->pdfW), maxPdf = std::max(maxPdf, s->pdfW);
    const Spectrum ratio = s->L * (1.0f / s->pdfW);
    if (!first) first = ratio;
    for (int k = 0; k < kLambda.count; ++k) ASSERT_NEAR(ratio[k], (*first)[k], 1e-4f * (*first)[k]) << i;
  }
  EXPECT_GT(maxPdf, 50.0f * minPdf);  // the sampling is far from uniform
}

TEST(Light, ImageEnvironmentRotatesWithItsTransform) {
  const TempEnvironmentFile file("tex_light_test_rot_env", false);
  const Mat4 rotation = glm::rotate(Mat4(1.0f), 0.9f, glm::normalize(Vec3(1, 2, -1)));
  std::string error;
  std::unique_ptr<ImageEnvironment> plain = loadImageEnvironment(file.path, Mat4(1.0f), 1.0f, error);
  std::unique_ptr<ImageEnvironment> rotated = loadImageEnvironment(file.path, rotation, 1.0f, error);
  ASSERT_TRUE(plain && rotated) << error;
  const glm::mat3 r(rotation);
  sampling::Pcg32 rng(13, 5);
  for (int i = 0; i < 1000; ++i) {
    const Vec2 u = next2(rng);
    const std::optional<LightLiSample> a = plain->sampleLi(Vec3(0.0f), u, kLambda);
    const std::optional<LightLiSample> b = rotated->sampleLi(Vec3(0.0f), u, kLambda);
    ASSERT_TRUE(a && b);
    EXPECT_GT(dot3(r * a->wi, b->wi), 1.0f - 1e-5f);
    EXPECT_NEAR(a->pdfW, b->pdfW, 1e-5f * a->pdfW);
    EXPECT_NEAR(a->L[0], b->L[0], 1e-5f * a->L[0]);
  }
  EXPECT_NEAR(plain->power(), rotated->power(), 1e-5f * plain->power());
}

// A matrix that shears (not a rotation times a scale) orients the sky by its nearest rotation,
// the same one for light samples and for rays: normalising its columns had sent samples out
// through one matrix and looked rays up through its transpose, which is no inverse (the sun
// that lit the scene was 10 degrees from the one rays saw). Scene files refuse such matrices.
TEST(Light, ImageEnvironmentSamplesAndRaysSeeOneSkyUnderAShearingMatrix) {
  const TempEnvironmentFile file("tex_light_test_shear_env", false);
  const Mat4 sheared = glm::scale(Mat4(1.0f), Vec3(1, 3, 1)) * glm::rotate(Mat4(1.0f), 0.7f, Vec3(0, 0, 1));
  std::string error;
  std::unique_ptr<ImageEnvironment> light = loadImageEnvironment(file.path, sheared, 1.0f, error);
  ASSERT_TRUE(light) << error;
  sampling::Pcg32 rng(14, 5);
  int mismatches = 0;
  for (int i = 0; i < 4000; ++i) {
    const std::optional<LightLiSample> s = light->sampleLi(Vec3(0.0f), next2(rng), kLambda);
    ASSERT_TRUE(s);
    const float pdf = light->pdfLi(Vec3(0.0f), s->wi, nullptr);
    const Spectrum le = light->Le(Ray{Vec3(0.0f), s->wi}, kLambda);
    if (std::fabs(pdf - s->pdfW) > 1e-4f * s->pdfW || std::fabs(le[1] - s->L[1]) > 1e-4f * s->L[1]) ++mismatches;
  }
  EXPECT_LE(mismatches, 10);  // only directions that round onto a pixel boundary
}

TEST(Light, ImageEnvironmentSampleLeMatchesPdfLe) {
  const TempEnvironmentFile file("tex_light_test_le_env", false);
  std::string error;
  std::unique_ptr<ImageEnvironment> light = loadImageEnvironment(file.path, Mat4(1.0f), 1.0f, error);
  ASSERT_TRUE(light) << error;
  const SceneSphere sphere{Vec3(1, 0, 0), 3.0f};
  light->preprocess(sphere);
  sampling::Pcg32 rng(14, 6);
  for (int i = 0; i < 2000; ++i) {
    const std::optional<LightLeSample> s = light->sampleLe(next2(rng), next2(rng), kLambda);
    ASSERT_TRUE(s);
    // The ray crosses the scene sphere's disk, heading into the scene.
    const Vec3 rel = sphere.center - s->ray.origin;
    const float along = dot3(rel, s->ray.direction);
    EXPECT_NEAR(along, sphere.radius, 1e-3f);
    EXPECT_LE(glm::length(rel - s->ray.direction * along), sphere.radius * (1 + 1e-4f));
    float pdfPosA, pdfDirW;
    light->pdfLe(s->ray, s->nLight, pdfPosA, pdfDirW);
    EXPECT_NEAR(pdfPosA, s->pdfPosA, 1e-6f);
    EXPECT_NEAR(pdfDirW, s->pdfDirW, 1e-4f * s->pdfDirW + 1e-6f);
  }
}

TEST(Light, ImageEnvironmentReportsABadFileByName) {
  std::string error;
  EXPECT_FALSE(loadImageEnvironment("/nonexistent/dir/sky.exr", Mat4(1.0f), 1.0f, error));
  EXPECT_NE(error.find("/nonexistent/dir/sky.exr"), std::string::npos) << error;
  const std::string garbage = (std::filesystem::temp_directory_path() / ("tex_light_test_garbage_" + std::to_string(getpid()) + ".exr")).string();
  std::ofstream(garbage) << "this is not an OpenEXR file";
  EXPECT_FALSE(loadImageEnvironment(garbage, Mat4(1.0f), 1.0f, error));
  EXPECT_NE(error.find(garbage), std::string::npos) << error;
  std::filesystem::remove(garbage);
  LightDesc desc;
  desc.kind = LightDesc::Kind::ImageEnvironment;
  desc.name = "sky";
  desc.imagePath = "/nonexistent/dir/sky.exr";
  EXPECT_FALSE(makeLight(desc, error));
  EXPECT_NE(error.find("sky"), std::string::npos);
  EXPECT_NE(error.find("/nonexistent/dir/sky.exr"), std::string::npos) << error;
}

// A light that only has a power (for the light sampler).
class FixedPowerLight final : public Light {
 public:
  explicit FixedPowerLight(float power) : power_(power) {}
  LightKind kind() const override { return LightKind::Point; }
  float power() const override { return power_; }
  std::optional<LightLiSample> sampleLi(const Vec3&, Vec2, const Wavelengths&) const override { return std::nullopt; }
  float pdfLi(const Vec3&, const Vec3&, const EmitterPoint*) const override { return 0; }
  std::optional<LightLeSample> sampleLe(Vec2, Vec2, const Wavelengths&) const override { return std::nullopt; }
  void pdfLe(const Ray&, const Vec3&, float& a, float& b) const override { a = b = 0; }

 private:
  float power_;
};

TEST(Light, SamplerPicksInProportionToPower) {
  const std::vector<float> powers = {1.0f, 0.0f, 3.0f, 0.5f, 10.0f, 0.0f, 2.5f};
  std::vector<FixedPowerLight> lights;
  for (float p : powers) lights.emplace_back(p);
  std::vector<const Light*> pointers;
  for (const FixedPowerLight& l : lights) pointers.push_back(&l);
  const LightSampler sampler(pointers);
  ASSERT_EQ(sampler.size(), int(powers.size()));
  const double total = 17.0;
  std::vector<double> observed(powers.size(), 0.0), expected(powers.size(), 0.0);
  sampling::Pcg32 rng(15, 7);
  constexpr int kSamples = 1000000;
  for (int i = 0; i < kSamples; ++i) {
    const auto pick = sampler.samplePower(rng.nextFloat());
    ASSERT_TRUE(pick);
    observed[size_t(pick->first)] += 1;
    ASSERT_EQ(pick->second, sampler.pmfPower(pick->first));
  }
  for (size_t i = 0; i < powers.size(); ++i) {
    expected[i] = powers[i] / total * kSamples;
    EXPECT_NEAR(sampler.pmfPower(int(i)), powers[i] / total, 1e-6);
  }
  const test::ChiSquareResult r = test::chiSquareTest(observed, expected);
  EXPECT_TRUE(r.passed) << r.detail;
  EXPECT_EQ(observed[1], 0.0);
  EXPECT_EQ(observed[5], 0.0);
  // The ends of [0,1), and u outside it, pick lights with power.
  for (const float u : {0.0f, 0x1.fffffep-1f, 1.0f, -0.5f, std::numeric_limits<float>::quiet_NaN()})
    EXPECT_GT(sampler.pmfPower(sampler.samplePower(u)->first), 0.0f) << u;
  // No light with power: nothing to choose.
  const FixedPowerLight dark(0.0f);
  const Light* darkOnly[] = {&dark, &dark};
  EXPECT_FALSE(LightSampler(darkOnly).samplePower(0.5f));
  EXPECT_FALSE(LightSampler(std::span<const Light* const>()).samplePower(0.5f));
}

// A power that overflows a float (4 pi I for I = 3e38, or a sun over a scene of huge bounds)
// still gets chosen; it had been left out like a broken light, and a scene lit by it alone was
// black. NaN powers stay out. A light whose intensity times emission overflows is an error.
TEST(Light, OverflowingPowersAreChosenAndOverflowingEmissionIsAnError) {
  const FixedPowerLight huge(INFINITY), dim(1.0f), broken(NAN);
  const Light* lights[] = {&dim, &huge, &broken};
  const LightSampler sampler(lights);
  EXPECT_GT(sampler.pmfPower(1), 0.99f);
  EXPECT_GT(sampler.pmfPower(0), 0.0f);
  EXPECT_EQ(sampler.pmfPower(2), 0.0f);
  EXPECT_EQ(sampler.samplePower(0.5f)->first, 1);
  LightDesc desc;
  desc.kind = LightDesc::Kind::Point;
  desc.name = "bright";
  desc.emission.kind = SpectrumDesc::Kind::Rgb;
  desc.emission.rgb = Vec3(1.0f);
  desc.intensity = 1e38f;  // its luminance is a float, its power 4 pi I is not
  std::string error;
  std::unique_ptr<Light> point = makeLight(desc, error);
  ASSERT_TRUE(point) << error;
  EXPECT_EQ(point->power(), INFINITY);
  const Light* alone[] = {point.get()};
  EXPECT_EQ(LightSampler(alone).pmfPower(0), 1.0f);
  desc.intensity = 1e20f;
  desc.emission.scale = 1e20f;
  EXPECT_FALSE(makeLight(desc, error));
  EXPECT_NE(error.find("light 'bright': its intensity times its emission overflows a 32-bit float"), std::string::npos) << error;
}

TEST(Light, FactoryBuildsEachKindFromItsDescription) {
  LightDesc desc;
  desc.emission.kind = SpectrumDesc::Kind::Constant;
  desc.emission.value = 2.0f;
  desc.intensity = 3.0f;
  desc.position = Vec3(0, 0, 2);
  std::string error;
  desc.kind = LightDesc::Kind::Point;
  std::unique_ptr<Light> point = makeLight(desc, error);
  ASSERT_TRUE(point) << error;
  EXPECT_EQ(point->kind(), LightKind::Point);
  EXPECT_NEAR(point->sampleLi(Vec3(0.0f), Vec2(0.5f), kLambda)->L[0], 6.0f / 4.0f, 1e-5f);
  desc.kind = LightDesc::Kind::Spot;
  EXPECT_EQ(makeLight(desc, error)->kind(), LightKind::Spot);
  desc.kind = LightDesc::Kind::Directional;
  EXPECT_EQ(makeLight(desc, error)->kind(), LightKind::Directional);
  desc.kind = LightDesc::Kind::ConstantEnvironment;
  std::unique_ptr<Light> env = makeLight(desc, error);
  EXPECT_EQ(env->kind(), LightKind::ConstantEnvironment);
  EXPECT_NEAR(env->Le(Ray{}, kLambda)[0], 6.0f, 1e-5f);
  const TempEnvironmentFile file("tex_light_test_factory_env", false);
  desc.kind = LightDesc::Kind::ImageEnvironment;
  desc.imagePath = file.path;
  std::unique_ptr<Light> image = makeLight(desc, error);
  ASSERT_TRUE(image) << error;
  EXPECT_EQ(image->kind(), LightKind::ImageEnvironment);
  EXPECT_GT(image->power(), 0.0f);
}

bool finite(const LightLiSample& s) {
  return !s.L.hasNaNOrInf() && std::isfinite(s.pdfW) && s.pdfW > 0 && std::isfinite(s.wi.x + s.wi.y + s.wi.z);
}

TEST(Light, NoNaNAtGrazingAnglesOrDegenerateInputs) {
  const TriangleLightDesc t = testTriangle();
  const ConstantEmission emission(1.0f);
  const TriangleLight light(t, &emission);
  const Vec3 centroid = (t.p0 + t.p1 + t.p2) / 3.0f;
  const Vec3 inPlaneOutside = centroid + (t.p1 - centroid) * 2.0f;  // exactly in the plane (up to rounding)
  const float us[] = {0.0f, 1e-7f, 0.5f, 0x1.fffffep-1f};
  for (const Vec3& ref : {inPlaneOutside, t.p0, t.p1, centroid, Vec3(3, 0, 0)})
    for (float a : us)
      for (float b : us) {
        if (const std::optional<LightLiSample> s = light.sampleLi(ref, Vec2(a, b), kLambda)) {
          EXPECT_TRUE(finite(*s)) << a << " " << b;
        }
        EmitterPoint e = light.pointAt(sampleUniformTriangle(Vec2(a, b)));
        const float pdf = light.pdfLi(ref, glm::normalize(e.p - ref + Vec3(1e-9f)), &e);
        EXPECT_TRUE(std::isfinite(pdf) && pdf >= 0.0f);
        if (const std::optional<LightLeSample> s = light.sampleLe(Vec2(a, b), Vec2(b, a), kLambda)) {
          EXPECT_TRUE(std::isfinite(s->pdfDirW) && s->pdfDirW > 0 && !s->L.hasNaNOrInf());
        }
      }
  // A triangle of zero area emits nothing and samples nothing.
  TriangleLightDesc degenerate = t;
  degenerate.p2 = degenerate.p1;
  const TriangleLight flat(degenerate, &emission);
  EXPECT_EQ(flat.power(), 0.0f);
  EXPECT_FALSE(flat.sampleLi(Vec3(0.0f), Vec2(0.5f), kLambda));
  // Environments at the poles and on the seam.
  const TempEnvironmentFile file("tex_light_test_nan_env", false);
  std::string error;
  std::unique_ptr<ImageEnvironment> env = loadImageEnvironment(file.path, Mat4(1.0f), 1.0f, error);
  ASSERT_TRUE(env) << error;
  for (const Vec3& w : {Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, -1), Vec3(0, 0, 1), Vec3(-1e-8f, 0, -1)}) {
    EXPECT_TRUE(std::isfinite(env->pdfLi(Vec3(0.0f), w, nullptr)));
    EXPECT_FALSE(env->Le(Ray{Vec3(0.0f), w}, kLambda).hasNaNOrInf());
  }
  for (float a : us)
    for (float b : us)
      if (const std::optional<LightLiSample> s = env->sampleLi(Vec3(0.0f), Vec2(a, b), kLambda)) {
        EXPECT_TRUE(finite(*s)) << a << " " << b;
      }
  // A spot light with a zero cone, a point light at the reference point.
  const SpotLight needle(Vec3(0.0f), Vec3(0, 0, 1), SpectrumSource::constant(1.0f), 0.0f, 0.0f);
  EXPECT_EQ(needle.power(), 0.0f);
  EXPECT_FALSE(needle.sampleLe(Vec2(0.5f), Vec2(0.5f), kLambda));
  // An inconsistent in-memory image is a black environment, not a crash.
  RgbImage broken;
  broken.width = 4, broken.height = 2;
  broken.rgb.assign(5, 1.0f);
  const ImageEnvironment black(broken, Mat4(1.0f));
  EXPECT_EQ(black.power(), 0.0f);
  EXPECT_FALSE(black.sampleLi(Vec3(0.0f), Vec2(0.5f), kLambda));
  EXPECT_TRUE(black.Le(Ray{}, kLambda).isBlack());
  const PointLight point(Vec3(1.0f), SpectrumSource::constant(1.0f));
  EXPECT_FALSE(point.sampleLi(Vec3(1.0f), Vec2(0.5f), kLambda));
}

}  // namespace
}  // namespace tex::render

namespace tex::render {
namespace {

// Pixels that cannot emit (NaN, infinite, negative) emit nothing and are counted, so that
// `tex render` can warn about them instead of dropping them silently.
TEST(ImageEnvironmentLight, BrokenPixelsEmitNothingAndAreCounted) {
  RgbImage image;
  image.width = 4;
  image.height = 2;
  image.rgb.assign(4 * 2 * 3, 0.5f);
  image.rgb[0] = std::numeric_limits<float>::quiet_NaN();  // pixel 0
  image.rgb[4] = std::numeric_limits<float>::infinity();   // pixel 1
  image.rgb[8] = -1.0f;                                     // pixel 2
  image.rgb[7] = -2.0f;                                     // still pixel 2
  const ImageEnvironment env(image, Mat4(1.0f));
  EXPECT_EQ(env.droppedPixels(), 3u);
  // Dropped whole: the same power as the image with those pixels black (only the broken
  // channel used to be zeroed, and a (NaN, 5, 5) pixel still lit the scene cyan).
  RgbImage black = image;
  for (size_t k = 0; k < 9; ++k) black.rgb[k] = 0.0f;
  EXPECT_EQ(env.power(), ImageEnvironment(black, Mat4(1.0f)).power());
  image.rgb.assign(4 * 2 * 3, 0.5f);
  EXPECT_EQ(ImageEnvironment(image, Mat4(1.0f)).droppedPixels(), 0u);
}

}  // namespace
}  // namespace tex::render
