// The glossy model (docs/glossy-model.md): kernel normalisation, exact sampling (chi-square
// with bins aligned to the lobe, so n = 1000 and 4000 have power), energy conservation
// (furnace by Monte Carlo and by quadrature), reciprocity, the dielectric's R + T <= 1 and
// generalized reciprocity, per-lane pdfs for spectral MIS, the energy-compensation lobe and its
// table, and robustness.
#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <vector>

#include "renderer/bsdf/bsdf.h"
#include "renderer/bsdf/glossy_albedo.h"
#include "renderer/bsdf/glossy_kernel.h"
#include "renderer/bsdf/glossy_lobe.h"
#include "renderer/bsdf/glossy_mass_table.h"
#include "renderer/sampling/pcg.h"
#include "tests/renderer/chi_square.h"

namespace tex::render {
namespace {

constexpr double kDeg = M_PI / 180.0;
const float kExponents[] = {10.0f, 100.0f, 1000.0f, 4000.0f};

Lobe glossyReflection(float n, float weight = 1.0f) {
  Lobe l;
  l.kind = LobeKind::GlossyReflection;
  l.exponent = n;
  for (int i = 0; i < 4; ++i) l.weight.v[i] = weight;
  return l;
}

Lobe glossyDielectric(float n, float eta) {
  Lobe l;
  l.kind = LobeKind::GlossyDielectric;
  l.exponent = n;
  for (int i = 0; i < 4; ++i) {
    l.weight.v[i] = 1.0f;
    l.a.v[i] = eta;
  }
  return l;
}

// IOR falling linearly over the lanes, as in the thesis's Table 1 scene (1.35 .. 1.20).
Lobe dispersiveDielectric(float n) {
  Lobe l = glossyDielectric(n, 1.0f);
  for (int i = 0; i < 4; ++i) l.a.v[i] = 1.35f - 0.05f * float(i);
  l.etaVaries = true;
  return l;
}

Vec3 fromAngles(double theta, double phi) {
  return Vec3(float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)), float(std::cos(theta)));
}

// ---- kernel

// kernelMassInDisk against a midpoint grid over the kernel's support (which also checks that
// kernelDensity integrates to 1 over the plane).
TEST(GlossyKernel, MassInDiskMatchesGridIntegration) {
  struct Case {
    double n, d, R;
  } cases[] = {{10, 0, 1}, {10, 0.5, 1}, {10, 0.95, 1}, {100, 0.9, 1},  {1000, 0.99, 1},
               {4000, 0.995, 1}, {1000, 1.3, 1.35}, {100, 1.4, 1.35}, {1000, 0.0, 1.35}, {10, 1.2, 1.0}};
  for (const Case& c : cases) {
    const double half = std::min(1.0, 9.0 / std::sqrt(c.n));  // the kernel beyond 9 sigma is < 1e-17
    const int cells = 1500;
    const double h = 2 * half / cells;
    double inside = 0, total = 0;
    for (int i = 0; i < cells; ++i)
      for (int j = 0; j < cells; ++j) {
        const double x = -half + (i + 0.5) * h, y = -half + (j + 0.5) * h;
        const double p = glossy::kernelDensity(c.n, x * x + y * y) * h * h;
        total += p;
        const double px = c.d + x;
        if (px * px + y * y < c.R * c.R) inside += p;
      }
    EXPECT_NEAR(total, 1.0, 2e-3) << "n = " << c.n;
    EXPECT_NEAR(glossy::kernelMassInDisk(c.n, c.d, c.R), inside, 2e-3) << "n = " << c.n << " d = " << c.d << " R = " << c.R;
  }
}

// The table bounds the quadrature from above, by at most its margin plus the interpolation
// error (each measured < its margin by bench/glossy_albedo masscheck), at random points of its
// domain: relative error < 1e-3 wherever M >= 0.25 (the normalisations the lobes use are
// >= ~0.3: one of the pair's kernels is centred inside its disk).
TEST(GlossyMassTable, BoundsTheQuadratureFromAboveWithinItsMargin) {
  sampling::Pcg32 rng(31, 7);
  double worstRelative = 0.0;
  for (int k = 0; k < 20000; ++k) {
    const double n = std::exp2(std::log2(1.0 + glossy::kMassTableMinExponent) + (17.0 - 3.0) * rng.nextFloat()) - 1.0;
    const double R = glossy::kMassTableMinRadius *
                     std::pow(glossy::kMassTableMaxRadius / glossy::kMassTableMinRadius, double(rng.nextFloat()));
    const double reach = glossy::sampleKernelRadius(n, 1e-16);
    const double d = std::max(0.0, R - reach) + (R + reach - std::max(0.0, R - reach)) * rng.nextFloat();
    const double exact = glossy::kernelMassInDisk(n, d, R), table = glossy::tabulatedMassInDisk(n, d, R);
    ASSERT_GE(table, exact) << "n = " << n << " d = " << d << " R = " << R;
    ASSERT_LE(table, exact + 2.0 * glossy::massTableMargin(n)) << "n = " << n << " d = " << d << " R = " << R;
    if (exact >= 0.25) worstRelative = std::max(worstRelative, (table - exact) / exact);
  }
  EXPECT_LT(worstRelative, 1e-3);
  EXPECT_GT(worstRelative, 0.0);  // the margin is there
}

