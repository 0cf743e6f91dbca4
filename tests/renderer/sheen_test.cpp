// The sheen lobes (renderer/bsdf/sheen_lobe.h): cosine-weighted sampling follows the claimed
// density (chi-square over roughness and incidence, grazing and from below included), samples
// carry the lobe's own value and density, reciprocity, white furnace albedo <= 1 over a grid of
// roughness and incidence (the sheen alone, and a white base under a white sheen, which is
// also near 1 where the sheen needs no normalisation), and no NaN for degenerate input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "renderer/bsdf/bsdf.h"
#include "renderer/bsdf/sheen_albedo.h"
#include "renderer/sampling/pcg.h"
#include "tests/renderer/chi_square.h"

namespace tex::render {
namespace {

constexpr float kAlphas[] = {0.01f, 0.05f, 0.3f, 1.0f};
constexpr float kWoThetas[] = {0.0f, 0.8f, 1.4f, 1.569f, 2.5f};  // 1.569: cos 0.0018; 2.5: from below
// Chi-square: the sheen at 4 alphas x 5 directions, the base under a sheen at 2 alphas x 5.
constexpr int kChiSquareRuns = 20 + 10;

Spectrum uniform(float v) {
  Spectrum s;
  for (int i = 0; i < 4; ++i) s.v[i] = v;
  return s;
}

Vec3 fromAngles(float thetaRad, float phiRad) {
  return Vec3(std::sin(thetaRad) * std::cos(phiRad), std::sin(thetaRad) * std::sin(phiRad), std::cos(thetaRad));
}

Lobe sheenLobe(float alpha, const Spectrum& colour) {
  Lobe l;
  l.kind = LobeKind::Sheen;
  l.weight = colour;
  l.roughness = alpha;
  return l;
}

Lobe baseLobe(float alpha, const Spectrum& albedo, const Spectrum& sheenColour) {
  Lobe l;
  l.kind = LobeKind::LambertianUnderSheen;
  l.weight = albedo;
  l.a = sheenColour;
  l.roughness = alpha;
  return l;
}

void expectSamplesFollowPdf(const Lobe& lobe, uint64_t seed) {
  for (float theta : kWoThetas) {
    const Vec3 wo = fromAngles(theta, 0.7f);
    test::DirectionTestOptions o;
    o.testCount = kChiSquareRuns;
    o.seed = seed++;
    const auto r = test::chiSquareDirections(
        [&](Vec2 u, float uc) -> std::optional<Vec3> {
          const auto s = lobeSample(lobe, wo, uc, u, TransportMode::Radiance);
          if (!s) return std::nullopt;
          return s->wi;
        },
        [&](const Vec3& wi) { return double(lobePdf(lobe, wo, wi, TransportMode::Radiance)); }, o);
    EXPECT_TRUE(r.passed) << "alpha " << lobe.roughness << " theta " << theta << ": " << r.detail;
  }
}

TEST(Sheen, SamplesFollowPdf) {
  uint64_t seed = 100;
  for (float alpha : kAlphas) {
    expectSamplesFollowPdf(sheenLobe(alpha, uniform(1.0f)), seed);
    seed += 10;
  }
}

TEST(Sheen, BaseUnderSheenSamplesFollowPdf) {
  expectSamplesFollowPdf(baseLobe(0.05f, uniform(0.8f), uniform(1.0f)), 200);
  expectSamplesFollowPdf(baseLobe(0.7f, uniform(0.8f), uniform(0.5f)), 210);
}

TEST(Sheen, SamplesCarryTheLobesValueAndDensity) {
  sampling::Pcg32 rng(3, 9);
  for (const Lobe& lobe : {sheenLobe(0.2f, uniform(0.9f)), baseLobe(0.6f, uniform(0.5f), uniform(0.7f))})
    for (float theta : kWoThetas) {
      const Vec3 wo = fromAngles(theta, 2.0f);
      for (int i = 0; i < 2000; ++i) {
        const auto s = lobeSample(lobe, wo, rng.nextFloat(), Vec2(rng.nextFloat(), rng.nextFloat()), TransportMode::Radiance);
        ASSERT_TRUE(s);
        EXPECT_FALSE(s->specular);
        EXPECT_GT(s->wi.z * wo.z, 0.0f);  // reflection on wo's side
        EXPECT_EQ(s->pdfW, lobePdf(lobe, wo, s->wi, TransportMode::Radiance));
        const Spectrum f = lobeEval(lobe, wo, s->wi, TransportMode::Radiance);
        for (int lane = 0; lane < 4; ++lane) EXPECT_EQ(s->f.v[lane], f.v[lane]);
      }
    }
}

TEST(Sheen, ValuesAreReciprocal) {
  sampling::Pcg32 rng(5, 1);
  for (float alpha : kAlphas)
    for (const Lobe& lobe : {sheenLobe(alpha, uniform(0.8f)), baseLobe(alpha, uniform(0.6f), uniform(0.9f))})
      for (int i = 0; i < 3000; ++i) {
        // Cosines log-uniform down to 1e-5: the normalisation and the scaling matter near grazing.
        auto direction = [&] {
          const float c = std::pow(10.0f, -5.0f * rng.nextFloat());
          const float s = std::sqrt(1 - c * c), phi = 6.2831853f * rng.nextFloat();
          return Vec3(s * std::cos(phi), s * std::sin(phi), c);
        };
        const Vec3 wo = direction(), wi = direction();
        const float forward = lobeEval(lobe, wo, wi, TransportMode::Radiance).v[0];
        const float backward = lobeEval(lobe, wi, wo, TransportMode::Importance).v[0];
        if (forward == 0.0f) {  // a smooth sheen's value underflows far from grazing
          EXPECT_EQ(backward, 0.0f);
          continue;
        }
        EXPECT_NEAR(forward / backward, 1.0f, 1e-5f) << alpha << " " << wo.z << " " << wi.z;
      }
}

// int f(wo, wi) |cos theta_i| dw_i by the midpoint rule in s (cos theta_i = s^3, which crowds
// the nodes toward grazing, where small roughnesses concentrate) and phi (the lobes are
// symmetric about wo's plane); n x n/2 nodes.
double albedoByQuadrature(const Lobe& lobe, float cosThetaO, int n) {
  const Vec3 wo(std::sqrt(1 - cosThetaO * cosThetaO), 0.0f, cosThetaO);
  const int m = n / 2;
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const double s = (i + 0.5) / n, c = s * s * s, sinI = std::sqrt(1 - c * c);
    double ring = 0;
    for (int j = 0; j < m; ++j) {
      const double phi = (j + 0.5) * M_PI / m;
      const Vec3 wi(float(sinI * std::cos(phi)), float(sinI * std::sin(phi)), float(c));
      ring += lobeEval(lobe, wo, wi, TransportMode::Radiance).v[0];
    }
    sum += ring * (2 * M_PI / m) * c * 3 * s * s / n;
  }
  return sum;
}

constexpr float kFurnaceAlphas[] = {0.01f, 0.02f, 0.05f, 0.1f, 0.3f, 1.0f};
constexpr float kFurnaceCosines[] = {1.0f, 0.7f, 0.3f, 0.1f, 0.03f, 0.01f, 1e-3f, 1e-5f};

TEST(Sheen, FurnaceAlbedoIsAtMostOne) {
  // The white sheen alone. Two resolutions: their difference bounds the quadrature's error,
  // which the bound allows (it is ~1e-5; the albedos stay well below 1 anyway).
  double worst = 0;
  float worstAlpha = 0, worstCos = 0;
  for (float alpha : kFurnaceAlphas)
    for (float c : kFurnaceCosines) {
      const Lobe lobe = sheenLobe(alpha, uniform(1.0f));
      const double fine = albedoByQuadrature(lobe, c, 600), coarse = albedoByQuadrature(lobe, c, 300);
      EXPECT_LE(fine, 1.0 + 2 * std::fabs(fine - coarse)) << alpha << " " << c;
      if (fine > worst) worst = fine, worstAlpha = alpha, worstCos = c;
    }
  std::printf("sheen furnace: max albedo %.5f at alpha %g, cos %g\n", worst, worstAlpha, worstCos);
}

TEST(Sheen, WhiteBaseUnderWhiteSheenConservesEnergy) {
  // Sheen + base: at most 1 everywhere. From alpha 0.1 up, where the sheen's E <= 1 except
  // within cos ~ 1e-5 of grazing (so its normalisation removes next to nothing), it is 1 up to
  // the table's margins (<= 0.01 by SheenAlbedoTable.BoundsTheAlbedoFromAboveEverywhere).
  // Below, the normalisation of wi's near grazing removes energy the base does not get back
  // (measured: 0.980 at alpha 0.01, cos 0.1).
  double worst = 0, lowest = 2, lowestNormalised = 2;
  for (float alpha : kFurnaceAlphas)
    for (float c : kFurnaceCosines) {
      const double fine = albedoByQuadrature(sheenLobe(alpha, uniform(1.0f)), c, 600) +
                          albedoByQuadrature(baseLobe(alpha, uniform(1.0f), uniform(1.0f)), c, 600);
      const double coarse = albedoByQuadrature(sheenLobe(alpha, uniform(1.0f)), c, 300) +
                            albedoByQuadrature(baseLobe(alpha, uniform(1.0f), uniform(1.0f)), c, 300);
      EXPECT_LE(fine, 1.0 + 2 * std::fabs(fine - coarse)) << alpha << " " << c;
      worst = std::max(worst, fine);
      if (alpha >= 0.1f) {
        EXPECT_GE(fine, 0.99) << alpha << " " << c;
        lowest = std::min(lowest, fine);
      } else {
        lowestNormalised = std::min(lowestNormalised, fine);
      }
    }
  std::printf("sheen over white base: max albedo %.5f, min %.5f (alpha >= 0.1), %.5f (alpha < 0.1)\n", worst,
              lowest, lowestNormalised);
}

TEST(Sheen, BaseAlbedoIsWhatTheSheenLeaves) {
  // The base's own albedo is (1 - a Eb(wo)) per lane, exactly up to the quadrature.
  const Spectrum colour = uniform(0.5f);
  for (float alpha : {0.02f, 0.4f})
    for (float c : {0.9f, 0.2f, 0.01f}) {
      const double got = albedoByQuadrature(baseLobe(alpha, uniform(1.0f), colour), c, 600);
      EXPECT_NEAR(got, 1.0 - 0.5 * sheen::boundedAlbedo(alpha, c), 2e-4) << alpha << " " << c;
    }
}

// The base's scaling uses Eb_avg of its own roughness, which sheen_lobe.cpp remembers per
// thread for a few roughnesses: evaluations alternating over more roughnesses than it keeps,
// in an order that defeats any small cache, equal the formula with a fresh Eb_avg bit for bit.
TEST(Sheen, BaseScalingUsesItsOwnRoughnessAverageWhateverWasEvaluatedBefore) {
  const Vec3 wo = fromAngles(0.6f, 0.2f), wi = fromAngles(1.1f, 2.0f);
  const Spectrum colour = uniform(0.7f), albedo = uniform(0.9f);
  std::vector<float> alphas;
  for (int k = 0; k < 13; ++k) alphas.push_back(0.02f + 0.07f * float(k));
  for (int round = 0; round < 3; ++round) {
    for (size_t n = 0; n < alphas.size(); ++n) {
      const float alpha = alphas[(n * 5 + size_t(round)) % alphas.size()];  // a stride co-prime with 13
      const Spectrum f = lobeEval(baseLobe(alpha, albedo, colour), wo, wi, TransportMode::Radiance);
      const double a = std::clamp(double(colour.v[0]), 0.0, 1.0);
      const double clamped = sheen::clampRoughness(alpha);
      const double eo = sheen::boundedAlbedo(clamped, std::fabs(wo.z)), ei = sheen::boundedAlbedo(clamped, std::fabs(wi.z));
      const double scale = (1.0 - a * eo) * (1.0 - a * ei) / (1.0 - a * sheen::boundedAverageAlbedo(clamped));
      EXPECT_EQ(f.v[0], albedo.v[0] * float(scale * (1.0 / 3.14159265358979323846))) << "alpha " << alpha;
    }
  }
}

TEST(Sheen, DegenerateInputsGiveZeroNotNaN) {
  const Lobe lobes[] = {sheenLobe(0.3f, uniform(1.0f)), baseLobe(0.3f, uniform(1.0f), uniform(1.0f)),
                        sheenLobe(std::nanf(""), uniform(1.0f)), sheenLobe(-1.0f, uniform(1.0f))};
  const Vec3 up(0, 0, 1), flat(1, 0, 0), nan(std::nanf(""), 0, 1), down(0, 0, -1);
  for (const Lobe& lobe : lobes) {
    EXPECT_EQ(lobeEval(lobe, flat, up, TransportMode::Radiance).v[0], 0.0f);
    EXPECT_EQ(lobeEval(lobe, up, down, TransportMode::Radiance).v[0], 0.0f);
    EXPECT_EQ(lobePdf(lobe, up, flat, TransportMode::Radiance), 0.0f);
    EXPECT_FALSE(lobeSample(lobe, flat, 0.5f, Vec2(0.3f, 0.6f), TransportMode::Radiance));
    const float v = lobeEval(lobe, nan, up, TransportMode::Radiance).v[0];
    EXPECT_FALSE(std::isnan(v));
    const float f = lobeEval(lobe, fromAngles(1.3f, 0), fromAngles(1.4f, 0.3f), TransportMode::Radiance).v[0];
    EXPECT_TRUE(std::isfinite(f) && f > 0.0f);  // clamped roughness still gives a lobe
  }
}

}  // namespace
}  // namespace tex::render
