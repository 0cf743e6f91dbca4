// GGX lobes and the thin slab: sampled directions follow the claimed densities (chi-square over
// roughness, incidence incl. grazing and from inside, and IOR down to 1.01; the visible normals
// themselves; per sample, the density against the facet's measured Jacobian), reciprocity
// (plain for reflection, generalized for radiance-mode transmission), white furnace bounds,
// per-lane densities for spectral MIS, thin-slab energy, and no NaN for degenerate inputs or
// near-index-matched IORs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

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

constexpr float kAlphas[] = {0.05f, 0.2f, 0.5f, 1.0f};
constexpr float kEtas[] = {1.1f, 1.5f, 2.4f};
// Chi-square IORs: near index-matched (1.01, 1.1), ordinary, high, and a lower index inside
// (1 / 1.1: total internal reflection seen from outside). eta = 1.1 once failed (the pdf's
// integral ~1e-3 off the sampled mass): the refraction density jumps along the ring where the
// generalized half vector reaches the microfacet horizon (see refractionHorizonCosTheta) and
// the midpoint quadrature misweighed that ring; the lobe itself was right (sample-by-sample
// densities and the sampled normals' histogram agree, tests below).
constexpr float kChiSquareEtas[] = {1.01f, 1.1f, 1.5f, 2.4f, 1.0f / 1.1f};
// Conductor: 4 alphas x 4 wo; dielectric: 4 alphas x 5 etas x 3 wo; per-lane densities: 2;
// visible normals: 2 alphas x 2 w; rough thin wall: 4 alphas x 3 wo.
constexpr int kChiSquareRuns = 16 + 60 + 2 + 4 + 12;

Spectrum lanes(std::initializer_list<float> values) {
  Spectrum s;
  int i = 0;
  for (float v : values) s[i++] = v;
  return s;
}

Vec3 fromAngles(float thetaRad, float phiRad) {
  return Vec3(std::sin(thetaRad) * std::cos(phiRad), std::sin(thetaRad) * std::sin(phiRad), std::cos(thetaRad));
}

Lobe roughConductor(float alpha, const Spectrum& eta, const Spectrum& k) {
  Lobe l;
  l.kind = LobeKind::RoughConductor;
  l.weight = lanes({1, 1, 1, 1});
  l.a = eta;
  l.b = k;
  l.roughness = alpha;
  return l;
}

Lobe roughDielectric(float alpha, const Spectrum& eta, bool etaVaries = false) {
  Lobe l;
  l.kind = LobeKind::RoughDielectric;
  l.weight = lanes({1, 1, 1, 1});
  l.a = eta;
  l.etaVaries = etaVaries;
  l.roughness = alpha;
  return l;
}

Spectrum uniform(float v) { return lanes({v, v, v, v}); }

test::DirectionTestOptions conductorChiOptions(uint64_t seed, float alpha) {
  test::DirectionTestOptions o;
  o.testCount = kChiSquareRuns;
  o.seed = seed;
  // Peaked lobes need fine quadrature of the expected counts per cell: 6 x 6 points misplace
  // ~1e-2 of the mass.
  o.subdivisions = alpha < 0.1f ? 48 : 24;
  return o;
}

// Where the refraction density jumps: wm ~ wo + eta_p wi lies on the microfacet horizon
// (wm.z = 0) exactly when wi.z = -wo.z / eta_p, and D there is alpha^2 / pi, not 0, so the
// transmitted density drops from D_wo(wm) (1 - F) |dwm/dwi| to 0 across that ring. Near
// eta = 1 the ring passes next to the lobe's peak (dwm/dwi ~ 1 / (eta - 1)^2 at wi = -wo).
double refractionHorizonCosTheta(const Vec3& wo, float eta) {
  const double etaP = wo.z > 0 ? eta : 1.0 / eta;
  return -wo.z / etaP;
}

// Rough dielectric densities are peaked (width ~ alpha (eta - 1) / eta near eta = 1) and jump
// on the horizon ring: integrate each side of the ring separately, and refine each cell's grid
// until its expected count is converged to 0.1 standard deviations.
test::DirectionTestOptions dielectricChiOptions(uint64_t seed, const Vec3& wo, float heroEta) {
  test::DirectionTestOptions o;
  o.testCount = kChiSquareRuns;
  o.seed = seed;
  o.cosThetaBreaks = {refractionHorizonCosTheta(wo, heroEta)};
  o.refineTolerance = 0.1;
  return o;
}


// ---------------------------------------------------------------- Distribution

TEST(BsdfRough, GgxDistributionIsNormalizedAndVisibleNormalsIntegrateToOne) {
  // int D(m) cos(theta_m) dm = 1 and int D_wo(m) dm = 1 (Heitz 2014, eqs. 4 and 38), by
  // midpoint quadrature in (cos theta, phi) over the upper hemisphere.
  for (float alpha : {0.1f, 0.3f, 0.7f, 1.0f}) {
    const int nTheta = 4000, nPhi = 64;
    for (const Vec3& wo : {fromAngles(0.0f, 0.0f), fromAngles(1.0f, 0.3f), fromAngles(1.5f, 2.0f)}) {
      const auto [projected, visible] = test::ggxNormalisation(alpha, wo, nTheta, nPhi);
      EXPECT_NEAR(projected, 1.0, 2e-3) << alpha;
      EXPECT_NEAR(visible, 1.0, 3e-3) << "alpha " << alpha << " wo.z " << wo.z;
    }
  }
}

// ---------------------------------------------------------------- Chi-square

