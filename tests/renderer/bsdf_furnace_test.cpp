// White furnace: with unit weights, the directional albedo E[f |cos| / pdf] of every lobe and
// mixture is 1 where energy is conserved exactly (Lambertian, dielectric R + T in Importance
// mode, a conductor with k -> infinity) and at most 1 otherwise. Where the sampler is exact the
// weight is 1 for every single sample, which is checked per sample, not only on average.
#include <gtest/gtest.h>

#include <cmath>

#include "renderer/bsdf/bsdf.h"
#include "renderer/core/warp.h"
#include "renderer/sampling/pcg.h"

namespace tex::render {
namespace {

constexpr int kSamples = 1000000;

Spectrum lanes(std::initializer_list<float> values) {
  Spectrum s;
  int i = 0;
  for (float v : values) s[i++] = v;
  return s;
}

Lobe makeLobe(LobeKind kind, const Spectrum& weight, const Spectrum& a = Spectrum(), const Spectrum& b = Spectrum(),
              bool etaVaries = false) {
  Lobe l;
  l.kind = kind;
  l.weight = weight;
  l.a = a;
  l.b = b;
  l.etaVaries = etaVaries;
  return l;
}

const Spectrum kUnit = lanes({1, 1, 1, 1});

Vec3 fromAngles(float thetaRad, float phiRad) {
  return Vec3(std::sin(thetaRad) * std::cos(phiRad), std::sin(thetaRad) * std::sin(phiRad), std::cos(thetaRad));
}

// Lane `lane` of f |cos| / pdf for a sample in the local frame (z up).
float sampleWeight(const BsdfSample& s, int lane) { return s.f[lane] * std::fabs(s.wi.z) / s.pdfW; }

const Vec3 kWos[] = {fromAngles(0.0f, 0.0f), fromAngles(0.6f, 1.0f), fromAngles(1.2f, 2.0f), fromAngles(1.55f, 3.0f),
                     fromAngles(2.0f, 4.0f), fromAngles(3.0f, 5.0f)};

TEST(BsdfFurnace, LambertianWeighsOneForEverySample) {
  const Lobe lobe = makeLobe(LobeKind::Lambertian, kUnit);
  sampling::Pcg32 rng(1, 1);
  for (const Vec3& wo : kWos) {
    double sum = 0;
    for (int i = 0; i < kSamples / 10; ++i) {
      const auto s = lobeSample(lobe, wo, rng.nextFloat(), Vec2(rng.nextFloat(), rng.nextFloat()), TransportMode::Radiance);
      ASSERT_TRUE(s);
      const float w = sampleWeight(*s, 2);
      ASSERT_NEAR(w, 1.0f, 1e-5f);
      sum += w;
    }
    EXPECT_NEAR(sum / (kSamples / 10), 1.0, 1e-5);
  }
}

TEST(BsdfFurnace, LambertianAlbedoByUniformSphereSamplingIsOne) {
  // Independent of the lobe's own sampler: integrate eval |cos| over the sphere with uniform
  // directions; the estimate must be 1 within 5 standard errors.
  const Lobe lobe = makeLobe(LobeKind::Lambertian, kUnit);
  sampling::Pcg32 rng(2, 1);
  for (const Vec3& wo : kWos) {
    double sum = 0, sumSquares = 0;
    for (int i = 0; i < kSamples; ++i) {
      const Vec3 wi = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
      const double w = double(lobeEval(lobe, wo, wi, TransportMode::Radiance)[0]) * std::fabs(wi.z) / kUniformSpherePdfW;
      sum += w;
      sumSquares += w * w;
    }
    const double mean = sum / kSamples;
    const double standardError = std::sqrt((sumSquares / kSamples - mean * mean) / kSamples);
    EXPECT_LT(standardError, 0.002);
    EXPECT_NEAR(mean, 1.0, 5 * standardError) << wo.z;
  }
}

TEST(BsdfFurnace, DielectricConservesEnergyInImportanceMode) {
  // Reflection weighs R / (R / (R+T)) and refraction T / (T / (R+T)): 1 for every sample.
  sampling::Pcg32 rng(3, 1);
  for (float eta : {1.1f, 1.5f, 2.4f, 0.7f}) {
    for (bool etaVaries : {false, true}) {
      const Spectrum etas = etaVaries ? lanes({eta, eta * 0.98f, eta * 0.96f, eta * 0.94f}) : lanes({eta, eta, eta, eta});
      const Lobe lobe = makeLobe(LobeKind::SmoothDielectric, kUnit, etas, Spectrum(), etaVaries);
      for (const Vec3& wo : kWos) {
        double sum = 0;
        for (int i = 0; i < kSamples / 20; ++i) {
          const auto s = lobeSample(lobe, wo, rng.nextFloat(), Vec2(0.5f), TransportMode::Importance);
          ASSERT_TRUE(s);
          const float w = sampleWeight(*s, 0);  // the hero lane: meaningful also when dispersive
          ASSERT_NEAR(w, 1.0f, 1e-5f) << "eta " << eta << " wo.z " << wo.z;
          sum += w;
        }
        EXPECT_NEAR(sum / (kSamples / 20), 1.0, 1e-5);
      }
    }
  }
}

TEST(BsdfFurnace, DielectricRadianceAlbedoIsAtMostOneEnteringAndEtaScaleRestoresOne) {
  // Radiance mode: refraction into the denser side weighs 1/eta^2, so the albedo is
  // R + T / eta^2 <= 1; multiplying by etaScale^2 (what the integrator's bookkeeping does)
  // gives 1 for every sample in either direction.
  sampling::Pcg32 rng(4, 1);
  for (float eta : {1.33f, 1.5f, 2.4f}) {
    const Lobe lobe = makeLobe(LobeKind::SmoothDielectric, kUnit, lanes({eta, eta, eta, eta}));
    for (const Vec3& wo : kWos) {
      double sum = 0;
      const int n = kSamples / 10;
      for (int i = 0; i < n; ++i) {
        const auto s = lobeSample(lobe, wo, rng.nextFloat(), Vec2(0.5f), TransportMode::Radiance);
        ASSERT_TRUE(s);
        const float w = sampleWeight(*s, 1);
        ASSERT_NEAR(w * s->etaScale * s->etaScale, 1.0f, 1e-5f);
        sum += w;
      }
      const double mean = sum / n;
      if (wo.z > 0) {
        const double r = fresnelDielectric(wo.z, eta);
        const double expected = r + (1 - r) / (double(eta) * eta);
        EXPECT_LE(mean, 1.0);
        // Each weight is 1 or 1/eta^2: the mean is binomial with variance p(1-p)(1-1/eta^2)^2 / n.
        const double sigma = std::sqrt(r * (1 - r) / n) * (1 - 1 / (double(eta) * eta));
        EXPECT_NEAR(mean, expected, 5 * sigma + 1e-6) << "eta " << eta << " wo.z " << wo.z;
      }
    }
  }
}

TEST(BsdfFurnace, ConductorWithInfiniteExtinctionReflectsEverything) {
  const Lobe lobe = makeLobe(LobeKind::SmoothConductor, kUnit, lanes({0.2f, 1.0f, 3.0f, 0.05f}),
                             lanes({1e4f, 1e4f, 1e4f, 1e4f}));
  for (const Vec3& wo : kWos) {
    const auto s = lobeSample(lobe, wo, 0.5f, Vec2(0.5f), TransportMode::Radiance);
    ASSERT_TRUE(s);
    for (int lane = 0; lane < 4; ++lane) {
      EXPECT_NEAR(sampleWeight(*s, lane), 1.0f, 1e-3f) << lane;
      EXPECT_LE(sampleWeight(*s, lane), 1.0f + 1e-6f);
    }
  }
}

TEST(BsdfFurnace, ConductorAlbedoIsItsFresnelReflectanceAndAtMostOne) {
  const Spectrum eta = lanes({0.43f, 0.059f, 0.96f, 1.04f}), k = lanes({2.45f, 3.6f, 6.69f, 2.59f});
  const Lobe lobe = makeLobe(LobeKind::SmoothConductor, kUnit, eta, k);
  for (int i = 1; i <= 100; ++i) {
    const Vec3 wo = fromAngles(1.5707f * i / 100.0f, 0.3f);
    const auto s = lobeSample(lobe, wo, 0.5f, Vec2(0.5f), TransportMode::Importance);
    ASSERT_TRUE(s);
    const Spectrum fresnel = fresnelConductor(wo.z, eta, k);
    for (int lane = 0; lane < 4; ++lane) {
      EXPECT_NEAR(sampleWeight(*s, lane), fresnel[lane], 1e-5f);
      EXPECT_GT(sampleWeight(*s, lane), 0.0f);
      EXPECT_LE(sampleWeight(*s, lane), 1.0f);
    }
  }
}

TEST(BsdfFurnace, MixturesWithUnitTotalWeightConserveEnergy) {
  // Lobes whose weights sum to 1 in every lane. Selection is proportional to the weight, so
  // every sample weighs 1 (up to the conductor's 1 - F ~ 1e-4) in Importance mode.
  Bsdf diffuse(Frame::fromNormal(glm::normalize(Vec3(0.3f, -0.2f, 1.0f))), glm::normalize(Vec3(0.3f, -0.2f, 1.0f)));
  diffuse.add(makeLobe(LobeKind::Lambertian, lanes({0.2f, 0.7f, 0.5f, 0.9f})));
  diffuse.add(makeLobe(LobeKind::Lambertian, lanes({0.8f, 0.3f, 0.5f, 0.1f})));

  Bsdf all(Frame::fromNormal(glm::normalize(Vec3(-0.5f, 0.1f, 0.7f))), glm::normalize(Vec3(-0.5f, 0.1f, 0.7f)));
  all.add(makeLobe(LobeKind::Lambertian, lanes({0.3f, 0.3f, 0.3f, 0.3f})));
  all.add(makeLobe(LobeKind::SmoothDielectric, lanes({0.5f, 0.5f, 0.5f, 0.5f}), lanes({1.5f, 1.5f, 1.5f, 1.5f})));
  all.add(makeLobe(LobeKind::SmoothConductor, lanes({0.2f, 0.2f, 0.2f, 0.2f}), lanes({0.2f, 0.2f, 0.2f, 0.2f}),
                   lanes({1e4f, 1e4f, 1e4f, 1e4f})));

  sampling::Pcg32 rng(5, 1);
  for (const Bsdf* bsdf : {&diffuse, &all}) {
    for (const Vec3& woLocal : kWos) {
      const Vec3 wo = bsdf->frame().toWorld(woLocal);
      double sum[4] = {};
      const int n = kSamples / 10;
      for (int i = 0; i < n; ++i) {
        const auto s = bsdf->sample(wo, rng.nextFloat(), Vec2(rng.nextFloat(), rng.nextFloat()), TransportMode::Importance);
        ASSERT_TRUE(s);
        const float cosWi = absDot(s->wi, bsdf->frame().n);
        for (int lane = 0; lane < 4; ++lane) {
          const float w = s->f[lane] * cosWi / s->pdfW;
          ASSERT_NEAR(w, 1.0f, 2e-4f) << "lane " << lane << " wo.z " << woLocal.z;
          sum[lane] += w;
        }
      }
      for (int lane = 0; lane < 4; ++lane) EXPECT_NEAR(sum[lane] / n, 1.0, 2e-4);
    }
  }
}

}  // namespace
}  // namespace tex::render
