// The light samplers (renderer/lights/light_sampler.h): the alias table's choices follow the
// weights; the light BVH's choices follow its pmf(ctx, i) at random contexts, the pmf sums to 1,
// sample() reports exactly pmf(), and no light that can light a point has pmf 0 there (the
// estimator would be biased). At the render level: both selections agree on a scene of many
// small lamps, and the BVH's noise there is several times lower.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "renderer/bsdf/bsdf.h"
#include "renderer/color/wavelengths.h"
#include "renderer/integrators/light_context.h"
#include "renderer/integrators/path_tracer.h"
#include "renderer/integrators/render_scene.h"
#include "renderer/lights/alias_table.h"
#include "renderer/lights/light_factory.h"
#include "renderer/lights/light_sampler.h"
#include "renderer/lights/triangle_light.h"
#include "renderer/sampling/pcg.h"
#include "renderer/scene/shapes.h"
#include "tests/renderer/chi_square.h"
#include "tests/renderer/constant_emission.h"
#include "tests/renderer/scene_fixtures.h"

namespace tex::render {
namespace {

using ::tex::test::ConstantEmission;

Vec3 randomUnit(sampling::Pcg32& rng) {
  const float z = 1.0f - 2.0f * rng.nextFloat(), phi = 2.0f * kPi * rng.nextFloat();
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  return Vec3(r * std::cos(phi), r * std::sin(phi), z);
}
Vec3 randomPoint(sampling::Pcg32& rng, float extent) {
  return Vec3(rng.nextFloat() - 0.5f, rng.nextFloat() - 0.5f, rng.nextFloat() - 0.5f) * (2.0f * extent);
}

// A set of lights with what the reachability check needs to know about each.
struct LightSet {
  std::vector<std::unique_ptr<EmissionSource>> emissions;
  std::vector<std::unique_ptr<Light>> owned;
  std::vector<const Light*> pointers;
  struct Shape {
    enum class Kind { Triangle, Point, Spot, Infinite } kind = Kind::Infinite;
    Vec3 p[3];
    Vec3 normal{0.0f};  // triangle: emitting side; spot: axis
    bool twoSided = false;
    float cosOuter = -1.0f;
  };
  std::vector<Shape> shapes;