TEST(BsdfRough, ConductorSamplesFollowPdf) {
  uint64_t seed = 1;
  for (float alpha : kAlphas) {
    const Lobe lobe = roughConductor(alpha, lanes({0.2f, 1.1f, 0.5f}), lanes({3.0f, 2.0f, 0.0f}));
    for (const Vec3& wo : {fromAngles(0.3f, 0.5f), fromAngles(1.2f, 2.0f), fromAngles(1.53f, 4.0f),
                           fromAngles(2.5f, 1.0f)}) {
      const auto r = test::chiSquareLobe(lobe, wo, conductorChiOptions(seed++, alpha));
      EXPECT_TRUE(r.passed) << "alpha " << alpha << " wo.z " << wo.z << ": " << r.detail;
    }
  }
}

void dielectricChiSquare(float alpha, uint64_t seed) {
  for (float eta : kChiSquareEtas) {
    const Lobe lobe = roughDielectric(alpha, uniform(eta));
    for (const Vec3& wo : {fromAngles(0.5f, 0.5f), fromAngles(1.53f, 2.0f), fromAngles(2.4f, 1.0f)}) {
      const auto r = test::chiSquareLobe(lobe, wo, dielectricChiOptions(seed++, wo, eta));
      EXPECT_TRUE(r.passed) << "alpha " << alpha << " eta " << eta << " wo.z " << wo.z << ": " << r.detail;
    }
  }
}

TEST(BsdfRough, DielectricSamplesFollowPdfAlpha005) { dielectricChiSquare(0.05f, 100); }
TEST(BsdfRough, DielectricSamplesFollowPdfAlpha02) { dielectricChiSquare(0.2f, 200); }
TEST(BsdfRough, DielectricSamplesFollowPdfAlpha05) { dielectricChiSquare(0.5f, 300); }
TEST(BsdfRough, DielectricSamplesFollowPdfAlpha1) { dielectricChiSquare(1.0f, 400); }

TEST(BsdfRough, VisibleNormalSamplesFollowVisibleD) {
  // The half vectors themselves, before reflection or refraction: m ~ D_w(m) on the side facing
  // w (from below, -w's visible normals, Heitz 2018).
  // (Smaller alphas put a peak of width ~alpha^2 in cos(theta) at the pole, which costs the
  // quadrature ~1e8 density evaluations.)
  uint64_t seed = 600;
  for (float alpha : {0.2f, 1.0f})
    for (const Vec3& w : {fromAngles(1.53f, 2.0f), fromAngles(2.4f, 1.0f)}) {
      const Vec3 wUpper = w.z < 0 ? -w : w;
      test::DirectionTestOptions o;
      o.testCount = kChiSquareRuns;
      o.seed = seed++;
      // Near the pole the phi cells are thin wedges, and at grazing w only a sliver of one is
      // visible (w.m > 0): start finer so that the doubling does not accept 0 = 0 there.
      o.subdivisions = 24;
      o.refineTolerance = 0.1;
      const auto r = test::chiSquareDirections(
          [&](Vec2 u, float) -> std::optional<Vec3> { return ggxSampleVisibleNormal(w, alpha, u); },
          [&](const Vec3& m) { return dot3(wUpper, m) > 0 ? double(ggxVisibleD(w, m, alpha)) : 0.0; }, o);
      EXPECT_TRUE(r.passed) << "alpha " << alpha << " w.z " << w.z << ": " << r.detail;
    }
}

// Reflection or refraction of wo by the facet m in double precision (nothing on TIR).
std::optional<glm::dvec3> scatterThroughFacet(const glm::dvec3& wo, glm::dvec3 m, double eta, bool reflect) {
  double cosO = glm::dot(wo, m);
  if (reflect) return 2.0 * cosO * m - wo;
  double etaRel = eta;  // transmitted side over incident side
  if (cosO < 0) {
    m = -m;
    cosO = -cosO;
    etaRel = 1.0 / eta;
  }
  const double sin2T = (1.0 - cosO * cosO) / (etaRel * etaRel);
  if (sin2T >= 1.0) return std::nullopt;
  return -wo / etaRel + m * (cosO / etaRel - std::sqrt(1.0 - sin2T));
}