// Where the kernel is clear of the rim the table is exact (1 inside, 0 outside, as the
// quadrature), so a lobe clear of the horizon loses nothing; outside the domain it is the
// quadrature itself.
TEST(GlossyMassTable, ExactBeyondTheRimZoneAndOutsideTheDomain) {
  for (double n : {10.0, 1000.0, 4000.0})
    for (double R : {0.7, 1.0, 1.35, 2.4}) {
      const double reach = glossy::sampleKernelRadius(n, 1e-16);
      for (double d : {R - reach - 1e-9, 0.5 * (R - reach)})
        if (d >= 0.0) {
          EXPECT_EQ(glossy::tabulatedMassInDisk(n, d, R), 1.0) << "n = " << n << " R = " << R;
        }
      EXPECT_EQ(glossy::tabulatedMassInDisk(n, R + reach + 1e-9, R), 0.0);
      EXPECT_EQ(glossy::kernelMassInDisk(n, R + reach + 1e-9, R), 0.0);
      if (R - reach - 1e-9 >= 0.0) {
        EXPECT_GE(glossy::kernelMassInDisk(n, R - reach - 1e-9, R), 1.0 - 1e-15);
      }
    }
  struct Outside {
    double n, d, R;
  } outside[] = {{2.0, 0.9, 1.0}, {1000.0, 0.3, 0.4}, {100.0, 3.4, 3.5}, {3e6, 0.999, 1.0}};
  for (const Outside& o : outside) {
    EXPECT_FALSE(glossy::massTableCovers(o.n, o.R));
    EXPECT_EQ(glossy::tabulatedMassInDisk(o.n, o.d, o.R), glossy::kernelMassInDisk(o.n, o.d, o.R));
  }
  EXPECT_TRUE(glossy::massTableCovers(1000.0, 1.35));
}

// ---- sampling: chi-square in the lobe's own plane

// Bins the sampled directions in the plane of the kernel's variable q around the ideal point
// (q = etaO wo_t + etaI wi_t, reflection: etaO = etaI = 1), over a square of half-width
// 6 / sqrt(n) (clipped to the kernel's support): the lobe fills the histogram whatever n is.
// The expected counts come from the lobe's pdf() through |cos| dw = dA (projected disk).
test::ChiSquareResult chiSquareInLobePlane(const Lobe& lobe, const Vec3& wo, bool transmission, double etaO,
                                          double etaI, float ucLo, float ucHi, double probability, int testCount) {
  const double half = std::min(1.0, 6.0 / std::sqrt(double(lobe.exponent)));
  const double cx = etaO * wo.x, cy = etaO * wo.y;  // q = c + etaI wi_t
  const float zSign = (wo.z > 0) != transmission ? 1.0f : -1.0f;
  auto sampler = [&](Vec2 u, float u3) -> std::optional<Vec2> {
    auto s = lobeSample(lobe, wo, ucLo + (ucHi - ucLo) * u3, u, TransportMode::Radiance);
    if (!s) return std::nullopt;
    if (s->transmission != transmission) return Vec2(-1.0f);  // wrong event: counted as outside
    const double qx = cx + etaI * s->wi.x, qy = cy + etaI * s->wi.y;
    return Vec2(float((qx / half + 1) * 0.5), float((qy / half + 1) * 0.5));
  };
  auto pdf = [&](Vec2 p) -> double {
    const double qx = (2.0 * p.x - 1.0) * half, qy = (2.0 * p.y - 1.0) * half;
    const double x = (qx - cx) / etaI, y = (qy - cy) / etaI;
    const double t2 = x * x + y * y;
    if (!(t2 < 1.0)) return 1e-9;
    const Vec3 wi(float(x), float(y), float(zSign * std::sqrt(1.0 - t2)));
    if (std::fabs(wi.z) < 1e-6f) return 1e-9;
    // density in q = pdfW / |cos| / etaI^2; in p: times (2 half)^2. Conditional on the event.
    // + 1e-9: cells that the disk's rim cuts with no quadrature point inside get a tiny
    // expected count and are pooled (samples there still count) instead of failing outright.
    return 1e-9 + lobePdf(lobe, wo, wi, TransportMode::Radiance) / std::fabs(double(wi.z)) / (etaI * etaI) * 4 * half * half /
           probability;
  };
  // 12 x 12 quadrature points per cell: the density jumps at the disk's rim (the horizon).
  return test::chiSquarePoints(sampler, pdf, 48, 1000000, 12, 0.01, testCount);
}

