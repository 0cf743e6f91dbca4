// The Charlie sheen's model pieces (renderer/bsdf/sheen_albedo.h): D is normalised, the
// quadrature of the albedo agrees with an independent Monte Carlo estimate, the table bounds the
// albedo from above everywhere (and not loosely), and the bounded average is the exact cosine-
// weighted mean of the bounded lookup. Also the table's generator (disabled test):
//   tests_renderer --gtest_also_run_disabled_tests --gtest_filter='SheenAlbedoTable.DISABLED_Generate'
// prints the file renderer/bsdf/sheen_albedo_table.cpp between gtest's own lines.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "renderer/bsdf/sheen_albedo.h"
#include "renderer/core/warp.h"
#include "renderer/sampling/pcg.h"

namespace tex::render {
namespace {

double alphaAt(double x) { return sheen::kMinRoughness * std::pow(1.0 / sheen::kMinRoughness, x); }
double cosAt(double y) { return sheen::kTableMinCos * std::pow(1.0 / sheen::kTableMinCos, y); }

TEST(SheenAlbedo, CharlieDistributionIsNormalized) {
  // int D(theta) cos(theta) dw = 1 by the midpoint rule in cos(theta).
  for (double alpha : {0.01, 0.05, 0.3, 1.0}) {
    const int n = 200000;
    double sum = 0;
    for (int i = 0; i < n; ++i) {
      const double c = (i + 0.5) / n;
      sum += sheen::charlieD(alpha, c) * c * (2.0 * M_PI / n);
    }
    EXPECT_NEAR(sum, 1.0, 1e-4) << alpha;
  }
}

TEST(SheenAlbedo, LambdaIsContinuousAtTheFitsJoin) {
  // The fit's two branches meet at cos = 0.5 (the paper mirrors the fit there).
  for (double alpha : {0.01, 0.2, 1.0}) {
    const double below = sheen::charlieLambda(alpha, 0.5 - 1e-9), above = sheen::charlieLambda(alpha, 0.5);
    EXPECT_NEAR(below / above, 1.0, 1e-6) << alpha;
  }
}

TEST(SheenAlbedo, QuadratureAgreesWithMonteCarlo) {
  // Independent estimate: uniform hemisphere directions, 5 standard errors.
  sampling::Pcg32 rng(7, 3);
  for (double alpha : {0.02, 0.3, 1.0})
    for (double mu : {1.0, 0.5, 0.05}) {
      const Vec3 wo(float(std::sqrt(1 - mu * mu)), 0.0f, float(mu));
      const int n = 400000;
      double sum = 0, sumSquares = 0;
      for (int i = 0; i < n; ++i) {
        const Vec3 wi = sampleUniformHemisphere(Vec2(rng.nextFloat(), rng.nextFloat()));
        const double w = sheen::charlieValue(alpha, wo, wi) * wi.z * 2.0 * M_PI;
        sum += w;
        sumSquares += w * w;
      }
      const double mean = sum / n, standardError = std::sqrt((sumSquares / n - mean * mean) / n);
      EXPECT_NEAR(sheen::albedoQuadrature(alpha, mu), mean, 5 * standardError + 1e-6) << alpha << " " << mu;
    }
}

TEST(SheenAlbedo, QuadratureIsConverged) {
  // The composite rule against the same integral over two halves in phi and mu (a different
  // node set): agreement to 1e-5 at the hardest places (small alpha, near grazing).
  for (double alpha : {0.01, 0.05, 1.0})
    for (double mu : {1e-6, 1e-3, 0.05, 0.5, 1.0}) {
      const Vec3 wo(float(std::sqrt(1 - mu * mu)), 0.0f, float(mu));
      const int n = 1500, m = 600;
      double sum = 0;  // midpoint in s with mu_i = s^3 (crowds at grazing), phi in [0, pi]
      for (int i = 0; i < n; ++i) {
        const double s = (i + 0.5) / n, muI = s * s * s, sinI = std::sqrt(1 - muI * muI);
        double ring = 0;
        for (int j = 0; j < m; ++j) {
          const double phi = (j + 0.5) * M_PI / m;
          const Vec3 wi(float(sinI * std::cos(phi)), float(sinI * std::sin(phi)), float(muI));
          ring += sheen::charlieValue(alpha, wo, wi);
        }
        sum += ring * (M_PI / m) * 2.0 * muI * 3.0 * s * s / n;
      }
      EXPECT_NEAR(sheen::albedoQuadrature(alpha, mu), sum, 1e-5 * std::max(1.0, sum)) << alpha << " " << mu;
    }
}

TEST(SheenAlbedoTable, BoundsTheAlbedoFromAboveEverywhere) {
  // Random points, log-uniform in both coordinates and along the domain's edges, and some
  // nodes: the lookup is never below the albedo, and never more than 0.01 above it (the
  // margins stay small).
  sampling::Pcg32 rng(11, 5);
  double worstBelow = 0, worstAbove = 0;
  std::vector<std::pair<double, double>> points;
  for (int k = 0; k < 400; ++k) points.push_back({alphaAt(rng.nextFloat()), cosAt(rng.nextFloat())});
  // The domain's edges: the smallest roughness and the most grazing cosine curve the most.
  for (int k = 0; k < 100; ++k) points.push_back({sheen::kMinRoughness, cosAt(rng.nextFloat())});
  for (int k = 0; k < 50; ++k) points.push_back({alphaAt(rng.nextFloat()), sheen::kTableMinCos});
  for (int i = 0; i < sheen::kTableAlphaNodes; i += 7)
    for (int j = 0; j < sheen::kTableCosNodes; j += 13)
      points.push_back({alphaAt(double(i) / (sheen::kTableAlphaNodes - 1)), cosAt(double(j) / (sheen::kTableCosNodes - 1))});
  for (const auto& [alpha, mu] : points) {
    const double truth = sheen::albedoQuadrature(alpha, mu), table = sheen::tabulatedAlbedo(alpha, mu);
    worstBelow = std::max(worstBelow, truth - table);
    worstAbove = std::max(worstAbove, table - truth);
  }
  std::printf("sheen table: max shortfall %.3g, max excess %.3g\n", worstBelow, worstAbove);
  EXPECT_LE(worstBelow, 0.0);
  EXPECT_LT(worstAbove, 0.01);
}

TEST(SheenAlbedoTable, AlbedoExceedsOneOnlyAtSmallRoughnessOrNearGrazing) {
  // Why the lobe is normalised (sheen_albedo.h): measured maxima over cos theta.
  double maxRough = 0, maxSmooth = 0, maxModerate = 0;
  for (int j = 0; j < sheen::kTableCosNodes; ++j) {
    const double mu = cosAt(double(j) / (sheen::kTableCosNodes - 1));
    maxRough = std::max(maxRough, sheen::albedoQuadrature(1.0, mu));
    maxSmooth = std::max(maxSmooth, sheen::albedoQuadrature(0.01, mu));
    if (mu >= 1e-3) maxModerate = std::max(maxModerate, sheen::albedoQuadrature(0.3, mu));
  }
  std::printf("sheen max E: alpha 1 %.4f, alpha 0.01 %.4f, alpha 0.3 (cos >= 1e-3) %.4f\n", maxRough, maxSmooth,
              maxModerate);
  EXPECT_GT(maxRough, 1.0);   // near grazing
  EXPECT_GT(maxSmooth, 1.5);  // small alpha
  EXPECT_LT(maxModerate, 1.0);
}

TEST(SheenAlbedoTable, BoundedAverageIsTheCosineWeightedMeanOfTheBoundedLookup) {
  // 2 int min(1, E_table) mu dmu by a fine midpoint rule in ln(mu) over the same lookup.
  for (double alpha : {0.01, 0.013, 0.1, 0.37, 1.0}) {
    const double vMin = std::log(sheen::kTableMinCos);
    const int n = 400000;
    double sum = sheen::kTableMinCos * sheen::kTableMinCos * sheen::boundedAlbedo(alpha, sheen::kTableMinCos);
    for (int i = 0; i < n; ++i) {
      const double v = vMin * (1.0 - (i + 0.5) / n), mu = std::exp(v);
      sum += sheen::boundedAlbedo(alpha, mu) * 2.0 * mu * mu * (-vMin / n);
    }
    EXPECT_NEAR(sheen::boundedAverageAlbedo(alpha), sum, 1e-6) << alpha;
    EXPECT_LT(sheen::boundedAverageAlbedo(alpha), 1.0);
  }
}

// The generator of renderer/bsdf/sheen_albedo_table.cpp (~3 minutes). Node values: the
// quadrature, raised by 2 x the largest bilinear shortfall sampled on a 5 x 5 grid over each
// neighbouring cell (edges included: the first rows curve most), plus 1e-5 for the
// quadrature's own error.
TEST(SheenAlbedoTable, DISABLED_Generate) {
  constexpr int nA = sheen::kTableAlphaNodes, nC = sheen::kTableCosNodes;
  std::vector<double> node(nA * nC), raise(nA * nC, 0.0);
  for (int i = 0; i < nA; ++i)
    for (int j = 0; j < nC; ++j)
      node[i * nC + j] = sheen::albedoQuadrature(alphaAt(double(i) / (nA - 1)), cosAt(double(j) / (nC - 1)));
  for (int i = 0; i + 1 < nA; ++i)
    for (int j = 0; j + 1 < nC; ++j) {
      double shortfall = 0;
      for (double fx : {0.0, 0.25, 0.5, 0.75, 1.0})
        for (double fy : {0.0, 0.25, 0.5, 0.75, 1.0}) {
          if ((fx == 0.0 || fx == 1.0) && (fy == 0.0 || fy == 1.0)) continue;  // the nodes themselves
          const double truth = sheen::albedoQuadrature(alphaAt((i + fx) / (nA - 1)), cosAt((j + fy) / (nC - 1)));
          const double interpolated = (1 - fx) * (1 - fy) * node[i * nC + j] + fx * (1 - fy) * node[(i + 1) * nC + j] +
                                      (1 - fx) * fy * node[i * nC + j + 1] + fx * fy * node[(i + 1) * nC + j + 1];
          shortfall = std::max(shortfall, truth - interpolated);
        }
      for (int di = 0; di < 2; ++di)
        for (int dj = 0; dj < 2; ++dj) raise[(i + di) * nC + j + dj] = std::max(raise[(i + di) * nC + j + dj], shortfall);
    }
  std::printf("// Generated by the disabled test SheenAlbedoTable.DISABLED_Generate\n");
  std::printf("// (tests/renderer/sheen_albedo_test.cpp): E(alpha, cos theta) of the unit-colour Charlie sheen\n");
  std::printf("// on the grid of sheen_albedo.h, each node raised by 2 x the largest bilinear shortfall of\n");
  std::printf("// its cells (sampled on a 5 x 5 grid) plus 1e-5, so that the interpolant is >= E.\n");
  std::printf("#include \"renderer/bsdf/sheen_albedo.h\"\n\nnamespace tex::render::sheen {\n\n");
  std::printf("const float kAlbedoTable[kTableAlphaNodes][kTableCosNodes] = {\n");
  for (int i = 0; i < nA; ++i) {
    std::printf("    {  // alpha = %.6g\n", alphaAt(double(i) / (nA - 1)));
    for (int j = 0; j < nC; ++j) {
      const double v = node[i * nC + j] + 2.0 * raise[i * nC + j] + 1e-5;
      std::printf("%s%.9gf,%s", j % 8 == 0 ? "      " : " ", float(v), j % 8 == 7 || j == nC - 1 ? "\n" : "");
    }
    std::printf("    },\n");
  }
  std::printf("};\n\n}  // namespace tex::render::sheen\n");
}

}  // namespace
}  // namespace tex::render