TEST(BsdfRough, DielectricSampleDensityIsThePdfAndTheSampledFacetsDensityOverItsJacobian) {
  // Per sample: pdfW is exactly what lobePdf says at wi, and equals the density of the facet the
  // sampler drew (the visible normal for the same u) times the choice probability (F or 1 - F),
  // over |dwi/dm| measured by central differences of the scattering in double precision: an
  // independent check of the Jacobian of the (generalized) half vector, Walter eq. 14 / 17.
  sampling::Pcg32 rng(81, 4);
  for (float eta : kChiSquareEtas)
    for (float alpha : {0.2f, 0.5f, 1.0f})
      for (const Vec3& wo : {fromAngles(0.5f, 0.5f), fromAngles(1.0f, 0.5f), fromAngles(1.5f, 2.0f),
                             fromAngles(2.4f, 1.0f)}) {
        const Lobe lobe = roughDielectric(alpha, uniform(eta));
        double maxRelativeError = 0;
        int transmissions = 0;
        for (int i = 0; i < 4000; ++i) {
          const Vec2 u(rng.nextFloat(), rng.nextFloat());
          const float uc = rng.nextFloat();
          const auto s = lobeSample(lobe, wo, uc, u, TransportMode::Radiance);
          if (!s) continue;
          ASSERT_EQ(s->pdfW, lobePdf(lobe, wo, s->wi, TransportMode::Radiance));
          const Spectrum f = lobeEval(lobe, wo, s->wi, TransportMode::Radiance);
          for (int k = 0; k < 4; ++k) ASSERT_EQ(s->f[k], f[k]);
          const Vec3 m = ggxSampleVisibleNormal(wo, alpha, u);
          const bool reflected = s->wi.z * wo.z > 0;
          transmissions += !reflected;
          // Near total internal reflection the float refraction (cos_t = sqrt(1 - sin^2)) puts
          // wi up to ~1e-6 rad off the exact refraction of m, where |dpdf/dwi| is large.
          if (std::fabs(dot3(s->wi, m)) < 0.05f) continue;
          const double reflectance = fresnelDielectric(dot3(wo, m), eta);
          const double facetPdf = ggxVisibleD(wo, m, alpha) * (reflected ? reflectance : 1 - reflectance);
          const glm::dvec3 wod(wo), md(m);
          const glm::dvec3 axisNotM = std::fabs(md.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
          const glm::dvec3 t1 = glm::normalize(glm::cross(md, axisNotM)), t2 = glm::cross(md, t1);
          const double h = 1e-6;
          glm::dvec3 d[2];
          bool ok = true;
          for (int axis = 0; axis < 2; ++axis) {
            const glm::dvec3 t = axis == 0 ? t1 : t2;
            const auto plus = scatterThroughFacet(wod, glm::normalize(md + h * t), eta, reflected);
            const auto minus = scatterThroughFacet(wod, glm::normalize(md - h * t), eta, reflected);
            ok = ok && plus && minus;
            if (ok) d[axis] = (*plus - *minus) / (2 * h);
          }
          if (!ok) continue;  // within h of total internal reflection
          const double jacobian = glm::length(glm::cross(d[0], d[1]));  // dwi / dm (solid angles)
          const double expected = facetPdf / jacobian;
          const double relativeError = std::fabs(s->pdfW - expected) / expected;
          maxRelativeError = std::max(maxRelativeError, relativeError);
        }
        std::printf("  eta %.3f alpha %.1f cos_o %+.3f: max relative error %.2e\n", eta, alpha, wo.z,
                    maxRelativeError);
        // Float evaluation: measured <= 1e-4 (largest at eta = 1.01, where the half vector
        // wo + eta_p wi, of length >= eta - 1, loses two digits); a wrong Jacobian is off by O(1).
        EXPECT_LT(maxRelativeError, 3e-4) << "eta " << eta << " alpha " << alpha << " wo.z " << wo.z;
        EXPECT_GT(transmissions, 100) << "eta " << eta << " alpha " << alpha << " wo.z " << wo.z;
      }
}

TEST(BsdfRough, DielectricStaysFiniteAndBoundedNearIndexMatched) {
  // eta -> 1 narrows the transmission lobe to the pass-through direction (dwm/dwi ~ 1/(eta-1)^2
  // at wi = -wo): values get large but stay finite, and the importance-mode sample weight is
  // G / G1(wo) <= 1 whatever eta (the (wi.wm + wo.wm / eta_p)^2 of f and pdf cancel).
  sampling::Pcg32 rng(91, 2);
  for (float eta : {1.0002f, 1.001f, 1.01f, 1.0f / 1.0002f, 1.0f / 1.001f})
    for (float alpha : {1e-3f, 0.05f, 0.5f, 1.0f}) {
      const Lobe lobe = roughDielectric(alpha, uniform(eta));
      int nonZero = 0;
      for (int i = 0; i < 3000; ++i) {
        const Vec3 wo = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
        const auto s = lobeSample(lobe, wo, rng.nextFloat(), Vec2(rng.nextFloat(), rng.nextFloat()),
                                  TransportMode::Importance);
        if (s) {
          ASSERT_FALSE(s->f.hasNaNOrInf());
          ASSERT_TRUE(std::isfinite(s->pdfW) && s->pdfW > 0.0f) << eta << " " << alpha;
          const float weight = s->f[0] * std::fabs(s->wi.z) / s->pdfW;
          ASSERT_LE(weight, 1.0f + 1e-3f) << "eta " << eta << " alpha " << alpha << " wo.z " << wo.z;
        }
        const Vec3 nearPassThrough = glm::normalize(-wo + Vec3(1e-4f, 0, 0));
        for (const Vec3& wi : {-wo, nearPassThrough, sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()))}) {
          for (TransportMode mode : {TransportMode::Radiance, TransportMode::Importance}) {
            const float f = lobeEval(lobe, wo, wi, mode)[0], pdf = lobePdf(lobe, wo, wi, mode);
            ASSERT_TRUE(std::isfinite(f) && f >= 0.0f) << eta << " " << alpha;
            ASSERT_TRUE(std::isfinite(pdf) && pdf >= 0.0f) << eta << " " << alpha;
            nonZero += pdf > 0.0f;
          }
        }
      }
      EXPECT_GT(nonZero, 0) << eta << " " << alpha;
    }
}

TEST(BsdfRough, LanePdfIsTheDensityOfThatLaneAsHero) {
  // Sampling with lane 2's eta as the hero must follow lobePdfForLane(..., 2) of the original.
  const Spectrum etas = lanes({1.5f, 1.6f, 1.8f, 1.4f});
  const Lobe lobe = roughDielectric(0.3f, etas, true);
  Lobe swapped = lobe;
  swapped.a = lanes({1.8f, 1.6f, 1.5f, 1.4f});
  uint64_t seed = 500;
  for (const Vec3& wo : {fromAngles(0.6f, 0.5f), fromAngles(2.2f, 1.0f)}) {
    const auto r = test::chiSquareDirections(
        [&](Vec2 u, float uc) -> std::optional<Vec3> {
          const auto s = lobeSample(swapped, wo, uc, u, TransportMode::Radiance);
          if (!s) return std::nullopt;
          return s->wi;
        },
        [&](const Vec3& wi) { return double(lobePdfForLane(lobe, wo, wi, TransportMode::Radiance, 2)); },
        dielectricChiOptions(seed++, wo, 1.8f));
    EXPECT_TRUE(r.passed) << "wo.z " << wo.z << ": " << r.detail;
  }
}