void reflectionChiSquare(float n, std::initializer_list<double> thetas) {
  for (double t : thetas) {
    const Lobe lobe = glossyReflection(n);
    const Vec3 wo = fromAngles(t * kDeg, 0.7);
    const auto r = chiSquareInLobePlane(lobe, wo, false, 1.0, 1.0, 0.0f, 1.0f, 1.0, 16 + 12);
    EXPECT_TRUE(r.passed) << "n = " << n << " theta_o = " << t << ": " << r.detail;
  }
}
// Split by angle to keep each test short (1M samples per angle; the Sidak count covers all).
TEST(GlossyChiSquare, ReflectionN10Near) { reflectionChiSquare(10.0f, {0.0, 30.0}); }
TEST(GlossyChiSquare, ReflectionN10Grazing) { reflectionChiSquare(10.0f, {60.0, 85.0}); }
TEST(GlossyChiSquare, ReflectionN100Near) { reflectionChiSquare(100.0f, {0.0, 30.0}); }
TEST(GlossyChiSquare, ReflectionN100Grazing) { reflectionChiSquare(100.0f, {60.0, 85.0}); }
TEST(GlossyChiSquare, ReflectionN1000) { reflectionChiSquare(1000.0f, {0.0, 30.0, 60.0, 85.0}); }
TEST(GlossyChiSquare, ReflectionN4000) { reflectionChiSquare(4000.0f, {0.0, 30.0, 60.0, 85.0}); }

struct DielectricCase {
  float n;
  double theta;
  bool inside;
};
// One event of GlossyDielectric (eta 1.35) in its own momentum plane. The sampler picks the
// event after q (probability F^ or 1 - F^), so all of uc is used: samples of the other event
// and "no sample" land in the outside cell, and the pdf is the joint density of event and
// direction (probability 1).
void dielectricChiSquare(std::initializer_list<DielectricCase> cases, bool transmission) {
  for (const DielectricCase& c : cases) {
    const Lobe lobe = glossyDielectric(c.n, 1.35f);
    Vec3 wo = fromAngles(c.theta * kDeg, 2.0);
    if (c.inside) wo.z = -wo.z;
    const double etaO = c.inside ? 1.35 : 1.0, etaI = transmission ? (c.inside ? 1.0 : 1.35) : etaO;
    const auto r = chiSquareInLobePlane(lobe, wo, transmission, etaO, etaI, 0.0f, 1.0f, 1.0, 16 + 12);
    EXPECT_TRUE(r.passed) << "n = " << c.n << " theta_o = " << c.theta << (c.inside ? " inside" : "")
                          << (transmission ? " refraction" : " reflection") << ": " << r.detail;
  }
}
TEST(GlossyChiSquare, DielectricRefractionFromOutsideWide) { dielectricChiSquare({{10, 30, false}, {100, 60, false}}, true); }
TEST(GlossyChiSquare, DielectricRefractionFromOutsideNarrow) {
  dielectricChiSquare({{1000, 85, false}, {4000, 40, false}}, true);
}
TEST(GlossyChiSquare, DielectricRefractionFromInside) { dielectricChiSquare({{100, 20, true}, {1000, 40, true}}, true); }
// Reflection inside lives in the momentum plane too (q = eta (wo_t + wi_t)): narrower by eta
// in direction cosines than outside. 50 degrees is beyond the critical angle (47.8).
TEST(GlossyChiSquare, DielectricReflectionInside) {
  dielectricChiSquare({{10, 30, true}, {100, 45, true}, {1000, 50, true}, {4000, 70, true}}, false);
}
TEST(GlossyChiSquare, DielectricReflectionOutside) { dielectricChiSquare({{100, 30, false}, {1000, 80, false}}, false); }

