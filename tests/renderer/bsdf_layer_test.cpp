// Layered coat (Bsdf::setCoat, docs/layering.md): a white Lambertian under a smooth coat has
// albedo 1 at every angle, under a rough coat at most 1 (the loss is printed), the mixture's
// samples follow its pdf (chi-square), eval is reciprocal, and degenerate inputs give no NaN.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "renderer/bsdf/bsdf.h"
#include "renderer/core/warp.h"
#include "renderer/sampling/pcg.h"
#include "tests/renderer/chi_square.h"

namespace tex::render {
namespace {

constexpr int kChiSquareRuns = 4;

Spectrum uniform(float v) {
  Spectrum s;
  for (int i = 0; i < 4; ++i) s[i] = v;
  return s;
}

Vec3 fromAngles(float thetaRad, float phiRad) {
  return Vec3(std::sin(thetaRad) * std::cos(phiRad), std::sin(thetaRad) * std::sin(phiRad), std::cos(thetaRad));
}

Bsdf coatedLambertian(LobeKind coatKind, float alpha, float eta, float albedo = 1.0f) {
  Bsdf bsdf(Frame(), Vec3(0, 0, 1));
  Lobe base;
  base.kind = LobeKind::Lambertian;
  base.weight = uniform(albedo);
  base.underCoat = true;
  EXPECT_TRUE(bsdf.add(base));
  Lobe coat;
  coat.kind = coatKind;
  coat.weight = uniform(1);
  coat.a = uniform(eta);
  coat.roughness = alpha;
  EXPECT_TRUE(bsdf.setCoat(coat));
  EXPECT_FALSE(bsdf.setCoat(coat));  // one coat per Bsdf
  return bsdf;
}

double albedo(const Bsdf& bsdf, const Vec3& wo, int n, uint64_t seed) {
  sampling::Pcg32 rng(seed, 3);
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const auto s = bsdf.sample(wo, rng.nextFloat(), Vec2(rng.nextFloat(), rng.nextFloat()), TransportMode::Importance);
    if (!s) continue;
    EXPECT_FALSE(s->f.hasNaNOrInf());
    sum += s->f[0] * std::fabs(s->wi.z) / s->pdfW;
  }
  return sum / n;
}

// A coat over a black base (whose zero-weight lobe the closure walk drops) is a Bsdf of its
// own: not empty, so the path tracer does not stop there, and it reflects F(cos) at its
// mirror direction (the helper's glTF piano black reflected nothing).
TEST(BsdfLayer, ACoatWithoutLobesStillReflects) {
  Bsdf bsdf(Frame(), Vec3(0, 0, 1));
  EXPECT_TRUE(bsdf.empty());
  Lobe coat;
  coat.kind = LobeKind::SmoothDielectric;
  coat.weight = uniform(1);
  coat.a = uniform(1.5f);
  ASSERT_TRUE(bsdf.setCoat(coat));
  EXPECT_FALSE(bsdf.empty());
  for (float theta : {0.0f, 1.0f}) {
    const Vec3 wo = fromAngles(theta, 0.3f);
    const auto s = bsdf.sample(wo, 0.5f, Vec2(0.5f), TransportMode::Radiance);
    ASSERT_TRUE(s && s->specular);
    EXPECT_EQ(s->wi, Vec3(-wo.x, -wo.y, wo.z));
    // The estimator's weight f cos / pdf is the reflectance.
    EXPECT_NEAR(s->f[0] * wo.z / s->pdfW, fresnelDielectric(wo.z, 1.5f), 1e-5f);
  }
}

TEST(BsdfLayer, SmoothCoatIsPickedWithItsFresnelShare) {
  // The coat is the last component: uc near 1 picks it. Its event probability is F(cos_o), so
  // its sample weighs F / F = 1 for a unit-weight coat (the hero lane).
  const Bsdf bsdf = coatedLambertian(LobeKind::SmoothDielectric, 0, 1.5f);
  for (float theta : {0.0f, 0.8f, 1.4f}) {
    const Vec3 wo = fromAngles(theta, 0.2f);
    const auto s = bsdf.sample(wo, 0x1.fffffep-1f, Vec2(0.5f), TransportMode::Radiance);
    ASSERT_TRUE(s && s->specular);
    EXPECT_EQ(s->wi, Vec3(-wo.x, -wo.y, wo.z));
    EXPECT_NEAR(s->pdfW, fresnelDielectric(wo.z, 1.5f), 1e-6f);
    EXPECT_NEAR(s->f[0] * wo.z / s->pdfW, 1.0f, 1e-4f);
    const auto base = bsdf.sample(wo, 0.0f, Vec2(0.5f), TransportMode::Radiance);
    ASSERT_TRUE(base && !base->specular);
  }
}

TEST(BsdfLayer, WhiteLambertianUnderSmoothCoatHasAlbedoOne) {
  for (float eta : {1.1f, 1.5f, 2.4f}) {
    const Bsdf bsdf = coatedLambertian(LobeKind::SmoothDielectric, 0, eta);
    for (float theta : {0.0f, 0.7f, 1.2f, 1.5f}) {
      const double a = albedo(bsdf, fromAngles(theta, 0.4f), 200000, 7);
      EXPECT_NEAR(a, 1.0, 6e-3) << "eta " << eta << " theta " << theta;
    }
  }
}

// A coat over a base that scatters near the mirror direction (a perfect mirror, a rough white
// metal, a sheen) must not gain energy. The Lambertian transmittance (1 - F_o)(1 - F_i) /
// (1 - F_avg) made a coat over a mirror reflect 1.055 of the light (a furnace brightened at
// every bounce); such lobes take 1 - max(F_o, F_i), which is exact for the mirror.
TEST(BsdfLayer, CoatsOverMirrorsAndGlossyBasesDoNotGainEnergy) {
  for (float eta : {1.5f, 2.4f}) {
    for (LobeKind baseKind : {LobeKind::SmoothConductor, LobeKind::RoughConductor}) {
      for (float alpha : {0.0f, 0.3f}) {
        Bsdf bsdf(Frame(), Vec3(0, 0, 1));
        Lobe base;
        base.kind = baseKind;
        base.weight = uniform(1);
        base.a = uniform(0.2f);
        base.b = uniform(1e4f);  // F = 1 to 1e-7: a white metal
        base.roughness = 0.2f;
        base.underCoat = true;
        ASSERT_TRUE(bsdf.add(base));
        Lobe coat;
        coat.kind = alpha > 0.0f ? LobeKind::RoughDielectric : LobeKind::SmoothDielectric;
        coat.weight = uniform(1);
        coat.a = uniform(eta);
        coat.roughness = alpha;
        ASSERT_TRUE(bsdf.setCoat(coat));
        for (float theta : {0.0f, 0.5f, 1.0f, 1.4f}) {
          const double a = albedo(bsdf, fromAngles(theta, 0.4f), 100000, 9);
          EXPECT_LE(a, 1.0 + 4e-3) << "eta " << eta << " base " << int(baseKind) << " coat alpha " << alpha << " theta " << theta;
          // A smooth coat over a mirror: exactly F + (1 - F) = 1.
          if (baseKind == LobeKind::SmoothConductor && alpha == 0.0f) {
            EXPECT_NEAR(a, 1.0, 4e-3) << "eta " << eta << " theta " << theta;
          }
        }
      }
    }
  }
}

TEST(BsdfLayer, RoughCoatAlbedoIsAtMostOneAndItsLossIsReported) {
  for (float alpha : {0.05f, 0.2f, 0.5f, 1.0f}) {
    for (float eta : {1.5f, 2.4f}) {
      const Bsdf bsdf = coatedLambertian(LobeKind::RoughDielectric, alpha, eta);
      for (float theta : {0.0f, 0.7f, 1.2f, 1.5f}) {
        const double a = albedo(bsdf, fromAngles(theta, 0.4f), 200000, 8);
        std::printf("  rough coat alpha %.2f eta %.1f theta %.2f: albedo %.4f\n", alpha, eta, theta, a);
        EXPECT_LE(a, 1.0 + 6e-3) << alpha << " " << eta << " " << theta;
        // The base's share is the smooth-coat one, 1 - F(cos_o), exactly: only the rough
        // coat's own reflection loses energy (single-scattering GGX, worst at grazing).
        EXPECT_GT(a, 1.0 - fresnelDielectric(std::cos(theta), eta) - 6e-3) << alpha << " " << eta << " " << theta;
      }
    }
  }
}

TEST(BsdfLayer, CoatedMixtureSamplesFollowPdf) {
  uint64_t seed = 1;
  for (float alpha : {0.1f, 0.5f}) {
    const Bsdf bsdf = coatedLambertian(LobeKind::RoughDielectric, alpha, 1.5f, 0.6f);
    for (const Vec3& wo : {fromAngles(0.3f, 0.2f), fromAngles(1.3f, 2.0f)}) {
      test::DirectionTestOptions o;
      o.testCount = kChiSquareRuns;
      o.seed = seed++;
      o.subdivisions = 24;
      const auto r = test::chiSquareDirections(
          [&](Vec2 u, float uc) -> std::optional<Vec3> {
            const auto s = bsdf.sample(wo, uc, u, TransportMode::Radiance);
            if (!s) return std::nullopt;
            return s->wi;
          },
          [&](const Vec3& wi) { return double(bsdf.pdf(wo, wi, TransportMode::Radiance)); }, o);
      EXPECT_TRUE(r.passed) << "alpha " << alpha << " wo.z " << wo.z << ": " << r.detail;
    }
  }
}

TEST(BsdfLayer, CoatedEvalIsReciprocalAndNeverNaN) {
  const Bsdf rough = coatedLambertian(LobeKind::RoughDielectric, 0.3f, 1.5f, 0.8f);
  const Bsdf smooth = coatedLambertian(LobeKind::SmoothDielectric, 0, 1.5f, 0.8f);
  sampling::Pcg32 rng(9, 9);
  for (int i = 0; i < 20000; ++i) {
    const Vec3 a = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
    const Vec3 b = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
    for (const Bsdf* bsdf : {&rough, &smooth}) {
      const Spectrum fab = bsdf->eval(a, b, TransportMode::Radiance), fba = bsdf->eval(b, a, TransportMode::Radiance);
      ASSERT_FALSE(fab.hasNaNOrInf());
      ASSERT_NEAR(fab[0], fba[0], 1e-4f * std::max(1.0f, fab[0]));
      const auto s = bsdf->sample(a, rng.nextFloat(), Vec2(rng.nextFloat(), rng.nextFloat()), TransportMode::Radiance);
      if (s) {
        ASSERT_FALSE(s->f.hasNaNOrInf());
        ASSERT_TRUE(std::isfinite(s->pdfW) && s->pdfW > 0.0f);
      }
    }
  }
  for (const Vec3& wo : {Vec3(1, 0, 0), Vec3(0, 0, 0), glm::normalize(Vec3(1, 0, 1e-7f))}) {
    ASSERT_FALSE(rough.sample(wo, 0.5f, Vec2(0.5f), TransportMode::Radiance).has_value());
    ASSERT_FALSE(rough.eval(wo, Vec3(0, 0, 1), TransportMode::Radiance).hasNaNOrInf());
  }
}

// A coat reflects, so its direction never depends on the IOR: every lane uses the hero's IOR
// (lane 0) unless the lobe says its IOR varies (layer.cpp and ggx_reflection.cpp then compute
// one Fresnel term for the group). Lanes with other IORs must change nothing, bit for bit.
TEST(BsdfLayer, CoatUsesTheHeroIorInEveryLaneUnlessItVaries) {
  const auto coated = [](LobeKind kind, float alpha, const Spectrum& eta, bool etaVaries) {
    Bsdf bsdf(Frame(), Vec3(0, 0, 1));
    Lobe base;
    base.kind = LobeKind::Lambertian;
    base.weight = uniform(0.8f);
    base.underCoat = true;
    EXPECT_TRUE(bsdf.add(base));
    Lobe coat;
    coat.kind = kind;
    coat.weight = uniform(1);
    coat.a = eta;
    coat.etaVaries = etaVaries;
    coat.roughness = alpha;
    EXPECT_TRUE(bsdf.setCoat(coat));
    return bsdf;
  };
  Spectrum spread;
  for (int i = 0; i < 4; ++i) spread[i] = 1.5f + 0.1f * float(i);
  for (const auto& [kind, alpha] : {std::pair{LobeKind::RoughDielectric, 0.3f}, std::pair{LobeKind::SmoothDielectric, 0.0f}}) {
    const Bsdf hero = coated(kind, alpha, uniform(1.5f), false);
    const Bsdf spreadIgnored = coated(kind, alpha, spread, false);
    const Bsdf spreadUsed = coated(kind, alpha, spread, true);
    sampling::Pcg32 rng(21, 5);
    int lanesThatDiffer = 0;
    for (int i = 0; i < 5000; ++i) {
      const Vec3 wo = sampleUniformHemisphere(Vec2(rng.nextFloat(), rng.nextFloat()));
      const Vec3 wi = sampleUniformHemisphere(Vec2(rng.nextFloat(), rng.nextFloat()));
      const float uc = rng.nextFloat();
      const Vec2 u2(rng.nextFloat(), rng.nextFloat());
      const Spectrum fHero = hero.eval(wo, wi, TransportMode::Radiance);
      const Spectrum fIgnored = spreadIgnored.eval(wo, wi, TransportMode::Radiance);
      const Spectrum fUsed = spreadUsed.eval(wo, wi, TransportMode::Radiance);
      const auto sHero = hero.sample(wo, uc, u2, TransportMode::Radiance);
      const auto sIgnored = spreadIgnored.sample(wo, uc, u2, TransportMode::Radiance);
      const auto sUsed = spreadUsed.sample(wo, uc, u2, TransportMode::Radiance);
      ASSERT_EQ(sHero.has_value(), sIgnored.has_value());
      for (int lane = 0; lane < kLanes; ++lane) {
        ASSERT_EQ(fHero[lane], fIgnored[lane]) << "lane " << lane;
        if (sHero) {
          ASSERT_EQ(sHero->f[lane], sIgnored->f[lane]) << "lane " << lane;
        }
      }
      ASSERT_EQ(fHero[0], fUsed[0]);  // the hero's own IOR is 1.5 either way
      for (int lane = 1; lane < 4; ++lane) {
        lanesThatDiffer += fUsed[lane] != fHero[lane];
        if (sHero && sUsed && sUsed->wi == sHero->wi) lanesThatDiffer += sUsed->f[lane] != sHero->f[lane];
      }
    }
    EXPECT_GT(lanesThatDiffer, 1000) << "etaVaries must give lanes their own IOR";
  }
}

}  // namespace
}  // namespace tex::render