TEST(BsdfRough, LanePdfEqualsPdfForTheHeroAndIntegratesToAtMostOne) {
  const Spectrum etas = lanes({1.5f, 1.55f, 1.7f, 2.4f});
  sampling::Pcg32 rng(11, 2);
  for (float alpha : kAlphas) {
    const Lobe lobe = roughDielectric(alpha, etas, true);
    for (const Vec3& wo : {fromAngles(0.4f, 0.5f), fromAngles(1.4f, 1.0f), fromAngles(2.7f, 3.0f)}) {
      for (int i = 0; i < 2000; ++i) {
        const Vec3 wi = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
        ASSERT_EQ(lobePdfForLane(lobe, wo, wi, TransportMode::Radiance, 0), lobePdf(lobe, wo, wi, TransportMode::Radiance));
      }
      // Integral over the sphere by importance sampling with the hero's own sampler:
      // E[pdf_k / pdf_0] = int_{pdf_0 > 0} pdf_k <= 1, plus a uniform estimate of the rest.
      for (int lane = 1; lane < 4; ++lane) {
        double sum = 0;
        const int n = 200000;
        for (int i = 0; i < n; ++i) {
          const Vec3 wi = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
          sum += lobePdfForLane(lobe, wo, wi, TransportMode::Radiance, lane) / kUniformSpherePdfW;
        }
        const double integral = sum / n;
        EXPECT_LE(integral, 1.0 + (alpha < 0.1f ? 0.05 : 0.01)) << "alpha " << alpha << " lane " << lane;
        EXPECT_GT(integral, 0.5) << "alpha " << alpha << " lane " << lane;  // a real density, not 0
      }
    }
  }
}

// ---------------------------------------------------------------- Reciprocity

TEST(BsdfRough, ConductorAndDielectricReflectionAreReciprocal) {
  sampling::Pcg32 rng(21, 1);
  for (float alpha : kAlphas) {
    const Lobe conductor = roughConductor(alpha, lanes({0.2f, 1.1f}), lanes({3.0f, 2.0f}));
    const Lobe dielectric = roughDielectric(alpha, uniform(1.5f));
    int checked = 0;
    for (int i = 0; i < 20000; ++i) {
      const Vec3 a = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
      const Vec3 b = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
      if (!sameHemisphere(a, b)) continue;
      for (const Lobe* l : {&conductor, &dielectric}) {
        for (TransportMode mode : {TransportMode::Radiance, TransportMode::Importance}) {
          const Spectrum fab = lobeEval(*l, a, b, mode), fba = lobeEval(*l, b, a, mode);
          for (int k = 0; k < 2; ++k) ASSERT_NEAR(fab[k], fba[k], 1e-4f * std::max(1.0f, fab[k]));
        }
      }
      checked += lobeEval(conductor, a, b, TransportMode::Radiance)[0] > 0.0f;
    }
    EXPECT_GT(checked, 5000);
  }
}

TEST(BsdfRough, TransmissionSatisfiesGeneralizedReciprocity) {
  // Veach 1997 eq. 5.14: f(wo, wi) / eta_o^2 = f(wi, wo) / eta_i^2 in Radiance mode, with
  // eta_o, eta_i the indices on wo's and wi's sides; Importance mode is the adjoint:
  // f_importance(wo, wi) = f_radiance(wi, wo).
  sampling::Pcg32 rng(22, 1);
  for (float alpha : kAlphas) {
    for (float eta : kEtas) {
      const Lobe lobe = roughDielectric(alpha, uniform(eta));
      int nonZero = 0;
      for (int i = 0; i < 20000; ++i) {
        const Vec3 a = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
        const Vec3 b = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
        if (sameHemisphere(a, b)) continue;
        const float etaA = a.z > 0 ? 1.0f : eta, etaB = b.z > 0 ? 1.0f : eta;
        const float fab = lobeEval(lobe, a, b, TransportMode::Radiance)[0];
        const float fba = lobeEval(lobe, b, a, TransportMode::Radiance)[0];
        ASSERT_NEAR(fab / (etaA * etaA), fba / (etaB * etaB), 1e-4f * std::max(1.0f, fab)) << alpha << " " << eta;
        const float iab = lobeEval(lobe, a, b, TransportMode::Importance)[0];
        ASSERT_NEAR(iab, fba, 1e-4f * std::max(1.0f, iab));
        ASSERT_NEAR(lobeEval(lobe, b, a, TransportMode::Importance)[0], fab, 1e-4f * std::max(1.0f, fab));
        nonZero += fab > 0.0f;
      }
      EXPECT_GT(nonZero, 300) << alpha << " " << eta;
    }
  }
}

// ---------------------------------------------------------------- Furnace

struct Albedo {
  double mean = 0;
  double maxWeight = 0;
};

Albedo albedo(const Lobe& lobe, const Vec3& wo, TransportMode mode, int lane, int n, uint64_t seed) {
  sampling::Pcg32 rng(seed, 5);
  Albedo a;
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const auto s = lobeSample(lobe, wo, rng.nextFloat(), Vec2(rng.nextFloat(), rng.nextFloat()), mode);
    if (!s) continue;
    EXPECT_FALSE(s->f.hasNaNOrInf());
    const double w = s->f[lane] * std::fabs(s->wi.z) / s->pdfW;
    EXPECT_TRUE(std::isfinite(w));
    sum += w;
    a.maxWeight = std::max(a.maxWeight, w);
  }
  a.mean = sum / n;
  return a;
}