// The whole sphere at once (reflection + refraction mixture) for a wide lobe, where the
// standard equal-solid-angle binning has power. Not at near-normal incidence: there the lobe
// sits on the pole, whose thin cells the helper's per-cell quadrature integrates poorly (at
// 15 degrees chi2 fell from 1937 to 1165 going from 6x6 to 12x12 points per cell); normal
// incidence is covered by the lobe-plane tests above.
void dielectricMixtureChiSquare(double t) {
  for (bool inside : {false, true}) {
      const Lobe lobe = glossyDielectric(10.0f, 1.5f);
      Vec3 wo = fromAngles(t * kDeg, 0.3);
      if (inside) wo.z = -wo.z;
      test::DirectionTestOptions o;
      o.testCount = 4;
      o.subdivisions = 12;  // a lobe at the pole varies fast across the thin polar cells
      const auto r = test::chiSquareDirections(
          [&](Vec2 u, float u3) -> std::optional<Vec3> {
            auto s = lobeSample(lobe, wo, u3, u, TransportMode::Radiance);
            return s ? std::optional<Vec3>(s->wi) : std::nullopt;
          },
          [&](const Vec3& wi) { return double(lobePdf(lobe, wo, wi, TransportMode::Radiance)); }, o);
      EXPECT_TRUE(r.passed) << "theta_o = " << t << (inside ? " inside" : "") << ": " << r.detail;
    }
}
TEST(GlossyChiSquare, DielectricMixtureOverTheSphere40) { dielectricMixtureChiSquare(40.0); }
TEST(GlossyChiSquare, DielectricMixtureOverTheSphere70) { dielectricMixtureChiSquare(70.0); }

// ---- energy

struct Estimate {
  double mean, stdError;
};
Estimate albedoMonteCarlo(const Lobe& lobe, const Vec3& wo, TransportMode mode, int lane = 0, int samples = 1000000) {
  sampling::Pcg32 rng(7, 11);
  double sum = 0, sum2 = 0;
  for (int i = 0; i < samples; ++i) {
    const float uc = rng.nextFloat();
    const Vec2 u(rng.nextFloat(), rng.nextFloat());
    auto s = lobeSample(lobe, wo, uc, u, mode);
    if (!s) continue;
    const double w = s->f.v[lane] * std::fabs(double(s->wi.z)) / s->pdfW;
    sum += w;
    sum2 += w * w;
  }
  const double mean = sum / samples;
  return {mean, std::sqrt(std::max(0.0, sum2 / samples - mean * mean) / samples)};
}

// With the compensation lobe: albedo <= 1 at every angle and within the table's margin of 1
// (the glossy lobe alone is exactly 1 where it is clear of the horizon), by quadrature and by
// Monte Carlo of the real sampler.
TEST(GlossyFurnace, ReflectionAlbedoIsOneAtEveryAngle) {
  const double thetas[] = {0, 30, 60, 75, 80, 85, 89};
  for (float n : kExponents)
    for (double t : thetas) {
      const double cosO = std::cos(t * kDeg), sinO = std::sin(t * kDeg);
      const double quad = glossyReflectionAlbedo(n, float(cosO));
      EXPECT_LE(quad, 1.0 + 1e-6) << "n = " << n << " theta = " << t;
      EXPECT_GE(quad, 1.0 - 1.5 * glossy::kTableMargin) << "n = " << n << " theta = " << t;
      if (sinO + 6.0 / std::sqrt(n + 4.0) < 1.0) {
        EXPECT_NEAR(glossy::reflectionAlbedoQuadrature(n, cosO), 1.0, 1e-6) << "n = " << n << " theta = " << t;
      }
      const Estimate mc = albedoMonteCarlo(glossyReflection(n), fromAngles(t * kDeg, 1.1), TransportMode::Radiance, 0,
                                           50000);
      EXPECT_NEAR(mc.mean, quad, 5 * mc.stdError + 1e-4) << "n = " << n << " theta = " << t;
    }
}

// The glossy lobe alone (what the compensation restores): the quadrature agrees with Monte
// Carlo of the glossy lobe's own sampler and value (weight p / max(M(wo), M(wi)) per
// kernel sample, 0 for samples below the horizon).
TEST(GlossyFurnace, GlossyLobeAloneQuadratureMatchesMonteCarlo) {
  for (float n : kExponents)
    for (double t : {60.0, 80.0, 89.0}) {
      const Vec3 wo = fromAngles(t * kDeg, 0.3);
      const double d = std::hypot(double(wo.x), double(wo.y));
      const double mo = glossy::kernelMassInDisk(n, d, 1.0);
      sampling::Pcg32 rng(21, 5);
      const int samples = 20000;
      double sum = 0, sum2 = 0;
      for (int k = 0; k < samples; ++k) {
        const double r = glossy::sampleKernelRadius(n, 1.0 - rng.nextFloat()), phi = 2 * M_PI * rng.nextFloat();
        const double x = -wo.x + r * std::cos(phi), y = -wo.y + r * std::sin(phi);
        const double x2 = x * x + y * y;
        const double w = x2 < 1.0 ? 1.0 / std::max(mo, glossy::kernelMassInDisk(n, std::sqrt(x2), 1.0)) : 0.0;
        sum += w;
        sum2 += w * w;
      }
      const double mean = sum / samples, se = std::sqrt((sum2 / samples - mean * mean) / samples);
      EXPECT_NEAR(glossy::reflectionAlbedoQuadrature(n, wo.z), mean, 5 * se + 1e-5) << "n = " << n << " theta = " << t;
    }
}