  void add(std::unique_ptr<Light> light, const Shape& shape) {
    pointers.push_back(light.get());
    owned.push_back(std::move(light));
    shapes.push_back(shape);
  }
};

LightSet randomLights(uint64_t seed, int triangles, int points, int spots, int infinite) {
  LightSet set;
  sampling::Pcg32 rng(seed, 11);
  for (int i = 0; i < triangles; ++i) {
    const Vec3 center = randomPoint(rng, 5.0f);
    const float size = 0.05f * std::pow(20.0f, rng.nextFloat());  // 0.05 .. 1, log-uniform
    TriangleLightDesc d;
    d.p0 = center + randomUnit(rng) * size;
    d.p1 = center + randomUnit(rng) * size;
    d.p2 = center + randomUnit(rng) * size;
    d.normal = glm::cross(d.p1 - d.p0, d.p2 - d.p0);
    d.twoSided = rng.nextFloat() < 0.25f;
    set.emissions.push_back(std::make_unique<ConstantEmission>(0.1f * std::pow(100.0f, rng.nextFloat())));
    std::unique_ptr<Light> light = makeTriangleLight(d, set.emissions.back().get());
    LightSet::Shape s;
    s.kind = LightSet::Shape::Kind::Triangle;
    s.p[0] = d.p0;
    s.p[1] = d.p1;
    s.p[2] = d.p2;
    s.normal = static_cast<const TriangleLight*>(light.get())->normal();
    s.twoSided = d.twoSided;
    set.add(std::move(light), s);
  }
  std::string error;
  for (int i = 0; i < points + spots; ++i) {
    LightDesc desc;
    desc.kind = i < points ? LightDesc::Kind::Point : LightDesc::Kind::Spot;
    desc.position = randomPoint(rng, 5.0f);
    desc.direction = randomUnit(rng);
    desc.emission.kind = SpectrumDesc::Kind::Constant;
    desc.emission.value = 1.0f;
    desc.intensity = 0.1f * std::pow(100.0f, rng.nextFloat());
    desc.outerConeRadians = 0.1f + 1.1f * rng.nextFloat();
    desc.innerConeRadians = 0.5f * desc.outerConeRadians;
    std::unique_ptr<Light> light = makeLight(desc, error);
    EXPECT_TRUE(light) << error;
    LightSet::Shape s;
    s.kind = i < points ? LightSet::Shape::Kind::Point : LightSet::Shape::Kind::Spot;
    s.p[0] = desc.position;
    s.normal = desc.direction;
    s.cosOuter = std::cos(desc.outerConeRadians);
    set.add(std::move(light), s);
  }
  for (int i = 0; i < infinite; ++i) {
    LightDesc desc;
    desc.kind = i % 2 == 0 ? LightDesc::Kind::ConstantEnvironment : LightDesc::Kind::Directional;
    desc.direction = Vec3(0.0f, -1.0f, 0.0f);
    desc.emission.kind = SpectrumDesc::Kind::Constant;
    desc.emission.value = 0.5f;
    std::unique_ptr<Light> light = makeLight(desc, error);
    EXPECT_TRUE(light) << error;
    light->preprocess(SceneSphere{Vec3(0.0f), 10.0f});
    set.add(std::move(light), LightSet::Shape{});
  }
  return set;
}

// A random reference context: a point near the lights, with a random normal or (a third of
// the time) none.
LightSampleContext randomContext(sampling::Pcg32& rng) {
  LightSampleContext ctx;
  ctx.p = randomPoint(rng, 6.0f);
  if (rng.nextFloat() < 2.0f / 3.0f) ctx.n = randomUnit(rng);
  return ctx;
}

std::vector<LightSet> testSets() {
  std::vector<LightSet> sets;
  sets.push_back(randomLights(1, 300, 0, 0, 0));  // many triangles
  sets.push_back(randomLights(2, 40, 10, 10, 2));  // every kind
  sets.push_back(randomLights(3, 1, 0, 0, 1));     // one bounded light beside a sky
  sets.push_back(randomLights(4, 0, 3, 0, 0));     // a few point lights
  return sets;
}

// 65536 entries, 65535 of weight 1 and one of 99 x their total (each light entry is kept
// with probability about 0.01 in its bin): the light ones together must have probability
// 0.01. Drawn as the path tracer draws u for the power choice (a 24-bit stratified float plus
// independent low bits) they do; from the 24-bit float alone the keep test had 8 bits and they
// took 3/256 (17 % too much; a review found a point light that much too bright).
TEST(AliasTable, ManyEntriesKeepTheirProbabilityBeyondTheSamplersBits) {
  constexpr int kEntries = 65536;
  std::vector<float> weights(kEntries, 1.0f);
  weights[0] = 99.0f * float(kEntries - 1);
  const AliasTable table(weights);
  const double lightTotal = double(kEntries - 1) / (double(kEntries - 1) * 100.0);
  sampling::Pcg32 rng(17, 3);
  constexpr int kDraws = 4 << 20;
  int light = 0, lightFloat = 0;
  for (int i = 0; i < kDraws; ++i) {
    const float u24 = float(rng.nextBits() >> 8) * 0x1p-24f;
    const double u = double(u24) + double(rng.nextFloat()) * 0x1p-24;
    light += table.sample(u)->first != 0;
    lightFloat += table.sample(double(u24))->first != 0;
  }
  const double sigma = std::sqrt(lightTotal * (1.0 - lightTotal) / kDraws);
  EXPECT_NEAR(double(light) / kDraws, lightTotal, 5.0 * sigma);
  EXPECT_GT(double(lightFloat) / kDraws, lightTotal * 1.1);  // the 24-bit float alone: biased
}

TEST(AliasTable, ChoicesFollowTheWeights) {
  sampling::Pcg32 rng(5, 1);
  std::vector<float> weights(1000);
  for (size_t i = 0; i < weights.size(); ++i)
    weights[i] = i % 10 == 3 ? 0.0f : i % 97 == 0 ? 1000.0f : std::pow(10.0f, 3.0f * rng.nextFloat());
  const AliasTable table(weights);
  ASSERT_EQ(table.size(), 1000);
  double total = 0, pmfSum = 0;
  for (const float w : weights) total += w;
  for (int i = 0; i < table.size(); ++i) {
    pmfSum += table.pmf(i);
    EXPECT_NEAR(table.pmf(i), weights[size_t(i)] / total, 1e-6 * weights[size_t(i)] / total + 1e-12);
  }
  EXPECT_NEAR(pmfSum, 1.0, 1e-5);
  constexpr int kSamples = 2000000;
  std::vector<double> observed(weights.size(), 0.0), expected(weights.size(), 0.0);
  for (int i = 0; i < kSamples; ++i) {
    const auto pick = table.sample(rng.nextFloat());
    ASSERT_TRUE(pick);
    ASSERT_EQ(pick->second, table.pmf(pick->first));
    observed[size_t(pick->first)] += 1;
  }
  for (size_t i = 0; i < weights.size(); ++i) {
    expected[i] = weights[i] / total * kSamples;
    if (weights[i] == 0.0f) {
      EXPECT_EQ(observed[i], 0.0) << i;
    }
  }
  const ::tex::test::ChiSquareResult r = ::tex::test::chiSquareTest(observed, expected);
  EXPECT_TRUE(r.passed) << r.detail;
  // Nothing to choose from; one entry.
  EXPECT_FALSE(AliasTable(std::vector<float>{0.0f, 0.0f}).sample(0.5f));
  EXPECT_FALSE(AliasTable(std::vector<float>{}).sample(0.5f));
  const std::vector<float> one = {0.0f, 2.0f, 0.0f};
  for (const float u : {0.0f, 0.3f, 0.5f, 0x1.fffffep-1f}) EXPECT_EQ(AliasTable(one).sample(u)->first, 1);
}

TEST(LightBvhSampler, ChoicesFollowThePmfAtRandomContexts) {
  const std::vector<LightSet> sets = testSets();
  constexpr int kContextsPerSet = 5, kSamples = 200000;
  const int testCount = int(sets.size()) * kContextsPerSet;
  sampling::Pcg32 rng(7, 3);
  for (size_t s = 0; s < sets.size(); ++s) {
    const LightSampler sampler(sets[s].pointers);
    for (int c = 0; c < kContextsPerSet; ++c) {
      const LightSampleContext ctx = randomContext(rng);
      const size_t n = sets[s].pointers.size();
      // One cell per light and one for "no light chosen".
      std::vector<double> observed(n + 1, 0.0), expected(n + 1, 0.0);
      double pmfSum = 0;
      for (size_t i = 0; i < n; ++i) {
        expected[i] = double(sampler.pmf(ctx, int(i))) * kSamples;
        pmfSum += sampler.pmf(ctx, int(i));
      }
      expected[n] = std::max(0.0, 1.0 - pmfSum) * kSamples;
      for (int k = 0; k < kSamples; ++k) {
        const auto pick = sampler.sample(ctx, rng.nextFloat());
        observed[pick ? size_t(pick->first) : n] += 1;
      }
      const ::tex::test::ChiSquareResult r = ::tex::test::chiSquareTest(observed, expected, 0.01, testCount);
      EXPECT_TRUE(r.passed) << "set " << s << " context " << c << ": " << r.detail;
    }
  }
}

// A grid of side x side small squares facing down (-z) at heights 0.2 .. 2.6 above z = 0.
LightSet lampGrid(int side) {
  LightSet set;
  sampling::Pcg32 rng(31, 4);
  const float spacing = 18.0f / float(side);
  for (int j = 0; j < side; ++j)
    for (int i = 0; i < side; ++i) {
      const float s = 0.25f * spacing * (0.5f + rng.nextFloat());
      const Vec3 c(-9.0f + (float(i) + 0.5f) * spacing, -9.0f + (float(j) + 0.5f) * spacing, 0.2f + 2.4f * rng.nextFloat());
      set.emissions.push_back(std::make_unique<ConstantEmission>(rng.nextFloat() < 0.5f ? 1.0f : 8.0f));
      const Vec3 corners[4] = {c, c + Vec3(0.0f, s, 0.0f), c + Vec3(s, s, 0.0f), c + Vec3(s, 0.0f, 0.0f)};
      for (int t = 0; t < 2; ++t) {
        TriangleLightDesc d;
        d.p0 = corners[0];
        d.p1 = corners[1 + t];
        d.p2 = corners[2 + t];
        d.normal = Vec3(0.0f, 0.0f, -1.0f);
        LightSet::Shape shape;
        shape.kind = LightSet::Shape::Kind::Triangle;
        shape.p[0] = d.p0, shape.p[1] = d.p1, shape.p[2] = d.p2;
        shape.normal = d.normal;
        set.add(makeTriangleLight(d, set.emissions.back().get()), shape);
      }
    }
  return set;
}

// sample() reports exactly pmf() (the MIS weights at emitters found by BSDF sampling use pmf(),
// so it must be the same number), and the pmf sums to 1 over the lights where the descent cannot
// end without a light. It can, as in pbrt-v4: a node whose loose bounds reach p may have two
// children that cannot (lights of random orientations around p); then sample() returns nothing
// with that probability, and the sum is 1 minus it (the chi-square test above counts that cell).
TEST(LightBvhSampler, PmfSumsToOneAndSampleReportsItExactly) {
  sampling::Pcg32 rng(8, 5);
  const auto checkReports = [&](const LightSampler& sampler, const LightSampleContext& ctx, const std::string& where) {
    for (int k = 0; k < 50; ++k) {
      const auto pick = sampler.sample(ctx, rng.nextFloat());
      if (pick) {
        ASSERT_EQ(pick->second, sampler.pmf(ctx, pick->first)) << where << " light " << pick->first;
      }
    }
  };
  const auto pmfSum = [](const LightSampler& sampler, const LightSampleContext& ctx) {
    double sum = 0;
    for (int i = 0; i < sampler.size(); ++i) sum += sampler.pmf(ctx, i);
    return sum;
  };
  // Lamps above a floor, as in a room: points under them, with the floor's normal or none.
  const LightSet grid = lampGrid(24);
  const LightSampler gridSampler(grid.pointers);
  for (int c = 0; c < 200; ++c) {
    LightSampleContext ctx;
    ctx.p = Vec3(20.0f * rng.nextFloat() - 10.0f, 20.0f * rng.nextFloat() - 10.0f, 0.0f);
    ctx.n = c % 2 == 0 ? Vec3(0.0f, 0.0f, 1.0f) : Vec3(0.0f);
    EXPECT_NEAR(pmfSum(gridSampler, ctx), 1.0, 1e-5) << "context " << c;
    checkReports(gridSampler, ctx, "grid context " + std::to_string(c));
  }
  // Random sets: never more than 1; exactly 1 without a normal when every light emits all around.
  const std::vector<LightSet> sets = testSets();
  for (size_t s = 0; s < sets.size(); ++s) {
    const LightSampler sampler(sets[s].pointers);
    for (int c = 0; c < 200; ++c) {
      LightSampleContext ctx = randomContext(rng);
      const double sum = pmfSum(sampler, ctx);
      EXPECT_LE(sum, 1.0 + 1e-5) << "set " << s << " context " << c;
      checkReports(sampler, ctx, "set " + std::to_string(s) + " context " + std::to_string(c));
      if (s == 3) {  // point lights only
        ctx.n = Vec3(0.0f);
        EXPECT_NEAR(pmfSum(sampler, ctx), 1.0, 1e-5) << "context " << c;
      }
    }
  }
}

// A bright lamp beside a far cluster of 16384 dim ones: at the point the cluster's lights
// together have probability about 2e-6, which a 24-bit u covers with about 30 values. The
// descent rescales u at every level, so from a float at most those 30 of the cluster's lights
// could ever be chosen, while pmf() promised each its share (their light was missing from light
// samples: a bias). With u in double (the path tracer adds independent low bits to the
// sampler's 24), every light of the cluster is chosen as often as its pmf says.
TEST(LightBvhSampler, LightsOfTinyTotalProbabilityAreAllReachable) {
  LightSet set;
  std::string error;
  const auto addPoint = [&](const Vec3& position, float intensity) {
    LightDesc desc;
    desc.kind = LightDesc::Kind::Point;
    desc.position = position;
    desc.emission.kind = SpectrumDesc::Kind::Constant;
    desc.emission.value = 1.0f;
    desc.intensity = intensity;
    std::unique_ptr<Light> light = makeLight(desc, error);
    ASSERT_TRUE(light) << error;
    LightSet::Shape shape;
    shape.kind = LightSet::Shape::Kind::Point;
    shape.p[0] = position;
    set.add(std::move(light), shape);
  };
  addPoint(Vec3(0.0f), 1e4f);
  constexpr int kSide = 128;  // the cluster: kSide^2 lamps 100 units away
  for (int j = 0; j < kSide; ++j)
    for (int i = 0; i < kSide; ++i) addPoint(Vec3(100.0f, float(i) * 0.1f, float(j) * 0.1f), 0.01f);
  const LightSampler sampler(set.pointers);
  LightSampleContext ctx;
  ctx.p = Vec3(-1.0f, 0.0f, 0.0f);
  double clusterPmf = 0;
  for (int i = 1; i < sampler.size(); ++i) clusterPmf += sampler.pmf(ctx, i);
  ASSERT_GT(clusterPmf, 0.0);
  ASSERT_LT(clusterPmf * 0x1p24, 100.0);  // the case this test is about
  // The cluster's interval of u lies at one end of [0, 1) (the root's children: lamp,
  // cluster). Its other end, found by bisection: the lamp's float pmf, 1 - 1.6e-6 to within
  // 6e-8, would misplace it by up to 4 % of its width.
  const bool clusterLow = sampler.sample(ctx, 0.0)->first != 0;
  ASSERT_NE(clusterLow, sampler.sample(ctx, 1.0 - 0x1p-53)->first != 0);
  double lamp = clusterLow ? 1.0 - 0x1p-53 : 0.0, cluster = clusterLow ? 0.0 : 1.0 - 0x1p-53;
  for (int k = 0; k < 64; ++k) {
    const double middle = 0.5 * (lamp + cluster);
    (sampler.sample(ctx, middle)->first != 0 ? cluster : lamp) = middle;
  }
  const double begin = clusterLow ? 0.0 : cluster, width = clusterLow ? cluster : 1.0 - cluster;
  EXPECT_NEAR(width, clusterPmf, 1e-4 * clusterPmf);
  sampling::Pcg32 rng(41, 2);
  constexpr int kDraws = 1 << 20;
  std::vector<double> observed(size_t(sampler.size() - 1), 0.0), expected(observed.size(), 0.0);
  int inCluster = 0;
  for (int k = 0; k < kDraws; ++k) {
    const double r = (double(rng.nextBits()) + double(rng.nextBits()) * 0x1p-32) * 0x1p-32;
    const auto pick = sampler.sample(ctx, begin + width * r);
    ASSERT_TRUE(pick);
    if (pick->first == 0) continue;
    ++inCluster;
    observed[size_t(pick->first - 1)] += 1;
  }
  EXPECT_EQ(inCluster, kDraws);
  int reached = 0;
  for (size_t i = 0; i < observed.size(); ++i) {
    reached += observed[i] > 0;
    expected[i] = double(sampler.pmf(ctx, int(i) + 1)) / clusterPmf * inCluster;
  }
  EXPECT_EQ(reached, kSide * kSide);
  const ::tex::test::ChiSquareResult r = ::tex::test::chiSquareTest(observed, expected);
  EXPECT_TRUE(r.passed) << r.detail;
}

// Brute force: a light can light ctx if one of its points lies on n's side of p (any side
// without a normal) and emits toward p. Every such light must have pmf > 0.
TEST(LightBvhSampler, EveryLightThatCanReachThePointHasPositivePmf) {
  const std::vector<LightSet> sets = testSets();
  sampling::Pcg32 rng(9, 7);
  int checkedReachable = 0, pruned = 0;
  for (size_t s = 0; s < sets.size(); ++s) {
    const LightSampler sampler(sets[s].pointers);
    const std::vector<LightSet::Shape>& shapes = sets[s].shapes;
    for (int c = 0; c < 300; ++c) {
      LightSampleContext ctx = randomContext(rng);
      // Also points right beside a light, where rounding matters most.
      if (c % 3 == 0 && shapes[0].kind == LightSet::Shape::Kind::Triangle) {
        const LightSet::Shape& t = shapes[size_t(rng.nextFloat() * float(shapes.size())) % shapes.size()];
        if (t.kind == LightSet::Shape::Kind::Triangle)
          ctx.p = (t.p[0] + t.p[1] + t.p[2]) / 3.0f + randomUnit(rng) * 0.01f;
      }
      const bool hasNormal = ctx.n != Vec3(0.0f);
      for (size_t i = 0; i < shapes.size(); ++i) {
        const LightSet::Shape& sh = shapes[i];
        if (sh.kind == LightSet::Shape::Kind::Infinite) {
          EXPECT_GT(sampler.pmf(ctx, int(i)), 0.0f);
          continue;
        }
        bool reachable = false;
        const int points = sh.kind == LightSet::Shape::Kind::Triangle ? 64 : 1;
        for (int k = 0; k < points && !reachable; ++k) {
          Vec3 x = sh.p[0];
          if (sh.kind == LightSet::Shape::Kind::Triangle) {
            float b0 = rng.nextFloat(), b1 = rng.nextFloat();
            if (k < 3) b0 = k == 0 ? 1.0f : 0.0f, b1 = k == 1 ? 1.0f : 0.0f;  // the corners
            if (b0 + b1 > 1.0f) b0 = 1.0f - b0, b1 = 1.0f - b1;
            x = sh.p[0] * b0 + sh.p[1] * b1 + sh.p[2] * (1.0f - b0 - b1);
          }
          const Vec3 toP = ctx.p - x;
          const bool inFront = !hasNormal || dot3(-toP, ctx.n) > 0.0f;
          bool emitsToward = true;
          if (sh.kind == LightSet::Shape::Kind::Triangle) emitsToward = sh.twoSided || dot3(toP, sh.normal) > 0.0f;
          if (sh.kind == LightSet::Shape::Kind::Spot) emitsToward = dot3(glm::normalize(toP), sh.normal) > sh.cosOuter;
          reachable = inFront && emitsToward && lengthSquared(toP) > 0.0f;
        }
        const float pmf = sampler.pmf(ctx, int(i));
        if (reachable) {
          ++checkedReachable;
          EXPECT_GT(pmf, 0.0f) << "set " << s << " context " << c << " light " << i;
        } else if (pmf == 0.0f) {
          ++pruned;
        }
      }
    }
  }
  EXPECT_GT(checkedReachable, 10000);
  // The bounds do exclude lights that cannot contribute (behind the normal or facing away).
  EXPECT_GT(pruned, 5000);
}

TEST(LightSampler, UnboundedLightsShareAFixedProbabilityAndALoneBoundedLightIsAlwaysChosen) {
  const LightSet set = randomLights(12, 1, 0, 0, 2);  // a triangle, a sky and a sun
  const LightSampler sampler(set.pointers);
  EXPECT_FLOAT_EQ(sampler.infiniteProbability(), 2.0f / 3.0f);
  sampling::Pcg32 rng(13, 1);
  for (int c = 0; c < 100; ++c) {
    const LightSampleContext ctx = randomContext(rng);
    EXPECT_FLOAT_EQ(sampler.pmf(ctx, 1), 1.0f / 3.0f);
    EXPECT_FLOAT_EQ(sampler.pmf(ctx, 2), 1.0f / 3.0f);
    // The lone triangle is not judged (its sample is empty where it cannot reach): no cost for
    // scenes with one bounded light, and its pmf is the tree's share everywhere.
    EXPECT_FLOAT_EQ(sampler.pmf(ctx, 0), 1.0f / 3.0f);
  }
  // The power distribution is still there, for emission sampling and --light-sampler power.
  double sum = 0;
  for (int i = 0; i < sampler.size(); ++i) sum += sampler.pmfPower(i);
  EXPECT_NEAR(sum, 1.0, 1e-6);
  EXPECT_NEAR(sampler.pmfPower(0) / sampler.pmfPower(1), set.pointers[0]->power() / set.pointers[1]->power(), 1e-3);
}

// A quad light (two triangles of one plane; the Cornell box's) is chosen by power, without a
// descent: the importance could only tell its halves apart by distance. Two quads in different
// planes, or many triangles, get the tree.
TEST(LightSampler, APlanarQuadLightIsChosenByPowerAndSeparateLightsAreNot) {
  const auto quad = [](LightSet& set, const Vec3& corner, float size, float L) {
    set.emissions.push_back(std::make_unique<ConstantEmission>(L));
    const Vec3 c[4] = {corner, corner + Vec3(0.0f, 0.0f, size), corner + Vec3(size * 0.7f, 0.0f, size),
                       corner + Vec3(size * 0.7f, 0.0f, 0.0f)};
    for (int t = 0; t < 2; ++t) {
      TriangleLightDesc d;
      d.p0 = c[0];
      d.p1 = c[1 + t];
      d.p2 = c[2 + t];
      d.normal = Vec3(0.0f, -1.0f, 0.0f);
      set.add(makeTriangleLight(d, set.emissions.back().get()), LightSet::Shape{});
    }
  };
  LightSet one;
  quad(one, Vec3(0.213f, 0.5487f, 0.227f), 0.13f, 17.0f);
  const LightSampler flat(one.pointers);
  EXPECT_TRUE(flat.bvh().flat());
  sampling::Pcg32 rng(14, 3);
  for (int c = 0; c < 50; ++c) {
    const LightSampleContext ctx = randomContext(rng);
    EXPECT_EQ(flat.pmf(ctx, 0), flat.pmfPower(0));
    EXPECT_EQ(flat.pmf(ctx, 1), flat.pmfPower(1));
    const auto pick = flat.sample(ctx, rng.nextFloat());
    ASSERT_TRUE(pick);
    EXPECT_EQ(pick->second, flat.pmf(ctx, pick->first));
  }
  LightSet two;
  quad(two, Vec3(0.0f, 1.0f, 0.0f), 0.2f, 1.0f);
  quad(two, Vec3(2.0f, 1.5f, 0.0f), 0.2f, 1.0f);  // another height: another plane
  EXPECT_FALSE(LightSampler(two.pointers).bvh().flat());
  EXPECT_FALSE(LightSampler(lampGrid(3).pointers).bvh().flat());
}

// The context next-event estimation passes: a reflecting BSDF's shading normal turned toward
// wo (lights behind it cannot contribute), no normal for one that transmits (they can).
TEST(LightSampler, NextEventContextKeepsLightsBehindTransmittingSurfaces) {
  const Vec3 n(0.0f, 0.0f, 1.0f), p(1.0f, 2.0f, 3.0f);
  Bsdf diffuse(Frame::fromNormal(n), n);
  Lobe lambert;
  lambert.kind = LobeKind::Lambertian;
  lambert.weight = Spectrum(0.5f);
  ASSERT_TRUE(diffuse.add(lambert));
  EXPECT_EQ(nextEventContext(diffuse, p, Vec3(0.0f, 0.6f, 0.8f)).n, n);
  EXPECT_EQ(nextEventContext(diffuse, p, Vec3(0.0f, 0.6f, -0.8f)).n, -n);  // seen from behind
  EXPECT_EQ(nextEventContext(diffuse, p, Vec3(0.0f, 0.6f, 0.8f)).p, p);
  Bsdf glass(Frame::fromNormal(n), n);
  Lobe rough;
  rough.kind = LobeKind::RoughDielectric;
  rough.weight = Spectrum(1.0f);
  rough.a = Spectrum(1.5f);
  rough.roughness = 0.3f;
  ASSERT_TRUE(glass.add(lambert));
  ASSERT_TRUE(glass.add(rough));
  EXPECT_EQ(nextEventContext(glass, p, Vec3(0.0f, 0.6f, 0.8f)).n, Vec3(0.0f));
  // With that context a light below the surface keeps its share; with the normal it has none.
  LightSet below;
  below.emissions.push_back(std::make_unique<ConstantEmission>(1.0f));
  for (int k = 0; k < 2; ++k) {
    TriangleLightDesc d;
    d.p0 = p + Vec3(float(k) * 3.0f, 0.0f, -2.0f);
    d.p1 = d.p0 + Vec3(0.5f, 0.0f, 0.0f);
    d.p2 = d.p0 + Vec3(0.0f, 0.5f, float(k));  // two planes: not a flat set
    d.normal = Vec3(0.0f, 0.0f, 1.0f);
    below.add(makeTriangleLight(d, below.emissions.back().get()), LightSet::Shape{});
  }
  const LightSampler sampler(below.pointers);
  ASSERT_FALSE(sampler.bvh().flat());
  EXPECT_GT(sampler.pmf(nextEventContext(glass, p, Vec3(0.0f, 0.6f, 0.8f)), 0), 0.0f);
  EXPECT_EQ(sampler.pmf(nextEventContext(diffuse, p, Vec3(0.0f, 0.6f, 0.8f)), 0), 0.0f);
}

// ---- Render level ----

// A 20 x 20 floor (z = 0, a Lambertian of albedo 0.5) under a grid of `side` x `side` small
// square lamps facing down at heights 0.2 .. 2.6 and three brightnesses, seen from above.
SceneDescription manyLampsScene(int side) {
  const std::string file = test::writeTexModule("many_lamps",
                                                "export fn floor(h: Hit) -> Material = diffuse(spectrum(0.5))\n"
                                                "export fn lamp(h: Hit) -> Material = emission(spectrum(4.0))\n");
  SceneDescription scene;
  MeshPrimitive floor = makeQuad(Vec3(-10.0f, -10.0f, 0.0f), Vec3(20.0f, 0.0f, 0.0f), Vec3(0.0f, 20.0f, 0.0f));
  floor.material = 0;
  scene.primitives.push_back(std::move(floor));
  MeshPrimitive lamps;
  sampling::Pcg32 rng(21, 2);
  const float spacing = 18.0f / float(side), size = 0.25f * spacing;
  for (int j = 0; j < side; ++j)
    for (int i = 0; i < side; ++i) {
      const float s = size * (0.5f + rng.nextFloat());
      const Vec3 corner(-9.0f + (float(i) + 0.5f) * spacing, -9.0f + (float(j) + 0.5f) * spacing, 0.2f + 2.4f * rng.nextFloat());
      // edge1 x edge2 = -z: the lamps face the floor.
      MeshPrimitive q = makeQuad(corner, Vec3(0.0f, s, 0.0f), Vec3(s, 0.0f, 0.0f));
      const uint32_t base = uint32_t(lamps.positions.size());
      for (const Vec3& p : q.positions) lamps.positions.push_back(p);
      for (const Vec2& uv : q.uv0) lamps.uv0.push_back(uv);
      for (const uint32_t k : q.indices) lamps.indices.push_back(base + k);
    }
  lamps.material = 1;
  scene.primitives.push_back(std::move(lamps));
  scene.instances.push_back(MeshInstance{0, Mat4(1.0f), "floor"});
  scene.instances.push_back(MeshInstance{1, Mat4(1.0f), "lamps"});
  GltfMaterial floorMaterial, lampMaterial;
  floorMaterial.name = "floor";
  lampMaterial.name = "lamp";
  scene.materials = {floorMaterial, lampMaterial};
  test::bindEntriesByMaterialName(scene, file, {"floor", "lamp"});
  scene.cameras.push_back(test::cameraLookingDownZ(Vec3(0.0f, 0.0f, 14.0f), 1.2f));
  return scene;
}

// Per-pixel statistics of an image's estimates (the lane-averaged L per sample).
struct PixelStatistics {
  double imageMean = 0;       // mean over pixels of the pixel means
  double imageMeanError = 0;  // its standard error, from the per-pixel sample variances
  double meanVariance = 0;    // the per-sample variance, averaged over pixels (the noise)
};

PixelStatistics renderStatistics(const RenderScene& rs, LightSelection selection, uint64_t seed, int width, int spp,
                                 int maxDepth) {
  sampling::PixelGrid grid;
  grid.width = grid.imageWidth = width;
  grid.height = grid.imageHeight = width;
  PathTracerSettings settings;
  settings.maxDepth = maxDepth;
  settings.lightSelection = selection;
  const PathTracer tracer(rs, sampling::Sampler(sampling::SamplerKind::Sobol, seed, grid), settings);
  const size_t pixels = size_t(width) * size_t(width);
  std::vector<double> sum(pixels, 0.0), sum2(pixels, 0.0);
  for (uint64_t i = 0; i < uint64_t(pixels) * uint64_t(spp); ++i) {
    const SampleRecord r = tracer.record(i);
    double v = 0;
    for (int j = 0; j < r.wavelengthCount; ++j) v += r.values[j] * color::visibleWavelengthPdf(r.lambdaNm[j]);
    v /= r.wavelengthCount;
    const int x = std::min(int(r.filmX * float(width)), width - 1), y = std::min(int(r.filmY * float(width)), width - 1);
    sum[size_t(y) * size_t(width) + size_t(x)] += v;
    sum2[size_t(y) * size_t(width) + size_t(x)] += v * v;
  }
  PixelStatistics st;
  double errorSquared = 0;
  for (size_t p = 0; p < pixels; ++p) {
    const double mean = sum[p] / spp, variance = std::max(0.0, sum2[p] / spp - mean * mean) * spp / (spp - 1);
    st.imageMean += mean / double(pixels);
    st.meanVariance += variance / double(pixels);
    errorSquared += variance / spp / double(pixels) / double(pixels);
  }
  st.imageMeanError = std::sqrt(errorSquared);
  return st;
}

// The render scene keeps pointers into its description: both live here.
struct ManyLamps {
  SceneDescription scene;
  std::unique_ptr<RenderScene> rs;
};

std::unique_ptr<ManyLamps> buildManyLamps(int side) {
  auto m = std::make_unique<ManyLamps>();
  m->scene = manyLampsScene(side);
  RenderSceneOptions o;
  o.width = o.height = 16;
  o.useCache = false;
  std::string error;
  m->rs = RenderScene::build(m->scene, o, error);
  EXPECT_TRUE(m->rs) << error;
  if (m->rs) {
    EXPECT_EQ(m->rs->triangleLightCount(), 2 * side * side);
  }
  return m;
}

// Unbiasedness: with two bounces (MIS at lamps found by BSDF sampling from the floor uses
// pmf(ctx) of the floor point) the BVH and power selections estimate the same image.
TEST(LightSamplerRender, BvhAndPowerAgreeOnManyLamps) {
  const std::unique_ptr<ManyLamps> lamps = buildManyLamps(32);
  ASSERT_TRUE(lamps->rs);
  const RenderScene& rs = *lamps->rs;
  const PixelStatistics bvh = renderStatistics(rs, LightSelection::Bvh, 1, 32, 512, 3);
  const PixelStatistics power = renderStatistics(rs, LightSelection::Power, 2, 32, 512, 3);
  const double error = std::sqrt(bvh.imageMeanError * bvh.imageMeanError + power.imageMeanError * power.imageMeanError);
  ASSERT_GT(bvh.imageMean, 0.0);
  EXPECT_LT(std::fabs(bvh.imageMean - power.imageMean), 4.5 * error)
      << "bvh " << bvh.imageMean << " +- " << bvh.imageMeanError << ", power " << power.imageMean << " +- "
      << power.imageMeanError;
  // Tight enough to see a bias of a few percent.
  EXPECT_LT(error, 0.01 * bvh.imageMean);
}

// The point of the BVH: at equal samples, lower noise where each point sees few of many lights.
// Direct lighting only (one bounce), so the light choice is the only difference.
TEST(LightSamplerRender, BvhReducesNoiseOnManyLampsSeveralfold) {
  // Measured 2.67 (64 x 64 pixels, 16 spp; MIS with BSDF sampling already rescues part of the
  // power selection's noise); equal selections give 1 within a few percent.
  constexpr double kMinimumVarianceRatio = 2.0;
  const std::unique_ptr<ManyLamps> lamps = buildManyLamps(32);
  ASSERT_TRUE(lamps->rs);
  const RenderScene& rs = *lamps->rs;
  const PixelStatistics bvh = renderStatistics(rs, LightSelection::Bvh, 3, 64, 16, 1);
  const PixelStatistics power = renderStatistics(rs, LightSelection::Power, 3, 64, 16, 1);
  const double ratio = power.meanVariance / bvh.meanVariance;
  RecordProperty("variance_ratio", std::to_string(ratio));
  EXPECT_GT(ratio, kMinimumVarianceRatio) << "power " << power.meanVariance << ", bvh " << bvh.meanVariance;
}

}  // namespace
}  // namespace tex::render