TEST(BsdfRough, ConductorFurnaceIsAtMostOneAndNearOneWhenSmooth) {
  // k -> infinity: F = 1, so the albedo is the single-scattering GGX albedo: <= 1, and the
  // energy lost to masking grows with roughness and at grazing (Kulla & Conty 2017). The
  // sampler's estimate must agree with an independent uniform-hemisphere integral of eval.
  const Lobe base = roughConductor(0.0f, uniform(0.2f), uniform(1e4f));
  for (float alpha : kAlphas) {
    Lobe lobe = base;
    lobe.roughness = alpha;
    for (float theta : {0.0f, 0.7f, 1.2f, 1.45f}) {
      const Vec3 wo = fromAngles(theta, 0.3f);
      const Albedo a = albedo(lobe, wo, TransportMode::Radiance, 0, 200000, 31);
      std::printf("  rough conductor alpha %.2f cos_o %.3f: albedo %.4f\n", alpha, wo.z, a.mean);
      EXPECT_LE(a.mean, 1.0 + 1e-3);
      EXPECT_LE(a.maxWeight, 1.0 + 1e-4);  // VNDF weight G1(wi)-like: never above 1 (F = 1)
      if (alpha <= 0.05f && theta < 1.3f) {
        EXPECT_GT(a.mean, 0.985) << theta;
      }
      // At normal incidence the visible normals tilted past 45 degrees, a share
      // alpha^2 / (1 + alpha^2) of them, reflect below the horizon: a lower bound on the loss.
      if (theta == 0.0f) {
        EXPECT_LT(a.mean, 1.0 - alpha * alpha / (1 + alpha * alpha) + 1e-3);
      }
      if (alpha >= 0.2f) {
        const test::AlbedoEstimate uniform = test::uniformHemisphereAlbedo(lobe, wo, 32, 400000);
        EXPECT_NEAR(a.mean, uniform.mean, 5 * uniform.standardError + 3e-3) << alpha << " " << theta;
      }
    }
  }
}

TEST(BsdfRough, DielectricFurnaceIsAtMostOneInImportanceMode) {
  for (float alpha : kAlphas) {
    for (float eta : kEtas) {
      const Lobe lobe = roughDielectric(alpha, uniform(eta));
      for (float theta : {0.0f, 0.8f, 1.45f, 2.0f, 3.0f}) {
        const Vec3 wo = fromAngles(theta, 0.3f);
        const Albedo a = albedo(lobe, wo, TransportMode::Importance, 0, 100000, 41);
        std::printf("  rough dielectric alpha %.2f eta %.1f cos_o %+.3f: albedo %.4f\n", alpha, eta, wo.z, a.mean);
        EXPECT_LE(a.mean, 1.0 + 5e-3);
        if (alpha <= 0.05f && theta != 1.45f) {
          EXPECT_GT(a.mean, 0.97) << eta << " " << theta;
        }
      }
    }
  }
}

// ---------------------------------------------------------------- Dispersion

TEST(BsdfRough, DispersiveTransmissionCarriesEveryLanesOwnValue) {
  const Spectrum etas = lanes({1.5f, 1.55f, 1.6f, 1.65f});
  const Lobe lobe = roughDielectric(0.2f, etas, true);
  sampling::Pcg32 rng(51, 1);
  int transmissions = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 wo = fromAngles(0.6f, 0.4f);
    const auto s = lobeSample(lobe, wo, rng.nextFloat(), Vec2(rng.nextFloat(), rng.nextFloat()), TransportMode::Radiance);
    if (!s) continue;
    EXPECT_TRUE(s->dispersive);
    EXPECT_FALSE(s->specular);
    if (!s->transmission) continue;
    ++transmissions;
    for (int k = 0; k < 4; ++k) {
      const float own = lobeEval(roughDielectric(0.2f, uniform(etas[k])), wo, s->wi, TransportMode::Radiance)[0];
      EXPECT_NEAR(s->f[k], own, 1e-5f * std::max(1.0f, own));
    }
    EXPECT_GT(s->f[1] + s->f[2] + s->f[3], 0.0f);
    EXPECT_FLOAT_EQ(s->etaScale, 1.5f);
  }
  EXPECT_GT(transmissions, 1500);
  const auto constant = lobeSample(roughDielectric(0.2f, uniform(1.5f)), fromAngles(0.6f, 0.4f), 0.9f, Vec2(0.3f),
                                   TransportMode::Radiance);
  ASSERT_TRUE(constant);
  EXPECT_FALSE(constant->dispersive);
}

// ---------------------------------------------------------------- Thin dielectric