// The table bounds the glossy lobe's albedo from above (so the compensated albedo is <= 1) and
// is tight (within the margin plus the bilinear error), at points off the table's grid.
TEST(GlossyCompensation, TableBoundsTheAlbedoFromAboveAndTightly) {
  sampling::Pcg32 rng(13, 1);
  for (int k = 0; k < 120; ++k) {
    const double n = std::exp2(14.0 * rng.nextFloat()) - 1.0;  // 0 .. 16383
    const double c = rng.nextFloat();
    const double e = glossy::reflectionAlbedoQuadrature(n, c), tab = glossy::tabulatedAlbedo(n, c);
    EXPECT_GE(tab, e) << "n = " << n << " cos = " << c;
    EXPECT_LE(tab, e + 2.0 * glossy::kTableMargin) << "n = " << n << " cos = " << c;
  }
  EXPECT_GT(glossy::kTableMargin, 0.0);
  EXPECT_LT(glossy::kTableMargin, 5e-3);
}

// int f_ms(wo, wi) cos_i dw_i = 1 - E_table(wo) (E_avg is the exact average of the
// interpolant), f_ms is symmetric, and it vanishes where the glossy lobe loses nothing.
TEST(GlossyCompensation, LobeAlbedoIsExactlyTheTablesLoss) {
  for (double n : {0.0, 10.0, 100.0, 1000.0, 4000.0, 1e5})
    for (double cosO : {0.0, 0.05, 0.2, 0.5, 1.0}) {
      const int cells = 20000;
      double sum = 0.0;
      for (int k = 0; k < cells; ++k) {
        const double cosI = (k + 0.5) / cells;
        sum += glossy::compensationValue(n, cosO, cosI) * cosI * 2 * M_PI / cells;
      }
      EXPECT_NEAR(sum, 1.0 - glossy::tabulatedAlbedo(n, cosO), 1e-6) << "n = " << n << " cos = " << cosO;
      EXPECT_DOUBLE_EQ(glossy::compensationValue(n, cosO, 0.3), glossy::compensationValue(n, 0.3, cosO));
    }
  EXPECT_GT(glossy::compensationValue(100.0, 0.05, 0.05), 0.0);
  EXPECT_EQ(glossy::compensationValue(100.0, 1.0, 0.05), 0.0);  // normal incidence loses nothing
  EXPECT_EQ(glossy::compensationValue(1e7, 0.05, 0.05), 0.0);    // beyond the table: none
}

// Sampling with the compensation lobe over the whole hemisphere (the cosine part is spread
// out, the lobe-plane tests see it only in their "outside" cell).
TEST(GlossyChiSquare, ReflectionWithCompensationOverTheHemisphere) {
  for (double t : {75.0, 88.0}) {
    const Lobe lobe = glossyReflection(10.0f);
    const Vec3 wo = fromAngles(t * kDeg, 0.3);
    test::DirectionTestOptions o;
    o.testCount = 2;
    const auto r = test::chiSquareDirections(
        [&](Vec2 u, float u3) -> std::optional<Vec3> {
          auto s = lobeSample(lobe, wo, u3, u, TransportMode::Radiance);
          return s ? std::optional<Vec3>(s->wi) : std::nullopt;
        },
        [&](const Vec3& wi) { return double(lobePdf(lobe, wo, wi, TransportMode::Radiance)); }, o);
    EXPECT_TRUE(r.passed) << "theta_o = " << t << ": " << r.detail;
  }
}

// Per sample the weight f |cos| / pdf is 1 / max(M(wo), M(wi)) * M(wo)-free: exactly the
// reflectance where the lobe is clear of the horizon (exact importance sampling).
TEST(GlossyFurnace, SampleWeightIsExactlyTheReflectanceAwayFromGrazing) {
  const Lobe lobe = glossyReflection(1000.0f, 0.8f);
  const Vec3 wo = fromAngles(40 * kDeg, 0.2);
  sampling::Pcg32 rng(3, 5);
  for (int i = 0; i < 10000; ++i) {
    auto s = lobeSample(lobe, wo, rng.nextFloat(), Vec2(rng.nextFloat(), rng.nextFloat()), TransportMode::Radiance);
    ASSERT_TRUE(s.has_value());
    EXPECT_NEAR(s->f.v[0] * std::fabs(s->wi.z) / s->pdfW, 0.8f, 1e-5f);
  }
}

