// BSDF lobes and their mixture: sampled directions follow the claimed densities (chi-square),
// discrete events follow their probabilities, Fresnel matches independent complex-arithmetic
// formulas, Snell's law and total internal reflection hold, the mixture rejects light leaks and
// applies the adjoint shading-normal correction, and no input produces NaN.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <complex>
#include <cstring>
#include <vector>

#include "renderer/bsdf/bsdf.h"
#include "renderer/core/warp.h"
#include "renderer/sampling/pcg.h"
#include "tests/renderer/chi_square.h"

namespace tex::render {
namespace {

// Every chi-square run in this file: the Sidak correction keeps the suite's false-alarm rate 1%.
constexpr int kChiSquareRuns = 17;  // 4 + 4 + 2 + 1 + 6 below
constexpr int kSamples = 1000000;

Spectrum lanes(std::initializer_list<float> values) {
  Spectrum s;
  int i = 0;
  for (float v : values) s[i++] = v;
  return s;
}

Lobe lambertian(const Spectrum& albedo) {
  Lobe l;
  l.kind = LobeKind::Lambertian;
  l.weight = albedo;
  return l;
}

Lobe dielectric(const Spectrum& eta, bool etaVaries, const Spectrum& weight = lanes({1, 1, 1, 1})) {
  Lobe l;
  l.kind = LobeKind::SmoothDielectric;
  l.etaVaries = etaVaries;
  l.weight = weight;
  l.a = eta;
  return l;
}

Lobe conductor(const Spectrum& eta, const Spectrum& k, const Spectrum& weight = lanes({1, 1, 1, 1})) {
  Lobe l;
  l.kind = LobeKind::SmoothConductor;
  l.weight = weight;
  l.a = eta;
  l.b = k;
  return l;
}

Vec3 fromAngles(float thetaRad, float phiRad) {
  return Vec3(std::sin(thetaRad) * std::cos(phiRad), std::sin(thetaRad) * std::sin(phiRad), std::cos(thetaRad));
}

test::DirectionTestOptions chiOptions(uint64_t seed) {
  test::DirectionTestOptions o;
  o.samples = kSamples;
  o.testCount = kChiSquareRuns;
  o.seed = seed;
  return o;
}

// Exact unpolarised Fresnel reflectance for light from index 1 onto n = eta + i k, with complex
// arithmetic in double (Born & Wolf 14.2): n cos(theta_t) = sqrt(n^2 - sin^2 theta_i).
double fresnelReference(double cosI, double eta, double k) {
  const std::complex<double> n2 = std::complex<double>(eta, k) * std::complex<double>(eta, k);
  const double sin2 = 1.0 - cosI * cosI;
  const std::complex<double> nCosT = std::sqrt(n2 - sin2);
  const std::complex<double> rs = (cosI - nCosT) / (cosI + nCosT);
  const std::complex<double> rp = (n2 * cosI - nCosT) / (n2 * cosI + nCosT);
  return 0.5 * (std::norm(rs) + std::norm(rp));
}

// A shading frame tilted 30 degrees away from the geometric normal +z (the chi-square bins are
// z-up, so the geometric horizon lies on a bin boundary).
Bsdf tiltedBsdf() {
  const Vec3 ns = glm::normalize(Vec3(std::sin(0.5236f), 0.0f, std::cos(0.5236f)));
  return Bsdf(Frame::fromNormal(ns), Vec3(0, 0, 1));
}

// ---------------------------------------------------------------- Lambertian

TEST(BsdfLambertian, SampledDirectionsFollowPdfForSeveralWo) {
  const Lobe lobe = lambertian(lanes({0.5f, 0.8f, 0.2f, 0.9f}));
  uint64_t seed = 1;
  for (const Vec3& wo : {fromAngles(0.0f, 0.0f), fromAngles(0.7f, 1.0f), fromAngles(1.5f, 4.0f),
                         fromAngles(2.6f, 2.0f)}) {
    const auto r = test::chiSquareDirections(
        [&](Vec2 u, float uc) -> std::optional<Vec3> {
          const auto s = lobeSample(lobe, wo, uc, u, TransportMode::Radiance);
          if (!s) return std::nullopt;
          return s->wi;
        },
        [&](const Vec3& wi) { return double(lobePdf(lobe, wo, wi, TransportMode::Radiance)); }, chiOptions(seed++));
    EXPECT_TRUE(r.passed) << "wo = (" << wo.x << ", " << wo.y << ", " << wo.z << "): " << r.detail;
  }
}

TEST(BsdfLambertian, EvalIsReciprocalAndOneSided) {
  const Lobe lobe = lambertian(lanes({0.5f, 0.8f, 0.2f, 0.9f}));
  sampling::Pcg32 rng(7, 3);
  for (int i = 0; i < 10000; ++i) {
    const Vec3 a = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
    const Vec3 b = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
    const Spectrum fab = lobeEval(lobe, a, b, TransportMode::Radiance);
    const Spectrum fba = lobeEval(lobe, b, a, TransportMode::Radiance);
    for (int k = 0; k < kLanes; ++k) ASSERT_EQ(fab[k], fba[k]);
    const float expected = sameHemisphere(a, b) ? 0.8f * kInvPi : 0.0f;
    ASSERT_FLOAT_EQ(fab[1], expected);
  }
}

TEST(BsdfLambertian, SampleAgreesWithEvalAndPdf) {
  const Lobe lobe = lambertian(lanes({0.5f, 0.8f, 0.2f, 0.9f}));
  sampling::Pcg32 rng(9, 1);
  for (int i = 0; i < 10000; ++i) {
    const Vec3 wo = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
    const auto s = lobeSample(lobe, wo, rng.nextFloat(), Vec2(rng.nextFloat(), rng.nextFloat()), TransportMode::Radiance);
    ASSERT_TRUE(s);
    EXPECT_TRUE(sameHemisphere(wo, s->wi));
    EXPECT_FALSE(s->specular);
    EXPECT_FALSE(s->transmission);
    EXPECT_FLOAT_EQ(s->pdfW, lobePdf(lobe, wo, s->wi, TransportMode::Radiance));
    EXPECT_FLOAT_EQ(s->f[3], lobeEval(lobe, wo, s->wi, TransportMode::Radiance)[3]);
  }
}

// ---------------------------------------------------------------- Mixture

TEST(BsdfMixture, TwoLambertiansInATiltedFrameFollowTheMixturePdf) {
  // Spectrally different weights: for a non-specular pick the sample must carry the whole
  // mixture's f, so f |cos| / pdf = weightA + weightB for every sample.
  const Spectrum a = lanes({0.6f, 0.1f, 0.3f, 0.05f}), b = lanes({0.1f, 0.5f, 0.2f, 0.7f});
  Bsdf bsdf = tiltedBsdf();
  ASSERT_TRUE(bsdf.add(lambertian(a)));
  ASSERT_TRUE(bsdf.add(lambertian(b)));
  const Spectrum sum = a + b;
  uint64_t seed = 100;
  int wrongWeights = 0;
  // The last wo is above the geometric surface but below the shading one: only a wedge agrees.
  for (const Vec3& wo : {fromAngles(0.2f, 0.5f), fromAngles(1.2f, 3.0f), fromAngles(2.5f, 1.0f),
                         fromAngles(1.45f, 3.14159f)}) {
    const auto r = test::chiSquareDirections(
        [&](Vec2 u, float uc) -> std::optional<Vec3> {
          const auto s = bsdf.sample(wo, uc, u, TransportMode::Radiance);
          if (!s) return std::nullopt;
          const float weight = s->f[2] * absDot(s->wi, bsdf.frame().n) / s->pdfW;
          if (std::fabs(weight - sum[2]) > 1e-4f * sum[2]) ++wrongWeights;
          return s->wi;
        },
        [&](const Vec3& wi) { return double(bsdf.pdf(wo, wi, TransportMode::Radiance)); }, chiOptions(seed++));
    EXPECT_TRUE(r.passed) << "wo = (" << wo.x << ", " << wo.y << ", " << wo.z << "): " << r.detail;
  }
  EXPECT_EQ(wrongWeights, 0);
}

TEST(BsdfMixture, NonSpecularSampleEqualsEvalAndPdfInBothModes) {
  Bsdf bsdf = tiltedBsdf();
  bsdf.add(lambertian(lanes({0.6f, 0.1f, 0.3f, 0.05f})));
  bsdf.add(conductor(lanes({0.2f, 0.2f, 0.2f, 0.2f}), lanes({3, 3, 3, 3})));
  bsdf.add(lambertian(lanes({0.1f, 0.5f, 0.2f, 0.7f})));
  sampling::Pcg32 rng(21, 5);
  int nonSpecular = 0;
  for (int i = 0; i < 20000; ++i) {
    const Vec3 wo = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
    for (TransportMode mode : {TransportMode::Radiance, TransportMode::Importance}) {
      const auto s = bsdf.sample(wo, rng.nextFloat(), Vec2(rng.nextFloat(), rng.nextFloat()), mode);
      if (!s || s->specular) continue;
      ++nonSpecular;
      const Spectrum f = bsdf.eval(wo, s->wi, mode);
      // eval and pdf see wi after a round trip through world space: a rounding apart.
      for (int k = 0; k < 4; ++k) ASSERT_NEAR(s->f[k], f[k], 2e-4f * f[k] + 1e-6f);
      ASSERT_NEAR(s->pdfW, bsdf.pdf(wo, s->wi, mode), 1e-5f * s->pdfW + 1e-6f);
    }
  }
  EXPECT_GT(nonSpecular, 10000);
}

TEST(BsdfMixture, LambertianAndDielectricSelectionProbability) {
  // Selection weights: Lambertian 0.25 * 4 lanes = 1, dielectric (0.9 + 0.6) * 2 = 3, so the
  // Lambertian is picked with probability 1/4. Specular samples count as "no sample", whose
  // expected share is 1 - integral of Bsdf::pdf (which holds only the Lambertian's 1/4).
  for (bool tilted : {false, true}) {
    Bsdf bsdf = tilted ? tiltedBsdf() : Bsdf(Frame(), Vec3(0, 0, 1));
    bsdf.add(lambertian(lanes({0.25f, 0.25f, 0.25f, 0.25f})));
    bsdf.add(dielectric(lanes({1.5f, 1.5f, 1.5f, 1.5f}), false, lanes({0.9f, 0.6f, 0.9f, 0.6f})));
    const Vec3 wo = fromAngles(0.9f, 2.0f);
    const auto r = test::chiSquareDirections(
        [&](Vec2 u, float uc) -> std::optional<Vec3> {
          const auto s = bsdf.sample(wo, uc, u, TransportMode::Radiance);
          if (!s || s->specular) return std::nullopt;
          return s->wi;
        },
        [&](const Vec3& wi) { return double(bsdf.pdf(wo, wi, TransportMode::Radiance)); },
        chiOptions(tilted ? 201 : 200));
    EXPECT_TRUE(r.passed) << "tilted " << tilted << ": " << r.detail;
  }
}

TEST(BsdfMixture, SpecularPickHasSelectionTimesEventProbability) {
  // Lambertian (selection 1) + conductor (selection 3): 3/4 of the picks are mirror events
  // with pdf 3/4 (the conductor's event probability is 1).
  Bsdf bsdf(Frame(), Vec3(0, 0, 1));
  bsdf.add(lambertian(lanes({0.25f, 0.25f, 0.25f, 0.25f})));
  const Spectrum metalEta = lanes({0.2f, 0.3f, 0.4f, 0.5f}), metalK = lanes({3, 3.5f, 4, 4.5f});
  bsdf.add(conductor(metalEta, metalK, lanes({0.75f, 0.75f, 0.75f, 0.75f})));
  const Vec3 wo = fromAngles(0.6f, 1.0f);
  sampling::Pcg32 rng(31, 2);
  double specular = 0;
  for (int i = 0; i < kSamples; ++i) {
    const auto s = bsdf.sample(wo, rng.nextFloat(), Vec2(rng.nextFloat(), rng.nextFloat()), TransportMode::Radiance);
    ASSERT_TRUE(s);
    if (!s->specular) continue;
    specular += 1;
    ASSERT_FLOAT_EQ(s->pdfW, 0.75f);
    ASSERT_NEAR(s->wi.x, -wo.x, 1e-6f);
    const Spectrum fresnel = fresnelConductor(wo.z, metalEta, metalK);
    ASSERT_NEAR(s->f[1] * wo.z, 0.75f * fresnel[1], 1e-5f);
  }
  const auto r = test::chiSquareTest({specular, kSamples - specular}, {0.75 * kSamples, 0.25 * kSamples}, 0.01,
                                     kChiSquareRuns);
  EXPECT_TRUE(r.passed) << r.detail;
}

TEST(BsdfMixture, NoLeaksAcrossTheGeometricSurface) {
  // Shading normal tilted 30 degrees toward +x; wo above both normals. A direction above the
  // shading horizon but below the geometric one is a leak: eval and pdf are 0 there, and no
  // reflection sample goes below the geometric surface.
  Bsdf bsdf = tiltedBsdf();
  bsdf.add(lambertian(lanes({0.8f, 0.8f, 0.8f, 0.8f})));
  bsdf.add(conductor(lanes({0.2f, 0.2f, 0.2f, 0.2f}), lanes({3, 3, 3, 3})));
  const Vec3 wo = fromAngles(0.96f, 3.14159f);  // from -x, 55 degrees: its mirror about ns dips below ng
  ASSERT_GT(dot3(wo, bsdf.frame().n), 0.0f);
  ASSERT_LT(reflect(wo, bsdf.frame().n).z, 0.0f);
  const Vec3 wiLeak = glm::normalize(Vec3(0.9f, 0.0f, -0.2f));
  ASSERT_GT(dot3(wiLeak, bsdf.frame().n), 0.0f);
  for (TransportMode mode : {TransportMode::Radiance, TransportMode::Importance}) {
    EXPECT_TRUE(bsdf.eval(wo, wiLeak, mode).isBlack());
    EXPECT_EQ(bsdf.pdf(wo, wiLeak, mode), 0.0f);
  }
  EXPECT_GT(bsdf.eval(wo, Vec3(0, 0, 1), TransportMode::Radiance)[0], 0.0f);
  sampling::Pcg32 rng(41, 2);
  int samples = 0;
  for (int i = 0; i < 100000; ++i) {
    const auto s = bsdf.sample(wo, rng.nextFloat(), Vec2(rng.nextFloat(), rng.nextFloat()), TransportMode::Radiance);
    if (!s) continue;
    ++samples;
    ASSERT_FALSE(s->specular);  // the conductor's mirror direction is a leak: always rejected
    ASSERT_GT(s->wi.z, 0.0f);
  }
  EXPECT_GT(samples, 10000);
}

TEST(BsdfMixture, EvalWithPdfIsEvalAndPdfBitForBit) {
  // A tilted mixture (leaks, both sides, glossy and diffuse parts) and a lone Lambertian, both
  // modes, directions over the whole sphere.
  Bsdf mixture = tiltedBsdf();
  mixture.add(lambertian(lanes({0.6f, 0.1f, 0.3f, 0.05f})));
  mixture.add(conductor(lanes({0.2f, 0.2f, 0.2f, 0.2f}), lanes({3, 3, 3, 3})));
  Bsdf lone = tiltedBsdf();
  lone.add(lambertian(lanes({0.5f, 0.8f, 0.2f, 0.9f})));
  sampling::Pcg32 rng(43, 5);
  int nonZero = 0;
  for (const Bsdf* bsdf : {&mixture, &lone})
    for (TransportMode mode : {TransportMode::Radiance, TransportMode::Importance})
      for (int i = 0; i < 20000; ++i) {
        const Vec3 wo = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
        const Vec3 wi = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
        float pdfW = -1.0f;
        const Spectrum f = bsdf->evalWithPdf(wo, wi, mode, pdfW);
        const Spectrum expectedF = bsdf->eval(wo, wi, mode);
        ASSERT_EQ(std::memcmp(&f, &expectedF, sizeof f), 0);
        ASSERT_EQ(std::bit_cast<uint32_t>(pdfW), std::bit_cast<uint32_t>(bsdf->pdf(wo, wi, mode)));
        nonZero += pdfW > 0.0f;
      }
  EXPECT_GT(nonZero, 20000);
}

TEST(BsdfMixture, ImportanceModeAppliesTheShadingNormalCorrection) {
  Bsdf bsdf = tiltedBsdf();
  bsdf.add(lambertian(lanes({0.8f, 0.4f, 0.8f, 0.8f})));
  const Vec3 ns = bsdf.frame().n, ng = bsdf.geometricNormal();
  sampling::Pcg32 rng(51, 2);
  int checked = 0;
  for (int i = 0; i < 10000; ++i) {
    const Vec3 wo = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
    const Vec3 wi = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
    const Spectrum radiance = bsdf.eval(wo, wi, TransportMode::Radiance);
    const Spectrum importance = bsdf.eval(wo, wi, TransportMode::Importance);
    if (radiance.isBlack()) {
      ASSERT_TRUE(importance.isBlack());
      continue;
    }
    ++checked;
    const float correction = absDot(wo, ns) * absDot(wi, ng) / (absDot(wo, ng) * absDot(wi, ns));
    ASSERT_NEAR(importance[1], radiance[1] * correction, 1e-4f * radiance[1] * correction);
    const auto s = bsdf.sample(wo, 0.5f, Vec2(rng.nextFloat(), rng.nextFloat()), TransportMode::Importance);
    if (s) {
      const Spectrum f = bsdf.eval(wo, s->wi, TransportMode::Importance);
      ASSERT_NEAR(s->f[1], f[1], 1e-5f * f[1]);
    }
  }
  EXPECT_GT(checked, 2000);
}

TEST(BsdfMixture, CapacityAndEmptiness) {
  Bsdf bsdf;
  EXPECT_TRUE(bsdf.empty());
  EXPECT_FALSE(bsdf.sample(Vec3(0, 0, 1), 0.5f, Vec2(0.5f), TransportMode::Radiance));
  EXPECT_FALSE(bsdf.hasNonSpecular());
  for (int i = 0; i < Bsdf::kMaxLobes; ++i) EXPECT_TRUE(bsdf.add(conductor(lanes({1}), lanes({2}))));
  EXPECT_FALSE(bsdf.add(lambertian(lanes({1}))));
  EXPECT_EQ(bsdf.lobeCount(), Bsdf::kMaxLobes);
  EXPECT_FALSE(bsdf.hasNonSpecular());
  // A zero-weight lobe is never picked.
  Bsdf zero;
  zero.add(lambertian(Spectrum()));
  zero.add(conductor(lanes({1}), lanes({2})));
  for (float uc : {0.0f, 0.3f, 0.99999f}) {
    const auto s = zero.sample(Vec3(0, 0.6f, 0.8f), uc, Vec2(0.3f), TransportMode::Radiance);
    ASSERT_TRUE(s);
    EXPECT_TRUE(s->specular);
  }
}

// ---------------------------------------------------------------- Smooth dielectric

TEST(BsdfDielectric, ReflectRefractFrequenciesMatchFresnel) {
  struct Case {
    float thetaRad, eta;
  };
  // Outside and inside (theta > pi/2), including an inside case beyond the critical angle.
  for (const Case c : {Case{0.0f, 1.5f}, Case{1.0f, 1.5f}, Case{1.45f, 1.33f}, Case{2.8f, 1.5f},
                       Case{2.4f, 1.5f}, Case{0.8f, 0.7f}}) {
    const Lobe lobe = dielectric(lanes({c.eta, c.eta, c.eta, c.eta}), false);
    const Vec3 wo = fromAngles(c.thetaRad, 0.3f);
    const double r = fresnelDielectric(wo.z, c.eta);
    sampling::Pcg32 rng(61, uint64_t(c.thetaRad * 100));
    double reflected = 0, refracted = 0;
    for (int i = 0; i < kSamples; ++i) {
      const auto s = lobeSample(lobe, wo, rng.nextFloat(), Vec2(0.5f), TransportMode::Radiance);
      ASSERT_TRUE(s);
      ASSERT_TRUE(s->specular);
      (s->transmission ? refracted : reflected) += 1;
      ASSERT_FLOAT_EQ(s->pdfW, float(s->transmission ? 1.0 - r : r));
    }
    const auto result = test::chiSquareTest({reflected, refracted}, {r * kSamples, (1 - r) * kSamples}, 0.01,
                                            kChiSquareRuns);
    EXPECT_TRUE(result.passed) << "theta " << c.thetaRad << " eta " << c.eta << " R " << r << ": " << result.detail;
  }
}

TEST(BsdfDielectric, FresnelMatchesComplexReference) {
  // Normal incidence: ((eta - 1) / (eta + 1))^2 from either side.
  for (float eta : {1.1f, 1.33f, 1.5f, 2.4f, 0.75f}) {
    const float r0 = ((eta - 1) / (eta + 1)) * ((eta - 1) / (eta + 1));
    EXPECT_NEAR(fresnelDielectric(1.0f, eta), r0, 1e-6f);
    EXPECT_NEAR(fresnelDielectric(-1.0f, eta), r0, 1e-6f);
  }
  // Oblique, from outside (index 1 onto eta) and inside (index 1 onto 1/eta, TIR included).
  for (float eta : {1.33f, 1.5f, 2.4f}) {
    for (int i = 0; i <= 100; ++i) {
      const double cosI = double(float(i / 100.0));  // the float the function sees (steep near TIR)
      EXPECT_NEAR(fresnelDielectric(float(cosI), eta), fresnelReference(cosI, eta, 0.0), 2e-6) << cosI;
      EXPECT_NEAR(fresnelDielectric(-float(cosI), eta), fresnelReference(cosI, 1.0 / eta, 0.0), 2e-6) << cosI;
    }
  }
  EXPECT_EQ(fresnelDielectric(0.3f, 1.0f), 0.0f);
}

TEST(BsdfDielectric, RefractionObeysSnellsLaw) {
  for (float eta : {1.33f, 1.5f, 2.4f}) {
    for (float thetaRad : {0.1f, 0.6f, 1.2f, 1.5f, 2.0f, 2.9f}) {
      const Vec3 wo = fromAngles(thetaRad, 0.8f);
      const bool inside = wo.z < 0.0f;
      const float sinO = std::sqrt(wo.x * wo.x + wo.y * wo.y);
      if (inside && eta * sinO >= 1.0f) continue;  // TIR, tested below
      const auto s = lobeSample(dielectric(lanes({eta}), false), wo, 0.9999999f, Vec2(0.5f), TransportMode::Radiance);
      ASSERT_TRUE(s);
      ASSERT_TRUE(s->transmission);
      const Vec3 wi = s->wi;
      EXPECT_NEAR(glm::length(wi), 1.0f, 1e-5f);
      EXPECT_LT(wo.z * wi.z, 0.0f);
      const float sinI = std::sqrt(wi.x * wi.x + wi.y * wi.y);
      // n_o sin(theta_o) = n_i sin(theta_i), with index 1 outside and eta inside.
      const float nO = inside ? eta : 1.0f, nI = inside ? 1.0f : eta;
      EXPECT_NEAR(nO * sinO, nI * sinI, 1e-5f) << eta << " " << thetaRad;
      // In the plane of incidence, on the far side of the normal.
      EXPECT_NEAR(wo.x * wi.y - wo.y * wi.x, 0.0f, 1e-6f);
      EXPECT_LE(wo.x * wi.x + wo.y * wi.y, 0.0f);
      EXPECT_FLOAT_EQ(s->etaScale, inside ? 1.0f / eta : eta);
    }
  }
}

TEST(BsdfDielectric, TotalInternalReflectionAboveTheCriticalAngle) {
  const float eta = 1.5f;
  const float criticalRad = std::asin(1.0f / eta);
  const Lobe lobe = dielectric(lanes({eta, eta}), false);
  const Vec3 beyond = fromAngles(float(M_PI) - (criticalRad + 0.02f), 1.0f);  // inside, just past critical
  const Vec3 before = fromAngles(float(M_PI) - (criticalRad - 0.02f), 1.0f);  // inside, just before
  EXPECT_EQ(fresnelDielectric(beyond.z, eta), 1.0f);
  EXPECT_LT(fresnelDielectric(before.z, eta), 1.0f);
  for (int i = 0; i < 1000; ++i) {
    const float uc = i / 1000.0f;
    const auto s = lobeSample(lobe, beyond, uc, Vec2(0.5f), TransportMode::Radiance);
    ASSERT_TRUE(s);
    ASSERT_FALSE(s->transmission);
    EXPECT_FLOAT_EQ(s->pdfW, 1.0f);
    EXPECT_NEAR(s->wi.z, beyond.z, 1e-7f);
    EXPECT_NEAR(s->f[0] * std::fabs(s->wi.z), 1.0f, 1e-6f);
  }
  const auto refracted = lobeSample(lobe, before, 0.9999f, Vec2(0.5f), TransportMode::Radiance);
  ASSERT_TRUE(refracted);
  EXPECT_TRUE(refracted->transmission);
}

TEST(BsdfDielectric, RefractionScalesRadianceButNotImportance) {
  for (float eta : {1.33f, 1.5f}) {
    const Lobe lobe = dielectric(lanes({eta, eta, eta}), false, lanes({0.9f, 0.8f, 0.7f}));
    for (const Vec3& wo : {fromAngles(0.5f, 0.2f), fromAngles(2.8f, 0.2f)}) {
      const auto radiance = lobeSample(lobe, wo, 0.999f, Vec2(0.5f), TransportMode::Radiance);
      const auto importance = lobeSample(lobe, wo, 0.999f, Vec2(0.5f), TransportMode::Importance);
      ASSERT_TRUE(radiance && importance);
      ASSERT_TRUE(radiance->transmission && importance->transmission);
      const float etaRel = wo.z > 0 ? eta : 1.0f / eta;
      const float t = 1.0f - fresnelDielectric(wo.z, eta);
      for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(importance->f[k] * std::fabs(importance->wi.z), lobe.weight[k] * t, 1e-5f);
        EXPECT_NEAR(radiance->f[k], importance->f[k] / (etaRel * etaRel), 1e-5f * importance->f[k]);
      }
      // Reflection is the same in both modes.
      const auto rRad = lobeSample(lobe, wo, 0.0f, Vec2(0.5f), TransportMode::Radiance);
      const auto rImp = lobeSample(lobe, wo, 0.0f, Vec2(0.5f), TransportMode::Importance);
      ASSERT_TRUE(rRad && rImp && !rRad->transmission);
      EXPECT_EQ(rRad->f[1], rImp->f[1]);
      EXPECT_EQ(rRad->etaScale, 1.0f);
    }
  }
}

TEST(BsdfDielectric, IndexMatchedPassesStraightThrough) {
  const Lobe lobe = dielectric(lanes({1, 1, 1, 1}), false, lanes({0.5f, 1, 1, 1}));
  sampling::Pcg32 rng(71, 1);
  for (int i = 0; i < 10000; ++i) {
    const Vec3 wo = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
    const float uc = i == 0 ? 0.0f : rng.nextFloat();
    for (TransportMode mode : {TransportMode::Radiance, TransportMode::Importance}) {
      const auto s = lobeSample(lobe, wo, uc, Vec2(0.5f), mode);
      if (std::fabs(wo.z) < 1e-6f) continue;
      ASSERT_TRUE(s);
      ASSERT_TRUE(s->transmission);
      ASSERT_EQ(s->wi, -wo);
      ASSERT_EQ(s->pdfW, 1.0f);
      ASSERT_NEAR(s->f[0] * std::fabs(s->wi.z), 0.5f, 1e-6f);
      ASSERT_EQ(s->etaScale, 1.0f);
    }
  }
}

TEST(BsdfDielectric, DispersiveOnlyWhenEtaVaries) {
  const Spectrum constantEta = lanes({1.5f, 1.5f, 1.5f, 1.5f}), varyingEta = lanes({1.52f, 1.5f, 1.48f, 1.46f});
  const Vec3 wo = fromAngles(0.7f, 0.4f);
  for (float uc : {0.0f, 0.5f, 0.999f}) {
    const auto s = lobeSample(dielectric(constantEta, false), wo, uc, Vec2(0.5f), TransportMode::Radiance);
    ASSERT_TRUE(s);
    EXPECT_FALSE(s->dispersive);
  }
  // Refraction: the hero's direction; lanes 1.. zeroed so they cannot be misused.
  const auto refracted = lobeSample(dielectric(varyingEta, true), wo, 0.999f, Vec2(0.5f), TransportMode::Radiance);
  ASSERT_TRUE(refracted && refracted->transmission);
  EXPECT_TRUE(refracted->dispersive);
  EXPECT_GT(refracted->f[0], 0.0f);
  for (int k = 1; k < kLanes; ++k) EXPECT_EQ(refracted->f[k], 0.0f);
  const auto hero = lobeSample(dielectric(lanes({1.52f}), false), wo, 0.999f, Vec2(0.5f), TransportMode::Radiance);
  EXPECT_EQ(refracted->wi, hero->wi);
  EXPECT_EQ(refracted->f[0], hero->f[0]);
  // Reflection: the mirror direction is the same for all wavelengths; each lane keeps its own R.
  const auto reflected = lobeSample(dielectric(varyingEta, true), wo, 0.0f, Vec2(0.5f), TransportMode::Radiance);
  ASSERT_TRUE(reflected && !reflected->transmission);
  EXPECT_FALSE(reflected->dispersive);
  for (int k = 0; k < 4; ++k)
    EXPECT_NEAR(reflected->f[k] * wo.z, fresnelDielectric(wo.z, varyingEta[k]), 1e-6f);
}

// ---------------------------------------------------------------- Smooth conductor

TEST(BsdfConductor, FresnelMatchesComplexReference) {
  // Gold, silver, aluminium and copper near 550 nm, an arbitrary absorber, and a dielectric (k = 0).
  const Spectrum eta = lanes({0.43f, 0.059f, 0.96f, 1.04f, 2.0f, 1.5f});
  const Spectrum k = lanes({2.45f, 3.6f, 6.69f, 2.59f, 0.5f, 0.0f});
  for (int i = 0; i <= 200; ++i) {
    const double cosI = double(float(i / 200.0));
    const Spectrum r = fresnelConductor(float(cosI), eta, k);
    for (int lane = 0; lane < 6; ++lane)
      EXPECT_NEAR(r[lane], fresnelReference(cosI, eta[lane], k[lane]), 2e-5) << "lane " << lane << " cos " << cosI;
    EXPECT_NEAR(r[5], fresnelDielectric(float(cosI), 1.5f), 2e-5);
    for (int lane = 6; lane < kLanes; ++lane) EXPECT_TRUE(std::isfinite(r[lane]));  // n = 0 lanes
  }
  // Gold at normal incidence: ((n-1)^2 + k^2) / ((n+1)^2 + k^2) = 0.7863.
  EXPECT_NEAR(fresnelConductor(1.0f, eta, k)[0], 0.78627, 1e-4);
}

TEST(BsdfConductor, MirrorReflectionWithFresnelWeight) {
  const Spectrum eta = lanes({0.43f, 0.2f}), k = lanes({2.45f, 3.0f});
  const Lobe lobe = conductor(eta, k, lanes({0.5f, 1.0f}));
  for (const Vec3& wo : {fromAngles(0.3f, 1.0f), fromAngles(2.5f, 4.0f)}) {
    const auto s = lobeSample(lobe, wo, 0.3f, Vec2(0.1f), TransportMode::Importance);
    ASSERT_TRUE(s);
    EXPECT_TRUE(s->specular);
    EXPECT_FALSE(s->transmission);
    EXPECT_EQ(s->pdfW, 1.0f);
    EXPECT_EQ(s->wi, Vec3(-wo.x, -wo.y, wo.z));
    const Spectrum fr = fresnelConductor(wo.z, eta, k);
    EXPECT_NEAR(s->f[0] * std::fabs(wo.z), 0.5f * fr[0], 1e-6f);
    EXPECT_NEAR(s->f[1] * std::fabs(wo.z), fr[1], 1e-6f);
    EXPECT_TRUE(lobeEval(lobe, wo, s->wi, TransportMode::Radiance).isBlack());
    EXPECT_EQ(lobePdf(lobe, wo, s->wi, TransportMode::Radiance), 0.0f);
  }
}

// ---------------------------------------------------------------- Robustness

bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

TEST(BsdfFuzz, NoNaNForGrazingAndDegenerateInputs) {
  const Lobe lobes[] = {
      lambertian(lanes({0.5f, 1, 0.2f, 0.9f})),
      dielectric(lanes({1.5f, 1.5f, 1.5f, 1.5f}), false),
      dielectric(lanes({2.4f, 2.3f, 2.2f, 2.1f}), true),
      dielectric(lanes({1, 1, 1, 1}), false),
      dielectric(lanes({0.01f, 100, 0, -1}), true),
      conductor(lanes({0.43f, 0.2f, 1e-4f, 0}), lanes({2.45f, 1e4f, 0, 0})),
  };
  Bsdf bsdf = tiltedBsdf();
  for (const Lobe& l : lobes) bsdf.add(l);
  const float tiny = 1e-8f;
  std::vector<Vec3> wos = {Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0, 0, 1), Vec3(0, 0, -1), glm::normalize(Vec3(1, 0, tiny)),
                           glm::normalize(Vec3(1, 0, -tiny)), glm::normalize(Vec3(0.5f, 0, 0.866f)), Vec3(0, 0, 0)};
  sampling::Pcg32 rng(81, 9);
  for (int i = 0; i < 3000; ++i) wos.push_back(sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat())));
  const float us[] = {0.0f, 0.5f, 0x1.fffffep-1f};
  auto check = [](const std::optional<BsdfSample>& s) {
    if (!s) return;
    ASSERT_FALSE(s->f.hasNaNOrInf());
    ASSERT_TRUE(std::isfinite(s->pdfW) && s->pdfW > 0.0f);
    ASSERT_TRUE(finite(s->wi));
    ASSERT_NEAR(glm::length(s->wi), 1.0f, 1e-4f);
    ASSERT_TRUE(std::isfinite(s->etaScale) && s->etaScale > 0.0f);
  };
  for (const Vec3& wo : wos) {
    for (TransportMode mode : {TransportMode::Radiance, TransportMode::Importance}) {
      for (int j = 0; j < 4; ++j) {
        const float uc = j < 3 ? us[j] : rng.nextFloat();
        const Vec2 u2 = j < 3 ? Vec2(us[j], us[2 - j]) : Vec2(rng.nextFloat(), rng.nextFloat());
        for (const Lobe& l : lobes) {
          check(lobeSample(l, wo, uc, u2, mode));
          const Vec3 wi = sampleUniformSphere(u2);
          ASSERT_FALSE(lobeEval(l, wo, wi, mode).hasNaNOrInf());
          ASSERT_TRUE(std::isfinite(lobePdf(l, wo, wi, mode)));
        }
        check(bsdf.sample(wo, uc, u2, mode));
        for (const Vec3& wi : {sampleUniformSphere(u2), Vec3(1, 0, 0), glm::normalize(Vec3(1, 0, tiny)), wo}) {
          ASSERT_FALSE(bsdf.eval(wo, wi, mode).hasNaNOrInf());
          const float pdfW = bsdf.pdf(wo, wi, mode);
          ASSERT_TRUE(std::isfinite(pdfW) && pdfW >= 0.0f);
        }
      }
    }
  }
}

}  // namespace
}  // namespace tex::render