TEST(BsdfRough, ThinDielectricConservesEnergyAndPassesStraightThrough) {
  Lobe lobe;
  lobe.kind = LobeKind::ThinDielectric;
  lobe.weight = lanes({1, 1, 1, 1});
  lobe.a = lanes({1.5f, 1.52f, 2.4f, 1.1f});
  lobe.b = uniform(1.0f);
  lobe.etaVaries = true;
  sampling::Pcg32 rng(61, 1);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 wo = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
    if (std::fabs(wo.z) < 1e-3f) continue;
    const auto r = lobeSample(lobe, wo, 0.0f, Vec2(0.5f), TransportMode::Radiance);
    const auto t = lobeSample(lobe, wo, 0x1.fffffep-1f, Vec2(0.5f), TransportMode::Radiance);
    ASSERT_TRUE(r && t);
    EXPECT_TRUE(r->specular && t->specular && !r->dispersive && !t->dispersive);
    EXPECT_EQ(r->wi, Vec3(-wo.x, -wo.y, wo.z));
    EXPECT_EQ(t->wi, -wo);
    EXPECT_TRUE(t->transmission);
    EXPECT_EQ(t->etaScale, 1.0f);
    EXPECT_NEAR(r->pdfW + t->pdfW, 1.0f, 1e-6f);
    for (int k = 0; k < 4; ++k) {
      const float rk = r->f[k] * std::fabs(wo.z), tk = t->f[k] * std::fabs(wo.z);
      EXPECT_NEAR(rk + tk, 1.0f, 1e-5f);
      const float single = fresnelDielectric(std::fabs(wo.z), lobe.a[k]);
      EXPECT_NEAR(rk, single + (1 - single) * (1 - single) * single / (1 - single * single), 1e-5f);
      EXPECT_GE(rk, single - 1e-7f);  // the slab reflects more than one interface
    }
  }
}

// ---------------------------------------------------------------- Rough thin dielectric

Lobe roughThin(float alpha, const Spectrum& eta, bool etaVaries = false) {
  Lobe l;
  l.kind = LobeKind::RoughThinDielectric;
  l.weight = uniform(1.0f);
  l.a = eta;
  l.b = uniform(1.0f);
  l.etaVaries = etaVaries;
  l.roughness = alpha;
  return l;
}

TEST(BsdfRough, RoughThinDielectricSamplesFollowPdf) {
  uint64_t seed = 500;
  for (float alpha : kAlphas) {
    const Lobe lobe = roughThin(alpha, uniform(1.5f));
    for (const Vec3& wo : {fromAngles(0.3f, 0.5f), fromAngles(1.3f, 2.0f), fromAngles(2.5f, 1.0f)}) {
      const auto r = test::chiSquareLobe(lobe, wo, conductorChiOptions(seed++, alpha));
      EXPECT_TRUE(r.passed) << "alpha " << alpha << " wo.z " << wo.z << ": " << r.detail;
    }
  }
}

// Every facet splits what it reflects into R' (mirror) and 1 - R' (the mirror image through the
// wall), so the wall's albedo is the GGX reflection's with F = 1, whatever the IOR: the same
// sample weights as a conductor of reflectance 1, sample by sample. An independent quadrature
// of eval over the whole sphere agrees, and the transmitted share is 1 - R' of the facets seen.
TEST(BsdfRough, RoughThinDielectricSplitsTheGgxAlbedoBetweenMirrorAndWall) {
  for (float alpha : kAlphas) {
    for (float eta : {1.1f, 1.5f, 2.4f}) {
      const Lobe lobe = roughThin(alpha, uniform(eta));
      const Lobe mirror = roughConductor(alpha, uniform(0.2f), uniform(1e4f));  // F = 1 to 1e-7
      for (float theta : {0.0f, 0.9f, 1.4f, 2.6f}) {
        const Vec3 wo = fromAngles(theta, 0.3f);
        sampling::Pcg32 rng(77, 3);
        double thin = 0, conductor = 0, transmitted = 0;
        const int n = 40000;
        for (int i = 0; i < n; ++i) {
          const float uc = rng.nextFloat();
          const Vec2 u2(rng.nextFloat(), rng.nextFloat());
          const auto s = lobeSample(lobe, wo, uc, u2, TransportMode::Radiance);
          const auto c = lobeSample(mirror, wo, uc, u2, TransportMode::Radiance);
          ASSERT_EQ(bool(s), bool(c));
          if (!s) continue;
          ASSERT_FALSE(s->specular);
          ASSERT_EQ(s->transmission, wo.z * s->wi.z < 0.0f);
          ASSERT_EQ(s->etaScale, 1.0f);
          const Vec3 mirrored = s->transmission ? Vec3(s->wi.x, s->wi.y, -s->wi.z) : s->wi;
          ASSERT_NEAR(glm::length(mirrored - c->wi), 0.0f, 1e-5f);
          const double w = s->f[0] * std::fabs(s->wi.z) / s->pdfW;
          const double wc = c->f[0] * std::fabs(c->wi.z) / c->pdfW;
          ASSERT_NEAR(w, wc, 2e-4 * std::max(1.0, wc));
          ASSERT_NEAR(s->f[0], lobeEval(lobe, wo, s->wi, TransportMode::Radiance)[0], 1e-4f * std::max(1.0f, s->f[0]));
          thin += w;
          conductor += wc;
          transmitted += s->transmission;
        }
        thin /= n;
        conductor /= n;
        EXPECT_LE(thin, 1.0 + 1e-3);
        EXPECT_NEAR(thin, conductor, 1e-3 * conductor) << alpha << " " << eta << " " << theta;
        // The transmitted share: near normal incidence and small alpha, 1 - R'(cos_o).
        if (alpha <= 0.05f && theta == 0.0f) {
          const double smooth = 1.0 - thinDielectricReflectance(1.0f, eta);
          EXPECT_NEAR(transmitted / n, smooth, 4 * std::sqrt(smooth * (1 - smooth) / n) + 2e-3) << eta;
        }
        // Independent: eval integrated over the sphere by uniform sampling.
        sampling::Pcg32 q(78, 1);
        double sum = 0, sumSquares = 0;
        const int m = 400000;
        if (alpha < 0.2f) continue;  // peaked lobes: uniform quadrature too noisy
        for (int i = 0; i < m; ++i) {
          const Vec3 wi = sampleUniformSphere(Vec2(q.nextFloat(), q.nextFloat()));
          const double v = lobeEval(lobe, wo, wi, TransportMode::Radiance)[0] * std::fabs(wi.z) * 4.0 * M_PI;
          sum += v;
          sumSquares += v * v;
        }
        const double mean = sum / m, standardError = std::sqrt((sumSquares / m - mean * mean) / m);
        EXPECT_NEAR(thin, mean, 5 * standardError + 3e-3) << alpha << " " << eta << " " << theta;
      }
    }
  }
}