TEST(GlossyFurnace, DielectricReflectionPlusRefractionAtMostOne) {
  const double thetas[] = {0, 30, 45, 60, 80, 89};
  for (float n : kExponents)
    for (double t : thetas)
      for (bool inside : {false, true}) {
        const Lobe lobe = glossyDielectric(n, 1.35f);
        Vec3 wo = fromAngles(t * kDeg, 0.4);
        if (inside) wo.z = -wo.z;
        const Estimate e = albedoMonteCarlo(lobe, wo, TransportMode::Importance, 0, 50000);
        EXPECT_LE(e.mean, 1.0 + 5 * e.stdError + 1e-6) << "n = " << n << " theta = " << t << (inside ? " inside" : "");
        // Where the kernel (6 sigma) is clear of both rims (momentum etaO sin(theta_o) away from
        // 1 and 1.35) nothing is lost: the critical angle costs only where the lobe straddles it.
        const double k = (inside ? 1.35 : 1.0) * std::sin(t * kDeg), reach = 6.0 / std::sqrt(n + 4.0);
        if (std::fabs(k - 1.0) > reach && std::fabs(k - 1.35) > reach) {
          EXPECT_GT(e.mean, 1.0 - 5 * e.stdError - 1e-4) << "n = " << n << " theta = " << t << (inside ? " inside" : "");
        }
      }
}

// Per sample f |cos| / pdf = 1 / max(N(wo), N(wi)) in Importance mode (the event's probability
// is its weight): exactly 1 where the lobe is clear of the rims, for either event; in Radiance
// mode refraction carries eta_o^2 / eta_i^2.
TEST(GlossyFurnace, DielectricSampleWeightIsExactlyOneAwayFromTheRims) {
  struct Case {
    float n;
    double theta;
    bool inside;
  } cases[] = {{1000, 30, false}, {1000, 15, true}, {4000, 55, false}, {4000, 35, true}, {4000, 60, true}};
  for (const Case& c : cases) {
    const Lobe lobe = glossyDielectric(c.n, 1.35f);
    Vec3 wo = fromAngles(c.theta * kDeg, 0.9);
    if (c.inside) wo.z = -wo.z;
    sampling::Pcg32 rng(3, 5);
    int reflected = 0, refracted = 0;
    for (int i = 0; i < 20000; ++i) {
      const float uc = rng.nextFloat();
      const Vec2 u(rng.nextFloat(), rng.nextFloat());
      for (TransportMode mode : {TransportMode::Importance, TransportMode::Radiance}) {
        auto s = lobeSample(lobe, wo, uc, u, mode);
        ASSERT_TRUE(s.has_value()) << "n = " << c.n << " theta = " << c.theta;
        const double etaO = c.inside ? 1.35 : 1.0, etaI = c.inside ? 1.0 : 1.35;
        const double expected = mode == TransportMode::Radiance && s->transmission ? etaO * etaO / (etaI * etaI) : 1.0;
        EXPECT_NEAR(s->f.v[0] * std::fabs(s->wi.z) / s->pdfW, expected, 1e-5 * expected)
            << "n = " << c.n << " theta = " << c.theta << (c.inside ? " inside" : "");
        if (mode == TransportMode::Importance) (s->transmission ? refracted : reflected)++;
      }
    }
    EXPECT_GT(reflected, 100);
    if (!(c.inside && c.theta > 50)) {
      EXPECT_GT(refracted, 1000);  // 60 degrees inside: TIR
    }
  }
}

// The mean-Fresnel weights lose nothing to Fresnel (the old min(F(wo), F(wi)) lost 1.4% at
// n = 1000 entering at 60 degrees, 15% near the critical angle inside); what remains is the
// lobe's share beyond the critical momentum weighted by (1 - F^) / 2 (docs/glossy-model.md).
TEST(GlossyFurnace, DielectricLosesLittleNearTheCriticalAngle) {
  struct Case {
    float n;
    double theta;
    bool inside;
    double atLeast;  // measured (docs/glossy-model.md) minus a little
  } cases[] = {{1000, 60, false, 0.9995}, {1000, 45, true, 0.98}, {100, 60, false, 0.97}, {100, 45, true, 0.92}};
  for (const Case& c : cases) {
    Vec3 wo = fromAngles(c.theta * kDeg, 0.4);
    if (c.inside) wo.z = -wo.z;
    const Estimate e = albedoMonteCarlo(glossyDielectric(c.n, 1.35f), wo, TransportMode::Importance, 0, 50000);
    EXPECT_GT(e.mean, c.atLeast) << "n = " << c.n << " theta = " << c.theta << (c.inside ? " inside" : "");
  }
}

