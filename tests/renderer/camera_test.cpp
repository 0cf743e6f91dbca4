// Cameras: generateRay and We invert each other, sampleWi lands where generateRay starts, the
// direction density of generateRay is pdfWe (chi-square), a thin lens focuses, importance
// integrates to 1, and light tracing and camera rays measure the same pixel values.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "renderer/camera/camera.h"
#include "renderer/core/warp.h"
#include "renderer/sampling/pcg.h"
#include "tests/renderer/chi_square.h"

namespace tex::render {
namespace {

using sampling::FilmPosition;

// A camera placed off the origin, rotated about a skew axis and scaled (glTF nodes may scale).
CameraSettings skewedSettings(float lensRadius) {
  CameraSettings s;
  Mat4 m = glm::translate(Mat4(1.0f), Vec3(1.5f, -0.5f, 2.0f));
  m = glm::rotate(m, 0.7f, glm::normalize(Vec3(0.3f, 1.0f, -0.2f)));
  m = glm::scale(m, Vec3(2.0f, 2.0f, 2.0f));
  s.cameraToWorld = m;
  s.yFovRadians = 0.9f;
  s.aspect = 1.6f;
  s.lensRadius = lensRadius;
  s.focusDistance = 3.0f;
  return s;
}

Vec2 next2(sampling::Pcg32& rng) { return Vec2(rng.nextFloat(), rng.nextFloat()); }

// The skewed camera made orthographic: a film 2.4 units high (glTF ymag 1.2), 3.84 wide.
CameraSettings orthographicSettings() {
  CameraSettings s = skewedSettings(0.0f);
  s.orthoHalfHeight = 1.2f;
  return s;
}

class CameraBothKinds : public ::testing::TestWithParam<float> {};

TEST_P(CameraBothKinds, GenerateRayThenWeReturnsTheFilmPositionAndUnitWeight) {
  const Camera camera(skewedSettings(GetParam()));
  sampling::Pcg32 rng(7, 1);
  for (int i = 0; i < 2000; ++i) {
    const FilmPosition film{rng.nextFloat(), rng.nextFloat()};
    const CameraRay r = camera.generateRay(film, next2(rng));
    EXPECT_NEAR(glm::length(r.ray.direction), 1.0f, 1e-5f);
    FilmPosition back{-1, -1};
    const float we = camera.We(r.ray, &back);
    ASSERT_GT(we, 0.0f) << film.x << " " << film.y;
    EXPECT_NEAR(back.x, film.x, 2e-4f);
    EXPECT_NEAR(back.y, film.y, 2e-4f);
    float pdfPosA = 0, pdfDirW = 0;
    camera.pdfWe(r.ray, pdfPosA, pdfDirW);
    const float cosTheta = dot3(r.ray.direction, camera.forward());
    EXPECT_NEAR(we * cosTheta / (pdfPosA * pdfDirW), r.weight, 1e-3f);
  }
  // Behind the camera: no importance.
  const Ray backwards{camera.position(), -camera.forward()};
  EXPECT_EQ(camera.We(backwards, nullptr), 0.0f);
}

TEST_P(CameraBothKinds, FilmCornersMapToTheImageCorners) {
  const Camera camera(skewedSettings(GetParam()));
  // Film (0,0) is top left: the ray leans to the camera's left (-right) and up.
  const Ray topLeft = camera.generateRay({0.0f, 0.0f}, Vec2(0.5f)).ray;
  const Mat4& m = camera.settings().cameraToWorld;
  const Vec3 right = glm::normalize(Vec3(m[0])), up = glm::normalize(Vec3(m[1]));
  EXPECT_LT(dot3(topLeft.direction, right), 0.0f);
  EXPECT_GT(dot3(topLeft.direction, up), 0.0f);
  const float tanHalfY = std::tan(0.5f * camera.settings().yFovRadians);
  const float cosTheta = dot3(topLeft.direction, camera.forward());
  EXPECT_NEAR(dot3(topLeft.direction, up) / cosTheta, tanHalfY, 1e-4f);
  EXPECT_NEAR(-dot3(topLeft.direction, right) / cosTheta, tanHalfY * camera.settings().aspect, 1e-4f);
}

TEST_P(CameraBothKinds, SampleWiLandsWhereGenerateRayStarts) {
  const Camera camera(skewedSettings(GetParam()));
  sampling::Pcg32 rng(11, 2);
  int hits = 0;
  for (int i = 0; i < 4000; ++i) {
    // Points in a box in front of the camera, some outside the field of view.
    const Ray probe = camera.generateRay({rng.nextFloat() * 1.4f - 0.2f, rng.nextFloat() * 1.4f - 0.2f}, Vec2(0.5f)).ray;
    const Vec3 ref = probe.origin + probe.direction * (0.5f + 6.0f * rng.nextFloat());
    const Vec2 uLens = next2(rng);
    const std::optional<CameraWiSample> s = camera.sampleWi(ref, uLens);
    if (!s) continue;
    ++hits;
    const CameraRay r = camera.generateRay(s->film, uLens);
    EXPECT_NEAR(glm::distance(r.ray.origin, s->pLens), 0.0f, 1e-4f);
    EXPECT_GT(dot3(r.ray.direction, -s->wi), 1.0f - 1e-5f);
    EXPECT_NEAR(s->distance, glm::distance(ref, s->pLens), 1e-4f * s->distance);
    // The density: lens area density converted to solid angle at ref.
    const float lensArea = camera.isPinhole() ? 1.0f : kPi * camera.settings().lensRadius * camera.settings().lensRadius;
    EXPECT_NEAR(s->pdfW, s->distance * s->distance / (absDot(s->wi, camera.forward()) * lensArea), 1e-3f * s->pdfW);
    EXPECT_NEAR(s->We, camera.We(r.ray, nullptr), 1e-3f * s->We);
  }
  EXPECT_GT(hits, 1000);
  EXPECT_FALSE(camera.sampleWi(camera.position() - camera.forward() * 2.0f, Vec2(0.5f)));  // behind
}

INSTANTIATE_TEST_SUITE_P(PinholeAndThinLens, CameraBothKinds, ::testing::Values(0.0f, 0.25f));

// Chi-square of generateRay's directions (film uniform) against pdfWe's pdfDirW. Directions
// are binned by where they cross the plane of focus (gnomonic coordinates around the camera
// axis, a margin of 1/8 of the film around it), so that bin edges fall on the film's edges;
// the density per unit of those coordinates is pdfDirW * dw/dp, with dw = cos^3 dA / d^2 on a
// plane at distance d.
test::ChiSquareResult chiSquareCameraDirections(const Camera& camera, Vec2 uLens) {
  const CameraSettings& s = camera.settings();
  const Mat4& m = s.cameraToWorld;
  const Vec3 right = glm::normalize(Vec3(m[0])), up = glm::normalize(Vec3(m[1])), forward = -glm::normalize(Vec3(m[2]));
  const float tanY = std::tan(0.5f * s.yFovRadians), tanX = tanY * s.aspect;
  const float focus = camera.isPinhole() ? 1.0f : s.focusDistance;
  const Vec3 pLens = camera.generateRay({0.5f, 0.5f}, uLens).ray.origin;
  constexpr float kMargin = 0.125f, kSpan = 1.0f + 2.0f * kMargin;
  // Bin coordinates [0,1)^2 <-> points on the plane of focus (relative to the camera position).
  auto toBin = [&](const Vec3& w) -> std::optional<Vec2> {
    const float cosTheta = dot3(w, forward);
    if (!(cosTheta > 0.0f)) return std::nullopt;
    const Vec3 p = pLens - camera.position() + w * (focus / cosTheta);
    const float fx = 0.5f * (dot3(p, right) / (focus * tanX) + 1.0f), fy = 0.5f * (1.0f - dot3(p, up) / (focus * tanY));
    return Vec2((fx + kMargin) / kSpan, (fy + kMargin) / kSpan);
  };
  const float binToPlaneArea = (2.0f * tanX * focus * kSpan) * (2.0f * tanY * focus * kSpan);
  return test::chiSquarePoints(
      [&](Vec2 u, float) { return toBin(camera.generateRay({u.x, u.y}, uLens).ray.direction); },
      [&](Vec2 b) -> double {
        const float fx = b.x * kSpan - kMargin, fy = b.y * kSpan - kMargin;
        const Vec3 pFocus = camera.position() + right * ((2.0f * fx - 1.0f) * tanX * focus) +
                            up * ((1.0f - 2.0f * fy) * tanY * focus) + forward * focus;
        const Vec3 d = pFocus - pLens;
        const float dist = glm::length(d);
        const Vec3 w = d / dist;
        float pdfPosA, pdfDirW;
        camera.pdfWe(Ray{pLens, w}, pdfPosA, pdfDirW);
        const float cosTheta = dot3(w, forward);
        return double(pdfDirW) * cosTheta / (dist * dist) * binToPlaneArea;  // dw/dA = cos / dist^2
      },
      /*bins=*/80);
}

TEST(Camera, PinholeDirectionsFollowPdfWe) {
  const test::ChiSquareResult r = chiSquareCameraDirections(Camera(skewedSettings(0.0f)), Vec2(0.5f));
  EXPECT_TRUE(r.passed) << r.detail;
}

TEST(Camera, ThinLensDirectionsFromOneLensPointFollowPdfWe) {
  // From a lens point off the centre, the directions of generateRay have density pdfDirW.
  const test::ChiSquareResult r = chiSquareCameraDirections(Camera(skewedSettings(0.3f)), Vec2(0.8f, 0.3f));
  EXPECT_TRUE(r.passed) << r.detail;
}

TEST(Camera, ThinLensRaysThroughOneFilmPointMeetOnThePlaneOfFocus) {
  const Camera camera(skewedSettings(0.4f));
  const float focus = camera.settings().focusDistance;
  sampling::Pcg32 rng(3, 3);
  for (int f = 0; f < 50; ++f) {
    const FilmPosition film{rng.nextFloat(), rng.nextFloat()};
    Vec3 first(0.0f);
    float spread = 0.0f;
    for (int l = 0; l < 20; ++l) {
      const Ray ray = camera.generateRay(film, next2(rng)).ray;
      const float t = focus / dot3(ray.direction, camera.forward());  // distance to the focus plane
      const Vec3 p = ray.origin + ray.direction * t;
      if (l == 0) first = p;
      spread = std::max(spread, glm::distance(p, first));
    }
    EXPECT_LT(spread, 1e-4f * focus);
  }
  // And at half the focus distance the same rays are spread over the lens' scale.
  const FilmPosition film{0.3f, 0.6f};
  const Ray a = camera.generateRay(film, Vec2(0.1f, 0.5f)).ray, b = camera.generateRay(film, Vec2(0.9f, 0.5f)).ray;
  const float ta = 0.5f * focus / dot3(a.direction, camera.forward()), tb = 0.5f * focus / dot3(b.direction, camera.forward());
  EXPECT_GT(glm::distance(a.origin + a.direction * ta, b.origin + b.direction * tb), 0.2f);
}

// Monte Carlo mean and standard error of a sequence of values.
struct MeanError {
  double sum = 0, sum2 = 0;
  int n = 0;
  void add(double x) { sum += x, sum2 += x * x, ++n; }
  double mean() const { return sum / n; }
  double error() const { return std::sqrt(std::max(0.0, sum2 / n - mean() * mean()) / n); }
};

TEST(Camera, ImportanceIntegratesToOne) {
  // Pinhole: integral of We cos over directions is 1. Thin lens: over directions and lens area.
  for (float lensRadius : {0.0f, 0.2f}) {
    const Camera camera(skewedSettings(lensRadius));
    const float lensArea = lensRadius > 0 ? kPi * lensRadius * lensRadius : 1.0f;
    const Mat4& m = camera.settings().cameraToWorld;
    const Vec3 right = glm::normalize(Vec3(m[0])), up = glm::normalize(Vec3(m[1]));
    sampling::Pcg32 rng(5, 4);
    MeanError estimate;
    for (int i = 0; i < 1000000; ++i) {
      const Vec2 lens = lensRadius * sampleConcentricDisk(next2(rng));
      const Vec3 w = sampleUniformSphere(next2(rng));
      const Ray ray{camera.position() + right * lens.x + up * lens.y, w};
      const float we = camera.We(ray, nullptr);
      estimate.add(we > 0 ? double(we) * dot3(w, camera.forward()) * lensArea / kUniformSpherePdfW : 0.0);
    }
    EXPECT_NEAR(estimate.mean(), 1.0, 4.0 * estimate.error()) << "lens radius " << lensRadius;
    EXPECT_LT(estimate.error(), 0.01);
  }
}

// Orthographic: rays leave the film rectangle (film (0,0) at its top left) along the view
// direction; We gives the film position back with 1 / area, and only for that direction.
TEST(Camera, OrthographicRaysLeaveTheFilmRectangleAlongTheViewDirection) {
  const Camera camera(orthographicSettings());
  ASSERT_TRUE(camera.isOrthographic());
  EXPECT_FALSE(camera.isPinhole());
  const Mat4& m = camera.settings().cameraToWorld;
  const Vec3 right = glm::normalize(Vec3(m[0])), up = glm::normalize(Vec3(m[1]));
  const float halfY = 1.2f, halfX = 1.2f * camera.settings().aspect, area = 4.0f * halfX * halfY;
  sampling::Pcg32 rng(13, 3);
  for (int i = 0; i < 2000; ++i) {
    const FilmPosition film{rng.nextFloat(), rng.nextFloat()};
    const CameraRay r = camera.generateRay(film, next2(rng));
    EXPECT_GT(dot3(r.ray.direction, camera.forward()), 1.0f - 1e-6f);
    const Vec3 local = r.ray.origin - camera.position();
    EXPECT_NEAR(dot3(local, right), (2.0f * film.x - 1.0f) * halfX, 1e-4f);
    EXPECT_NEAR(dot3(local, up), (1.0f - 2.0f * film.y) * halfY, 1e-4f);
    FilmPosition back{-1, -1};
    const float we = camera.We(r.ray, &back);
    EXPECT_NEAR(we, 1.0f / area, 1e-6f);
    EXPECT_NEAR(back.x, film.x, 1e-4f);
    EXPECT_NEAR(back.y, film.y, 1e-4f);
    float pdfPosA = 0, pdfDirW = 0;
    camera.pdfWe(r.ray, pdfPosA, pdfDirW);
    EXPECT_NEAR(we / (pdfPosA * pdfDirW), r.weight, 1e-4f);
    // Another direction from the same point carries nothing.
    const Vec3 tilted = glm::normalize(r.ray.direction + 1e-2f * right);
    EXPECT_EQ(camera.We(Ray{r.ray.origin, tilted}, nullptr), 0.0f);
  }
  EXPECT_EQ(camera.We(Ray{camera.position(), -camera.forward()}, nullptr), 0.0f);
}

// Chi-square of the orthographic rays' origins on the camera plane (a margin of 1/8 around the
// film) against pdfPosA: uniform on the film, nothing outside.
TEST(Camera, OrthographicRayOriginsFollowPdfWe) {
  const Camera camera(orthographicSettings());
  const Mat4& m = camera.settings().cameraToWorld;
  const Vec3 right = glm::normalize(Vec3(m[0])), up = glm::normalize(Vec3(m[1]));
  const float halfY = 1.2f, halfX = 1.2f * camera.settings().aspect;
  constexpr float kMargin = 0.125f, kSpan = 1.0f + 2.0f * kMargin;
  const float binToPlaneArea = (2.0f * halfX * kSpan) * (2.0f * halfY * kSpan);
  const test::ChiSquareResult r = test::chiSquarePoints(
      [&](Vec2 u, float) -> std::optional<Vec2> {
        const Vec3 local = camera.generateRay({u.x, u.y}, Vec2(0.5f)).ray.origin - camera.position();
        const float fx = 0.5f * (dot3(local, right) / halfX + 1.0f), fy = 0.5f * (1.0f - dot3(local, up) / halfY);
        return Vec2((fx + kMargin) / kSpan, (fy + kMargin) / kSpan);
      },
      [&](Vec2 b) -> double {
        const float fx = b.x * kSpan - kMargin, fy = b.y * kSpan - kMargin;
        const Vec3 origin = camera.position() + right * ((2.0f * fx - 1.0f) * halfX) + up * ((1.0f - 2.0f * fy) * halfY);
        float pdfPosA, pdfDirW;
        camera.pdfWe(Ray{origin, camera.forward()}, pdfPosA, pdfDirW);
        return double(pdfPosA) * binToPlaneArea;
      },
      /*bins=*/80);
  EXPECT_TRUE(r.passed) << r.detail;
}

// Orthographic sampleWi: the reference point's projection on the film plane, along -forward,
// at its distance along the axis; outside the film or behind the camera, nothing.
TEST(Camera, OrthographicSampleWiProjectsAlongTheViewDirection) {
  const Camera camera(orthographicSettings());
  sampling::Pcg32 rng(17, 4);
  int hits = 0;
  for (int i = 0; i < 4000; ++i) {
    const Ray probe = camera.generateRay({rng.nextFloat() * 1.4f - 0.2f, rng.nextFloat() * 1.4f - 0.2f}, Vec2(0.5f)).ray;
    const float depth = 0.5f + 6.0f * rng.nextFloat();
    const Vec3 ref = probe.origin + probe.direction * depth;
    const std::optional<CameraWiSample> s = camera.sampleWi(ref, next2(rng));
    if (!s) continue;
    ++hits;
    const CameraRay r = camera.generateRay(s->film, Vec2(0.5f));
    EXPECT_NEAR(glm::distance(r.ray.origin, s->pLens), 0.0f, 1e-4f);
    EXPECT_NEAR(glm::distance(s->pLens, probe.origin), 0.0f, 1e-4f);
    EXPECT_GT(dot3(-s->wi, camera.forward()), 1.0f - 1e-6f);
    EXPECT_NEAR(s->distance, depth, 1e-4f * depth);
    EXPECT_EQ(s->pdfW, 1.0f);
    EXPECT_NEAR(s->We, camera.We(r.ray, nullptr), 1e-6f);
  }
  EXPECT_GT(hits, 1500);  // about half of the points project inside the film
  EXPECT_LT(hits, 2600);
  EXPECT_FALSE(camera.sampleWi(camera.position() - camera.forward() * 2.0f, Vec2(0.5f)));  // behind
}

// A one-sided square emitter of radiance 1 facing the camera, partly covering the view.
struct SquareEmitter {
  Vec3 corner, edgeU, edgeV, n;
  float area() const { return glm::length(glm::cross(edgeU, edgeV)); }
  // Radiance 1 where the ray hits the front side, 0 elsewhere.
  float radianceAlong(const Ray& ray) const {
    const float denom = dot3(ray.direction, n);
    if (!(denom < 0.0f)) return 0.0f;
    const float t = dot3(corner - ray.origin, n) / denom;
    if (!(t > 0.0f)) return 0.0f;
    // Coordinates along the (non-orthogonal) edges: solve the 2x2 Gram system.
    const Vec3 d = ray.origin + ray.direction * t - corner;
    const float uu = dot3(edgeU, edgeU), uv = dot3(edgeU, edgeV), vv = dot3(edgeV, edgeV);
    const float du = dot3(d, edgeU), dv = dot3(d, edgeV), det = uu * vv - uv * uv;
    const float a = (du * vv - dv * uv) / det, b = (dv * uu - du * uv) / det;
    return a >= 0 && a <= 1 && b >= 0 && b <= 1 ? 1.0f : 0.0f;
  }
};

// The pixel values of a 4x4 film seen by camera rays and by light tracing (points on the
// emitter connected to the lens with sampleWi) agree: pbrt-v4's importance normalisation, and
// the orthographic camera's Dirac in direction (pdfW 1, no distance falloff).
TEST(Camera, LightTracingAndCameraRaysMeasureTheSamePixels) {
  for (float lensRadius : {0.0f, 0.15f, -1.0f /* orthographic */}) {
    const Camera camera(lensRadius < 0.0f ? orthographicSettings() : skewedSettings(lensRadius));
    // The emitter: tilted, about 4 units in front, covering part of the view.
    const Vec3 centre = camera.position() + camera.forward() * 4.0f;
    const Mat4& m = camera.settings().cameraToWorld;
    const Vec3 right = glm::normalize(Vec3(m[0])), up = glm::normalize(Vec3(m[1]));
    SquareEmitter emitter;
    // The orthographic film is 3.84 x 2.4 units wherever the emitter is: a smaller emitter.
    const float size = camera.isOrthographic() ? 0.55f : 1.0f;
    emitter.edgeU = (right * 5.0f + camera.forward() * 0.8f) * size;
    emitter.edgeV = (up * 3.5f - camera.forward() * 0.3f) * size;
    emitter.corner = centre - 0.45f * emitter.edgeU - 0.4f * emitter.edgeV;  // reaches a corner of the film
    emitter.n = glm::normalize(glm::cross(emitter.edgeU, emitter.edgeV));
    if (dot3(emitter.n, camera.forward()) > 0) emitter.n = -emitter.n;
    constexpr int kGrid = 4, kSamples = 1000000;
    std::vector<MeanError> cameraEstimate(kGrid * kGrid), lightEstimate(kGrid * kGrid);
    sampling::Pcg32 rng(9, 5);
    // Pixel value = integral of L over the pixel's film area, divided by that area.
    const double pixelArea = 1.0 / (kGrid * kGrid);
    for (int i = 0; i < kSamples; ++i) {
      const FilmPosition film{rng.nextFloat(), rng.nextFloat()};
      const Ray ray = camera.generateRay(film, next2(rng)).ray;
      const int pixel = int(film.y * kGrid) * kGrid + int(film.x * kGrid);
      for (int p = 0; p < kGrid * kGrid; ++p)
        cameraEstimate[size_t(p)].add(p == pixel ? emitter.radianceAlong(ray) / pixelArea : 0.0);
    }
    for (int i = 0; i < kSamples; ++i) {
      const Vec2 uv = next2(rng);
      const Vec3 x = emitter.corner + emitter.edgeU * uv.x + emitter.edgeV * uv.y;
      const std::optional<CameraWiSample> s = camera.sampleWi(x, next2(rng));
      int pixel = -1;
      double value = 0;
      if (s && dot3(s->wi, emitter.n) > 0) {
        pixel = int(s->film.y * kGrid) * kGrid + int(s->film.x * kGrid);
        // L We cos_x / (pdfW pdfA), pdfA = 1 / area.
        value = double(s->We) * dot3(s->wi, emitter.n) / s->pdfW * emitter.area() / pixelArea;
      }
      for (int p = 0; p < kGrid * kGrid; ++p) lightEstimate[size_t(p)].add(p == pixel ? value : 0.0);
    }
    int lit = 0;
    for (int p = 0; p < kGrid * kGrid; ++p) {
      const MeanError& c = cameraEstimate[size_t(p)];
      const MeanError& l = lightEstimate[size_t(p)];
      const double sigma = std::sqrt(c.error() * c.error() + l.error() * l.error());
      EXPECT_NEAR(c.mean(), l.mean(), 4.5 * sigma + 1e-9) << "pixel " << p << " lens " << lensRadius;
      if (c.mean() > 0.2) ++lit;
    }
    EXPECT_GE(lit, 4);       // the emitter covers part of the film...
    EXPECT_LE(lit, 15);      // ...but not all of it
  }
}

}  // namespace
}  // namespace tex::render