TEST(BsdfRough, RoughThinDielectricIsReciprocalAndTheSameInBothTransportModes) {
  sampling::Pcg32 rng(79, 1);
  for (float alpha : kAlphas) {
    const Lobe lobe = roughThin(alpha, lanes({1.5f, 1.3f, 2.0f, 1.05f}), true);
    int transmissions = 0;
    for (int i = 0; i < 20000; ++i) {
      const Vec3 a = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
      const Vec3 b = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
      const Spectrum fab = lobeEval(lobe, a, b, TransportMode::Radiance);
      const Spectrum fba = lobeEval(lobe, b, a, TransportMode::Radiance);
      const Spectrum iab = lobeEval(lobe, a, b, TransportMode::Importance);
      for (int k = 0; k < 4; ++k) {
        ASSERT_NEAR(fab[k], fba[k], 1e-4f * std::max(1.0f, fab[k]));
        ASSERT_EQ(fab[k], iab[k]);  // the wall leaves into the medium it came from: no 1/eta^2
      }
      transmissions += !sameHemisphere(a, b) && fab[0] > 0.0f;
    }
    EXPECT_GT(transmissions, 1000) << alpha;
  }
}

// A varying IOR changes each lane's R', not the direction: every lane carries the value of a
// wall of its own IOR, the density is the hero's, and the Bsdf reports no dispersive density
// (spectral MIS and the terminate mode must leave such a wall's lanes alone).
TEST(BsdfRough, RoughThinDielectricLanesCarryTheirOwnFresnelWithoutDispersion) {
  const float etas[4] = {1.5f, 1.3f, 2.0f, 1.05f};
  const Lobe lobe = roughThin(0.3f, lanes({etas[0], etas[1], etas[2], etas[3]}), true);
  sampling::Pcg32 rng(80, 1);
  int transmissions = 0, reflections = 0;
  for (int i = 0; i < 4000; ++i) {
    const Vec3 wo = fromAngles(0.7f, 0.2f);
    const auto s = lobeSample(lobe, wo, rng.nextFloat(), Vec2(rng.nextFloat(), rng.nextFloat()), TransportMode::Radiance);
    if (!s) continue;
    EXPECT_FALSE(s->dispersive);
    EXPECT_FLOAT_EQ(s->pdfW, lobePdf(roughThin(0.3f, uniform(etas[0])), wo, s->wi, TransportMode::Radiance));
    for (int k = 0; k < 4; ++k) {
      const float own = lobeEval(roughThin(0.3f, uniform(etas[k])), wo, s->wi, TransportMode::Radiance)[0];
      EXPECT_NEAR(s->f[k], own, 1e-5f * std::max(1.0f, own));
    }
    (s->transmission ? transmissions : reflections)++;
  }
  EXPECT_GT(transmissions, 2000);
  EXPECT_GT(reflections, 100);
  Bsdf bsdf;
  ASSERT_TRUE(bsdf.add(lobe));
  EXPECT_FALSE(bsdf.hasDispersiveDensity());
}

// A thin wall's tint (glTF's base colour on a thin-walled transmissive material) multiplies the
// transmission only: the reflection stays the untinted wall's R' (the slab's, not a single
// interface's), smooth or rough, and the densities do not change.
TEST(BsdfRough, ThinWallsTintTheirTransmissionOnly) {
  const Spectrum tint = lanes({0.8f, 0.25f, 0.0f, 1.0f});
  for (float alpha : {0.0f, 0.3f}) {
    Lobe clear = roughThin(alpha, uniform(1.5f));
    if (alpha == 0.0f) clear.kind = LobeKind::ThinDielectric;
    Lobe tinted = clear;
    tinted.b = tint;
    sampling::Pcg32 rng(82, 1);
    int transmissions = 0, reflections = 0;
    for (int i = 0; i < 4000; ++i) {
      const Vec3 wo = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
      if (std::fabs(wo.z) < 0.05f) continue;
      const float uc = rng.nextFloat();
      const Vec2 u2(rng.nextFloat(), rng.nextFloat());
      const auto a = lobeSample(clear, wo, uc, u2, TransportMode::Radiance);
      const auto b = lobeSample(tinted, wo, uc, u2, TransportMode::Radiance);
      ASSERT_EQ(bool(a), bool(b));
      if (!a) continue;
      ASSERT_EQ(a->wi, b->wi);
      ASSERT_EQ(a->pdfW, b->pdfW);
      ASSERT_EQ(a->transmission, b->transmission);
      const Spectrum evalClear = lobeEval(clear, wo, a->wi, TransportMode::Radiance);
      const Spectrum evalTinted = lobeEval(tinted, wo, a->wi, TransportMode::Radiance);
      for (int k = 0; k < 4; ++k) {
        const float expected = a->transmission ? a->f[k] * tint[k] : a->f[k];
        ASSERT_FLOAT_EQ(b->f[k], expected) << alpha << " lane " << k;
        ASSERT_FLOAT_EQ(evalTinted[k], a->transmission ? evalClear[k] * tint[k] : evalClear[k]);
      }
      (a->transmission ? transmissions : reflections)++;
    }
    EXPECT_GT(transmissions, 1000) << alpha;
    EXPECT_GT(reflections, 100) << alpha;
    // Head-on, the smooth wall reflects the slab's R' = 2R / (1 + R) = 0.0769 untinted.
    if (alpha == 0.0f) {
      const auto r = lobeSample(tinted, Vec3(0, 0, 1), 0.0f, Vec2(0.5f), TransportMode::Radiance);
      ASSERT_TRUE(r && !r->transmission);
      EXPECT_NEAR(r->f[2], 2.0f * 0.04f / 1.04f, 1e-6f);
    }
  }
}