// ---- reciprocity

TEST(GlossyReciprocity, ReflectionIsSymmetric) {
  sampling::Pcg32 rng(5, 9);
  for (float n : kExponents) {
    const Lobe lobe = glossyReflection(n);
    int nonZero = 0;
    for (int i = 0; i < 2000; ++i) {
      const Vec3 wo = fromAngles(std::acos(std::max(0.02f, rng.nextFloat())), 2 * M_PI * rng.nextFloat());
      auto s = lobeSample(lobe, wo, 0.5f, Vec2(rng.nextFloat(), rng.nextFloat()), TransportMode::Radiance);
      if (!s) continue;
      const float a = glossyLobeEval(lobe, wo, s->wi, TransportMode::Radiance).v[0];
      const float b = glossyLobeEval(lobe, s->wi, wo, TransportMode::Radiance).v[0];
      ASSERT_GT(a, 0.0f);
      EXPECT_NEAR(a, b, 1e-5f * a + 1e-30f) << "n = " << n;
      ++nonZero;
    }
    EXPECT_GT(nonZero, 1000);
  }
}

// Veach (1997, 5.2): f_rad(wo, wi) / eta_o^2 = f_rad(wi, wo) / eta_i^2, and the Importance
// BSDF is the adjoint: f_imp(wo, wi) = f_rad(wi, wo). Reflection of the dielectric is symmetric.
TEST(GlossyReciprocity, DielectricGeneralizedReciprocity) {
  sampling::Pcg32 rng(8, 3);
  for (float n : {10.0f, 100.0f, 1000.0f}) {
    const Lobe lobe = glossyDielectric(n, 1.35f);
    int transmitted = 0;
    for (int i = 0; i < 2000; ++i) {
      Vec3 wo = fromAngles(std::acos(std::max(0.05f, rng.nextFloat())), 2 * M_PI * rng.nextFloat());
      if (i % 2) wo.z = -wo.z;
      auto s = lobeSample(lobe, wo, rng.nextFloat(), Vec2(rng.nextFloat(), rng.nextFloat()), TransportMode::Radiance);
      if (!s) continue;
      const float fwd = glossyLobeEval(lobe, wo, s->wi, TransportMode::Radiance).v[0];
      const float back = glossyLobeEval(lobe, s->wi, wo, TransportMode::Radiance).v[0];
      const float adj = glossyLobeEval(lobe, s->wi, wo, TransportMode::Importance).v[0];
      if (!(fwd > 0.0f)) continue;
      if (!s->transmission) {
        EXPECT_NEAR(fwd, back, 1e-5f * fwd);
        continue;
      }
      ++transmitted;
      const float etaO = wo.z > 0 ? 1.0f : 1.35f, etaI = wo.z > 0 ? 1.35f : 1.0f;
      EXPECT_NEAR(fwd / (etaO * etaO), back / (etaI * etaI), 1e-5f * fwd) << "n = " << n;
      EXPECT_NEAR(glossyLobeEval(lobe, wo, s->wi, TransportMode::Importance).v[0], back, 1e-5f * back) << "n = " << n;
      EXPECT_NEAR(adj, fwd, 1e-5f * fwd) << "n = " << n;
    }
    EXPECT_GT(transmitted, 500);
  }
}

// ---- spectral lanes

// Lane k's pdf is the pdf of the same lobe with lane k's IOR moved to the hero lane, and it
// is what that lobe's sampler really produces (chi-square in its refraction plane).
TEST(GlossyLanes, PerLanePdfIsTheDensityWithThatLanesIor) {
  const Lobe lobe = dispersiveDielectric(1000.0f);
  sampling::Pcg32 rng(4, 4);
  for (int lane = 0; lane < 4; ++lane) {
    Lobe hero = lobe;
    std::swap(hero.a.v[0], hero.a.v[lane]);
    for (int i = 0; i < 500; ++i) {
      const Vec3 wo = fromAngles(std::acos(std::max(0.1f, rng.nextFloat())), 2 * M_PI * rng.nextFloat());
      auto s = lobeSample(hero, wo, rng.nextFloat(), Vec2(rng.nextFloat(), rng.nextFloat()), TransportMode::Radiance);
      if (!s) continue;
      const float expected = glossyLobePdf(hero, wo, s->wi, TransportMode::Radiance);
      EXPECT_FLOAT_EQ(glossyLobePdfForLane(lobe, wo, s->wi, TransportMode::Radiance, lane), expected);
      EXPECT_FLOAT_EQ(s->pdfW, expected);
      // The sampled lane's own value is non-zero where its pdf is (the event's weight is its
      // probability: same support).
      EXPECT_GT(glossyLobeEval(lobe, wo, s->wi, TransportMode::Radiance).v[lane], 0.0f);
    }
  }
  const Vec3 wo = fromAngles(35 * kDeg, 0.0);
  const float eta3 = lobe.a.v[3];
  const auto r = chiSquareInLobePlane(
      [&] {
        Lobe hero = lobe;
        std::swap(hero.a.v[0], hero.a.v[3]);
        return hero;
      }(),
      wo, true, 1.0, eta3, 0.0f, 1.0f, 1.0, 1);
  EXPECT_TRUE(r.passed) << r.detail;
}

