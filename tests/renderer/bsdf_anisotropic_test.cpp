// Anisotropic GGX (renderer/bsdf/ggx_anisotropic.h): normalisation of D and of the visible
// normals, chi-square of the rough conductor's and rough dielectric's sampling for several
// alpha pairs, rotations and incidences, the sampler's pdf against pdf(), reciprocity, the
// white furnace, bit-identity of equal alphas with the isotropic lobe, and the axis
// conventions (a 90 degree turn swaps the alphas; a larger alpha_x spreads along x).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "renderer/bsdf/bsdf.h"
#include "renderer/bsdf/microfacet.h"
#include "renderer/core/warp.h"
#include "renderer/sampling/pcg.h"
#include "tests/renderer/chi_square.h"
#include "tests/renderer/lobe_albedo.h"
#include "tests/renderer/lobe_chi_square.h"
#include "tests/renderer/ggx_quadrature.h"

namespace tex::render {
namespace {

struct AlphaPair {
  float x, y, rotationRad;
};
// Mild and strong anisotropy, both orientations, a turned axis, and one nearly a mirror along y.
constexpr AlphaPair kPairs[] = {{0.3f, 0.1f, 0.0f}, {0.05f, 0.4f, 0.0f}, {0.6f, 0.2f, 0.7f}, {1.0f, 0.02f, -1.2f}};
// Conductor: 4 pairs x 4 wo; dielectric: 2 pairs x 2 etas x 3 wo.
constexpr int kChiSquareRuns = 16 + 12;

Vec3 fromAngles(float thetaRad, float phiRad) {
  return Vec3(std::sin(thetaRad) * std::cos(phiRad), std::sin(thetaRad) * std::sin(phiRad), std::cos(thetaRad));
}

Spectrum uniform(float v) { return Spectrum(v); }

Lobe conductor(const AlphaPair& p, float k = 2.0f) {
  Lobe l;
  l.kind = LobeKind::RoughConductor;
  l.weight = uniform(1.0f);
  l.a = uniform(0.3f);
  l.b = uniform(k);
  l.roughness = p.x;
  l.roughnessY = p.y;
  l.anisotropyRotationRad = p.rotationRad;
  return l;
}

Lobe dielectric(const AlphaPair& p, float eta) {
  Lobe l = conductor(p);
  l.kind = LobeKind::RoughDielectric;
  l.a = uniform(eta);
  l.b = Spectrum();
  return l;
}


TEST(BsdfAnisotropic, DistributionAndVisibleNormalsIntegrateToOne) {
  for (const AlphaPair& p : kPairs) {
    if (std::min(p.x, p.y) < 0.05f) continue;  // too peaked for this grid
    const GgxAlpha alpha(p.x, p.y, p.rotationRad);
    const int nTheta = 4000, nPhi = 256;
    for (const Vec3& wo : {fromAngles(0.0f, 0.0f), fromAngles(1.0f, 0.3f), fromAngles(1.4f, 2.0f)}) {
      const auto [projected, visible] = test::ggxNormalisation(alpha, wo, nTheta, nPhi);
      EXPECT_NEAR(projected, 1.0, 3e-3) << p.x << " " << p.y;
      EXPECT_NEAR(visible, 1.0, 4e-3) << p.x << " " << p.y << " wo.z " << wo.z;
    }
  }
}

TEST(BsdfAnisotropic, ConductorSamplesFollowPdf) {
  uint64_t seed = 500;
  for (const AlphaPair& p : kPairs) {
    const Lobe lobe = conductor(p);
    for (const Vec3& wo : {fromAngles(0.0f, 0.0f), fromAngles(0.6f, 0.5f), fromAngles(1.3f, 2.0f),
                           fromAngles(2.2f, 4.0f)}) {
      test::DirectionTestOptions o;
      o.testCount = kChiSquareRuns;
      o.seed = seed++;
      o.subdivisions = std::min(p.x, p.y) < 0.1f ? 48 : 24;
      o.refineTolerance = 0.1;
      const auto r = test::chiSquareLobe(lobe, wo, o);
      std::printf("  aniso conductor (%.2f, %.2f, rot %.1f) wo.z %+.3f: p = %.3g\n", p.x, p.y, p.rotationRad, wo.z, r.pValue);
      EXPECT_TRUE(r.passed) << p.x << " " << p.y << " wo.z " << wo.z << ": " << r.detail;
    }
  }
}

TEST(BsdfAnisotropic, DielectricSamplesFollowPdf) {
  uint64_t seed = 600;
  for (const AlphaPair& p : {kPairs[0], kPairs[2]}) {
    for (float eta : {1.5f, 1.0f / 1.33f}) {
      const Lobe lobe = dielectric(p, eta);
      for (const Vec3& wo : {fromAngles(0.4f, 0.5f), fromAngles(1.4f, 2.0f), fromAngles(2.5f, 1.0f)}) {
        test::DirectionTestOptions o;
        o.testCount = kChiSquareRuns;
        o.seed = seed++;
        const double etaP = wo.z > 0 ? eta : 1.0 / eta;
        o.cosThetaBreaks = {-wo.z / etaP};  // where the refraction density jumps (bsdf_rough_test.cpp)
        o.refineTolerance = 0.1;
        const auto r = test::chiSquareLobe(lobe, wo, o);
        std::printf("  aniso dielectric (%.2f, %.2f, rot %.1f) eta %.3f wo.z %+.3f: p = %.3g\n", p.x, p.y, p.rotationRad,
                    eta, wo.z, r.pValue);
        EXPECT_TRUE(r.passed) << p.x << " " << p.y << " eta " << eta << " wo.z " << wo.z << ": " << r.detail;
      }
    }
  }
}

TEST(BsdfAnisotropic, SampledPdfIsPdfAndValueIsEval) {
  sampling::Pcg32 rng(7, 3);
  for (const AlphaPair& p : kPairs) {
    for (const Lobe& lobe : {conductor(p), dielectric(p, 1.5f)}) {
      int sampled = 0;
      for (int i = 0; i < 20000; ++i) {
        const Vec3 wo = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
        const auto s = lobeSample(lobe, wo, rng.nextFloat(), Vec2(rng.nextFloat(), rng.nextFloat()), TransportMode::Radiance);
        if (!s) continue;
        ++sampled;
        const float pdf = lobePdf(lobe, wo, s->wi, TransportMode::Radiance);
        ASSERT_NEAR(s->pdfW, pdf, 1e-5f * std::max(1.0f, pdf));
        const Spectrum f = lobeEval(lobe, wo, s->wi, TransportMode::Radiance);
        ASSERT_NEAR(s->f[0], f[0], 1e-5f * std::max(1.0f, f[0]));
      }
      EXPECT_GT(sampled, 10000);
    }
  }
}

TEST(BsdfAnisotropic, ReflectionIsReciprocalAndTransmissionGeneralizedReciprocal) {
  sampling::Pcg32 rng(8, 1);
  for (const AlphaPair& p : kPairs) {
    const float eta = 1.5f;
    const Lobe metal = conductor(p), glass = dielectric(p, eta);
    int reflected = 0, transmitted = 0;
    for (int i = 0; i < 40000; ++i) {
      const Vec3 a = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
      const Vec3 b = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
      if (sameHemisphere(a, b)) {
        for (const Lobe* l : {&metal, &glass}) {
          const float fab = lobeEval(*l, a, b, TransportMode::Radiance)[0], fba = lobeEval(*l, b, a, TransportMode::Radiance)[0];
          ASSERT_NEAR(fab, fba, 1e-4f * std::max(1.0f, fab));
        }
        reflected += lobeEval(metal, a, b, TransportMode::Radiance)[0] > 0.0f;
      } else {
        // Veach eq. 5.14: f(a, b) / eta_a^2 = f(b, a) / eta_b^2 in Radiance mode.
        const float etaA = a.z > 0 ? 1.0f : eta, etaB = b.z > 0 ? 1.0f : eta;
        const float fab = lobeEval(glass, a, b, TransportMode::Radiance)[0];
        const float fba = lobeEval(glass, b, a, TransportMode::Radiance)[0];
        ASSERT_NEAR(fab / (etaA * etaA), fba / (etaB * etaB), 1e-4f * std::max(1.0f, fab));
        transmitted += fab > 0.0f;
      }
    }
    EXPECT_GT(reflected, 5000);
    EXPECT_GT(transmitted, 300);
  }
}

double furnaceAlbedo(const Lobe& lobe, const Vec3& wo, int n, uint64_t seed) {
  sampling::Pcg32 rng(seed, 5);
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const auto s = lobeSample(lobe, wo, rng.nextFloat(), Vec2(rng.nextFloat(), rng.nextFloat()), TransportMode::Radiance);
    if (!s) continue;
    const double w = s->f[0] * std::fabs(s->wi.z) / s->pdfW;
    EXPECT_LE(w, 1.0 + 1e-4);  // VNDF weights are G1-like: at most 1 with F = 1
    sum += w;
  }
  return sum / n;
}

TEST(BsdfAnisotropic, FurnaceIsAtMostOneAndBetweenTheIsotropicAlbedosOfItsAlphas) {
  // k -> infinity makes F = 1: the single-scattering albedo, at most 1; an anisotropic lobe's
  // masking lies between that of its two alphas taken isotropically (a tolerance for the
  // statistics and for grazing azimuths), and a uniform-hemisphere integral of eval agrees.
  for (const AlphaPair& p : kPairs) {
    const Lobe lobe = conductor(p, 1e4f);
    Lobe lo = lobe, hi = lobe;
    lo.roughness = lo.roughnessY = std::min(p.x, p.y);
    hi.roughness = hi.roughnessY = std::max(p.x, p.y);
    for (float theta : {0.0f, 0.7f, 1.2f}) {
      for (float phi : {0.0f, 1.0f, 1.5708f}) {
        const Vec3 wo = fromAngles(theta, phi);
        const double a = furnaceAlbedo(lobe, wo, 100000, 31);
        const double aLo = furnaceAlbedo(lo, wo, 100000, 32), aHi = furnaceAlbedo(hi, wo, 100000, 33);
        std::printf("  aniso furnace (%.2f, %.2f, rot %.1f) theta %.1f phi %.1f: %.4f (isotropic %.4f .. %.4f)\n", p.x,
                    p.y, p.rotationRad, theta, phi, a, aHi, aLo);
        EXPECT_LE(a, 1.0 + 1e-3);
        EXPECT_GE(a, aHi - 0.01);
        EXPECT_LE(a, aLo + 0.01);
        if (theta == 0.7f && std::min(p.x, p.y) >= 0.1f) {
          const test::AlbedoEstimate uniform = test::uniformHemisphereAlbedo(lobe, wo, 34, 400000);
          EXPECT_NEAR(a, uniform.mean, 5 * uniform.standardError + 3e-3);
        }
      }
    }
  }
}

TEST(BsdfAnisotropic, EqualAlphasAreTheIsotropicLobeBitForBit) {
  sampling::Pcg32 rng(9, 2);
  for (float alpha : {0.05f, 0.3f, 1.0f}) {
    for (LobeKind kind : {LobeKind::RoughConductor, LobeKind::RoughDielectric}) {
      Lobe iso = kind == LobeKind::RoughConductor ? conductor({alpha, 0.0f, 0.0f}) : dielectric({alpha, 0.0f, 0.0f}, 1.5f);
      Lobe same = iso;
      same.roughnessY = alpha;
      same.anisotropyRotationRad = 0.8f;  // turning an isotropic roughness changes nothing
      for (int i = 0; i < 2000; ++i) {
        const Vec3 wo = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
        const Vec3 wi = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
        const float uc = rng.nextFloat();
        const Vec2 u(rng.nextFloat(), rng.nextFloat());
        for (TransportMode mode : {TransportMode::Radiance, TransportMode::Importance}) {
          ASSERT_EQ(lobeEval(iso, wo, wi, mode)[0], lobeEval(same, wo, wi, mode)[0]);
          ASSERT_EQ(lobePdf(iso, wo, wi, mode), lobePdf(same, wo, wi, mode));
          const auto a = lobeSample(iso, wo, uc, u, mode), b = lobeSample(same, wo, uc, u, mode);
          ASSERT_EQ(a.has_value(), b.has_value());
          if (!a) continue;
          ASSERT_EQ(a->wi.x, b->wi.x);
          ASSERT_EQ(a->wi.y, b->wi.y);
          ASSERT_EQ(a->wi.z, b->wi.z);
          ASSERT_EQ(a->pdfW, b->pdfW);
          ASSERT_EQ(a->f[0], b->f[0]);
        }
      }
      // GgxAlpha of two equal alphas is the float overloads' arithmetic.
      const Vec3 m = glm::normalize(Vec3(0.3f, -0.2f, 0.9f)), w = glm::normalize(Vec3(-0.5f, 0.1f, 0.4f));
      const GgxAlpha pair(alpha, alpha, 0.4f);
      EXPECT_EQ(ggxD(m, pair), ggxD(m, alpha));
      EXPECT_EQ(ggxLambda(w, pair), ggxLambda(w, alpha));
      EXPECT_EQ(ggxVisibleD(w, m, pair), ggxVisibleD(w, m, alpha));
    }
  }
}

// (x, y) -> (-y, x): exact in floats.
Vec3 turn90(const Vec3& v) { return Vec3(-v.y, v.x, v.z); }

TEST(BsdfAnisotropic, TurningTheFrame90DegreesSwapsTheAlphas) {
  // A lobe with alphas (ax, ay) seen in a tangent frame turned by 90 degrees is the lobe with
  // (ay, ax): f(wo, wi) of (ax, ay) equals f(turn wo, turn wi) of (ay, ax); and the rotation
  // parameter at pi/2 does the same turn.
  sampling::Pcg32 rng(10, 4);
  for (const AlphaPair& p : kPairs) {
    const AlphaPair swapped{p.y, p.x, 0.0f}, plain{p.x, p.y, 0.0f}, turned{p.x, p.y, 0.5f * kPi};
    for (bool glass : {false, true}) {
      const Lobe a = glass ? dielectric(plain, 1.5f) : conductor(plain);
      const Lobe b = glass ? dielectric(swapped, 1.5f) : conductor(swapped);
      const Lobe c = glass ? dielectric(turned, 1.5f) : conductor(turned);
      int nonZero = 0;
      for (int i = 0; i < 5000; ++i) {
        const Vec3 wo = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
        const Vec3 wi = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
        const float fa = lobeEval(a, wo, wi, TransportMode::Radiance)[0];
        const float fb = lobeEval(b, turn90(wo), turn90(wi), TransportMode::Radiance)[0];
        ASSERT_NEAR(fa, fb, 1e-4f * std::max(1.0f, fa));
        const float pa = lobePdf(a, wo, wi, TransportMode::Radiance);
        ASSERT_NEAR(pa, lobePdf(b, turn90(wo), turn90(wi), TransportMode::Radiance), 1e-4f * std::max(1.0f, pa));
        // c's axis is local y: it is b's lobe without the frame turned, i.e. a's lobe turned.
        const float fc = lobeEval(c, turn90(wo), turn90(wi), TransportMode::Radiance)[0];
        ASSERT_NEAR(fa, fc, 1e-4f * std::max(1.0f, fa));
        nonZero += fa > 0.0f;
      }
      EXPECT_GT(nonZero, 1000);
    }
  }
}

TEST(BsdfAnisotropic, TheLargerAlphaSpreadsTheReflectionAlongItsAxis) {
  // Normal incidence, alphas (0.4, 0.05): reflected directions spread along x, hardly along y;
  // turned by 90 degrees the other way round.
  for (float rotation : {0.0f, 0.5f * kPi}) {
    const Lobe lobe = conductor({0.4f, 0.05f, rotation});
    sampling::Pcg32 rng(11, 1);
    double sumX2 = 0, sumY2 = 0;
    int n = 0;
    for (int i = 0; i < 20000; ++i) {
      const auto s = lobeSample(lobe, Vec3(0, 0, 1), 0.5f, Vec2(rng.nextFloat(), rng.nextFloat()), TransportMode::Radiance);
      if (!s) continue;
      sumX2 += s->wi.x * s->wi.x;
      sumY2 += s->wi.y * s->wi.y;
      ++n;
    }
    const double spreadX = std::sqrt(sumX2 / n), spreadY = std::sqrt(sumY2 / n);
    if (rotation == 0.0f) {
      EXPECT_GT(spreadX, 4.0 * spreadY);
    } else {
      EXPECT_GT(spreadY, 4.0 * spreadX);
    }
  }
}

}  // namespace
}  // namespace tex::render