// As alpha goes to 0 the rough wall becomes the smooth slab: transmission straight through.
// GGX's tail is long (a share alpha^2 / (alpha^2 + t^2) of the facets lean beyond tan = t):
// at alpha 2e-3 about 1 % of the samples leave the 0.999 cone.
TEST(BsdfRough, RoughThinDielectricTendsToTheSmoothSlab) {
  const Lobe lobe = roughThin(2e-3f, uniform(1.5f));
  sampling::Pcg32 rng(81, 1);
  int samples = 0, near = 0, transmissions = 0;
  for (int i = 0; i < 4000; ++i) {
    const Vec3 wo = sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat()));
    if (std::fabs(wo.z) < 0.1f) continue;
    const auto s = lobeSample(lobe, wo, rng.nextFloat(), Vec2(rng.nextFloat(), rng.nextFloat()), TransportMode::Radiance);
    if (!s) continue;
    const Vec3 smooth = s->transmission ? -wo : Vec3(-wo.x, -wo.y, wo.z);
    ++samples;
    near += dot3(s->wi, smooth) > 0.999f;
    transmissions += s->transmission;
  }
  EXPECT_GT(samples, 3000);
  EXPECT_GT(near, 0.97 * samples);
  EXPECT_GT(transmissions, 0.7 * samples);
}

// ---------------------------------------------------------------- Robustness

TEST(BsdfRough, NoNaNForDegenerateInputs) {
  std::vector<Lobe> lobes;
  for (float alpha : {0.0f, 1e-4f, 1e-3f, 0.5f, 1.0f, 50.0f, NAN, -1.0f}) {
    lobes.push_back(roughConductor(alpha, lanes({0.2f, 0, 1e-4f, 3}), lanes({3, 0, 1e4f, 0})));
    lobes.push_back(roughDielectric(alpha, lanes({1.5f, 1.5f, 1.5f, 1.5f})));
    lobes.push_back(roughDielectric(alpha, lanes({2.4f, 1.0f, 0.0f, -1.0f}), true));
    lobes.push_back(roughDielectric(alpha, lanes({1.0f, 1.0f, 1.0f, 1.0f})));
    lobes.push_back(roughDielectric(alpha, lanes({1.00001f, 1e4f, 1e-4f, NAN}), true));
    Lobe thin;
    thin.kind = LobeKind::ThinDielectric;
    thin.weight = uniform(1);
    thin.a = lanes({1.5f, 0.0f, 1.0f, 1e4f});
    thin.b = lanes({1.0f, 0.5f, 0.0f, 1.0f});
    thin.etaVaries = true;
    lobes.push_back(thin);
    thin.kind = LobeKind::RoughThinDielectric;
    thin.roughness = alpha;
    lobes.push_back(thin);
  }
  const float tiny = 1e-8f;
  std::vector<Vec3> wos = {Vec3(1, 0, 0), Vec3(0, 0, 1), Vec3(0, 0, -1), glm::normalize(Vec3(1, 0, tiny)),
                           glm::normalize(Vec3(1, 0, -tiny)), glm::normalize(Vec3(1, 0, 1e-5f)), Vec3(0, 0, 0)};
  sampling::Pcg32 rng(71, 9);
  for (int i = 0; i < 300; ++i) wos.push_back(sampleUniformSphere(Vec2(rng.nextFloat(), rng.nextFloat())));
  for (const Vec3& wo : wos)
    for (TransportMode mode : {TransportMode::Radiance, TransportMode::Importance})
      for (int j = 0; j < 6; ++j) {
        const float uc = j == 0 ? 0.0f : j == 1 ? 0x1.fffffep-1f : rng.nextFloat();
        const Vec2 u2 = j < 2 ? Vec2(float(j), 1.0f - float(j)) * 0x1.fffffep-1f : Vec2(rng.nextFloat(), rng.nextFloat());
        for (const Lobe& l : lobes) {
          const auto s = lobeSample(l, wo, uc, u2, mode);
          if (s) {
            ASSERT_FALSE(s->f.hasNaNOrInf());
            ASSERT_TRUE(std::isfinite(s->pdfW) && s->pdfW > 0.0f);
            ASSERT_NEAR(glm::length(s->wi), 1.0f, 1e-3f);
            ASSERT_TRUE(std::isfinite(s->etaScale) && s->etaScale > 0.0f);
          }
          for (const Vec3& wi : {sampleUniformSphere(u2), -wo, Vec3(-wo.x, -wo.y, wo.z), Vec3(1, 0, 0)}) {
            ASSERT_FALSE(lobeEval(l, wo, wi, mode).hasNaNOrInf());
            for (int lane = 0; lane < 4; ++lane) {
              const float p = lobePdfForLane(l, wo, wi, mode, lane);
              ASSERT_TRUE(std::isfinite(p) && p >= 0.0f);
            }
          }
        }
      }
}

}  // namespace
}  // namespace tex::render