TEST(GlossyLanes, DispersiveRefractionIsFlaggedAndEveryLaneHasItsOwnLobe) {
  const Lobe lobe = dispersiveDielectric(1000.0f);
  const Vec3 wo = fromAngles(50 * kDeg, 0.0);
  sampling::Pcg32 rng(2, 2);
  int refracted = 0;
  for (int i = 0; i < 1000; ++i) {
    auto s = lobeSample(lobe, wo, rng.nextFloat(), Vec2(rng.nextFloat(), rng.nextFloat()), TransportMode::Radiance);
    if (!s) continue;
    EXPECT_EQ(s->dispersive, s->transmission);
    if (!s->transmission) {
      for (int k = 1; k < 4; ++k) EXPECT_GT(s->f.v[k], 0.0f);  // the mirror lobe is shared
      continue;
    }
    ++refracted;
    EXPECT_GT(s->f.v[0], 0.0f);
    // Lane 3's value and its own pdf share their support (spectral MIS needs pdf > 0 where f > 0).
    EXPECT_EQ(s->f.v[3] > 0.0f, glossyLobePdfForLane(lobe, wo, s->wi, TransportMode::Radiance, 3) > 0.0f);
  }
  EXPECT_GT(refracted, 900);
  // Inside, reflection is dispersive too: its lobe is narrower by each lane's own eta.
  Vec3 below = fromAngles(30 * kDeg, 0.0);
  below.z = -below.z;
  int reflectedInside = 0;
  for (int i = 0; i < 1000; ++i) {
    auto s = lobeSample(lobe, below, rng.nextFloat(), Vec2(rng.nextFloat(), rng.nextFloat()), TransportMode::Radiance);
    if (!s) continue;
    EXPECT_TRUE(s->dispersive);
    reflectedInside += !s->transmission;
  }
  EXPECT_GT(reflectedInside, 5);
}

// ---- robustness

TEST(GlossyRobustness, DegenerateInputsGiveZeroNotNaN) {
  const float nan = std::nanf("");
  const Vec3 good = fromAngles(0.5, 0.1), mirror(-good.x, -good.y, good.z);
  const Vec3 bad[] = {Vec3(0.0f), Vec3(1, 0, 0), Vec3(nan, 0, 1), Vec3(0, 0, nan), Vec3(0.6f, 0.8f, 1e-8f)};
  std::vector<Lobe> lobes = {glossyReflection(100), glossyDielectric(100, 1.5f), dispersiveDielectric(4000)};
  for (float n : {0.0f, -1.0f, nan, 1e9f}) lobes.push_back(glossyReflection(n));
  for (float eta : {0.0f, -1.0f, nan, 1.0f}) lobes.push_back(glossyDielectric(1000, eta));
  for (const Lobe& lobe : lobes) {
    for (const Vec3& w : bad) {
      EXPECT_FALSE(glossyLobeEval(lobe, w, good, TransportMode::Radiance).hasNaNOrInf());
      EXPECT_FALSE(glossyLobeEval(lobe, good, w, TransportMode::Importance).hasNaNOrInf());
      EXPECT_TRUE(std::isfinite(glossyLobePdf(lobe, good, w, TransportMode::Radiance)));
      EXPECT_FALSE(glossyLobeSample(lobe, w, 0.3f, Vec2(0.5f), TransportMode::Radiance).has_value());
    }
    for (float u : {0.0f, 0.5f, 0x1.fffffep-1f}) {
      auto s = glossyLobeSample(lobe, good, u, Vec2(u, u), TransportMode::Radiance);
      if (s) {
        EXPECT_FALSE(s->f.hasNaNOrInf());
        EXPECT_TRUE(std::isfinite(s->pdfW) && s->pdfW > 0);
      }
    }
    EXPECT_FALSE(glossyLobeEval(lobe, good, mirror, TransportMode::Radiance).hasNaNOrInf());
  }
  EXPECT_TRUE(std::isfinite(glossyReflectionAlbedo(nan, 0.5f)));
  EXPECT_TRUE(std::isfinite(glossyReflectionAlbedo(100, 0.0f)));
}

}  // namespace
}  // namespace tex::render
