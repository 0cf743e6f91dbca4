#include "renderer/lights/triangle_light.h"

#include <cmath>

#include "renderer/core/warp.h"

namespace tex::render {

TriangleLight::TriangleLight(const TriangleLightDesc& desc, const EmissionSource* emission)
    : desc_(desc), emission_(emission), emissionReadsHit_(emission && emission->readsHit()) {
  float len = 0.0f;
  const Vec3 n = triangleUnitNormal(desc.p1 - desc.p0, desc.p2 - desc.p0, len);
  area_ = 0.5f * len;
  pdfA_ = area_ > 0.0f ? 1.0f / area_ : 0.0f;
  pointError_ = maxAbsComponent(trianglePointError(desc.p0, desc.p1, desc.p2));
  if (len > 0.0f) {
    n_ = n;
    if (dot3(n_, desc.normal) < 0.0f) n_ = -n_;
  }
}

float TriangleLight::power() const {
  if (!emission_ || !(area_ > 0.0f)) return 0.0f;
  const float sides = desc_.twoSided ? 2.0f : 1.0f;
  if (!emissionReadsHit_) return sides * kPi * area_ * emission_->averageRadiance();
  // An emission that varies over the surface (a texture, a pattern): this triangle's own
  // radiance at its centroid and three inner points, so that bright parts are chosen more
  // often. A tenth of the material's average keeps every triangle reachable by light
  // sampling where the four points happen to be dark.
  const Vec2 points[4] = {Vec2(1.0f / 3.0f), Vec2(2.0f / 3.0f, 1.0f / 6.0f), Vec2(1.0f / 6.0f, 2.0f / 3.0f),
                          Vec2(1.0f / 6.0f, 1.0f / 6.0f)};
  float local = 0.0f;
  for (const Vec2& b : points) local += std::max(emission_->radianceEstimate(pointAt(b)), 0.0f);
  return sides * kPi * area_ * (0.9f * local / 4.0f + 0.1f * emission_->averageRadiance());
}

std::optional<LightBounds> TriangleLight::bounds() const {
  LightBounds b;
  b.box.extend(desc_.p0);
  b.box.extend(desc_.p1);
  b.box.extend(desc_.p2);
  const float sides = desc_.twoSided ? 2.0f : 1.0f;
  // A degenerate triangle has no normal: it gets no share of the choices (power() is 0 too).
  b.phi = area_ > 0.0f ? power() / (kPi * sides) : 0.0f;
  b.normals = {n_, 1.0f};
  b.cosThetaE = 0.0f;
  b.twoSided = desc_.twoSided;
  return b;
}

namespace {
// A vertex attribute at barycentrics (b0, b1) of the first two vertices.
template <class T>
T interpolate(const T& a0, const T& a1, const T& a2, Vec2 b) {
  const float b2 = 1.0f - b.x - b.y;
  return a0 * b.x + a1 * b.y + a2 * b2;
}
}  // namespace

EmitterPoint TriangleLight::pointAt(Vec2 b) const {
  EmitterPoint e;
  e.p = interpolate(desc_.p0, desc_.p1, desc_.p2, b);
  e.n = n_;
  e.primitive = desc_.primitive;
  if (emissionReadsHit_) placeOnGeometry(e, b);
  return e;
}

// The barycentrics (b.x of p0, b.y of p1) of a point on the triangle (least squares on the
// edges); only for emissions that read their Hit, so light samples need not carry them.
Vec2 TriangleLight::barycentricsOf(const Vec3& p) const {
  const Vec3 e0 = desc_.p0 - desc_.p2, e1 = desc_.p1 - desc_.p2, d = p - desc_.p2;
  const float a00 = dot3(e0, e0), a01 = dot3(e0, e1), a11 = dot3(e1, e1);
  const float b0 = dot3(e0, d), b1 = dot3(e1, d);
  const float det = a00 * a11 - a01 * a01;
  if (!(std::fabs(det) > 0.0f)) return Vec2(1.0f / 3.0f);
  return Vec2((a11 * b0 - a01 * b1) / det, (a00 * b1 - a01 * b0) / det);
}

// interpolate() weighs p0, p1, p2 by b.x, b.y, 1 - b.x - b.y; SurfaceHit's barycentrics are
// those of the second and third vertices.
void TriangleLight::placeOnGeometry(EmitterPoint& e, Vec2 b) const {
  e.instance = desc_.instance;
  e.triangle = desc_.triangle;
  e.b12 = Vec2(b.y, 1.0f - b.x - b.y);
}

Spectrum TriangleLight::L(const EmitterPoint& point, const Vec3& w, const Wavelengths& lambda) const {
  if (!emission_ || !(desc_.twoSided || dot3(w, n_) > 0.0f)) return Spectrum();
  EmitterPoint toward = point;
  toward.w = w;
  return emission_->radiance(toward, lambda);
}

std::optional<LightLiSample> TriangleLight::sampleLiDeferred(const Vec3& refPoint, Vec2 u, const Wavelengths& lambda) const {
  (void)lambda;
  // Every return returns `result`, so that it is the caller's object (NRVO): a local copied
  // into the optional went through the stack, and the copy's 16-byte reloads of 4- and 8-byte
  // stores stalled on store forwarding.
  // Engaged from the start and reset() where there is no sample: a default-constructed optional
  // had GCC zero its whole 128-byte storage (rep stos) at every call, before emplace() wrote it.
  std::optional<LightLiSample> result(std::in_place);
  if (!(area_ > 0.0f) || !emission_) {
    result.reset();
    return result;
  }
  const Vec2 b = sampleUniformTriangle(u);
  const Vec3 pLight = interpolate(desc_.p0, desc_.p1, desc_.p2, b);  // pointAt's, without its EmitterPoint
  const Vec3 toLight = pLight - refPoint;
  const float dist2 = lengthSquared(toLight);
  if (!(dist2 > 0.0f)) {
    result.reset();
    return result;
  }
  const float dist = std::sqrt(dist2);
  const Vec3 wi = toLight / dist;
  const float cosFront = -dot3(wi, n_);
  const float cosLight = desc_.twoSided ? std::fabs(cosFront) : cosFront;
  if (!(cosLight > 0.0f)) {  // the back side emits nothing (unless two-sided)
    result.reset();
    return result;
  }
  const float pdfW = areaToSolidAnglePdf(pdfA_, dist2, cosLight);
  if (!std::isfinite(pdfW)) {  // grazing: the density overflows
    result.reset();
    return result;
  }
  LightLiSample& s = *result;
  s.radianceDeferred = true;
  s.wi = wi;
  s.pLight = pLight;
  s.pLightError = pointError_;
  s.nLight = cosFront >= 0.0f ? n_ : -n_;  // the side that faces refPoint
  s.distance = dist;
  s.pdfW = pdfW;
  return result;
}

Spectrum TriangleLight::deferredRadiance(const LightLiSample& sample, const Wavelengths& lambda) const {
  if (!sample.radianceDeferred) return sample.L;
  EmitterPoint e;
  e.p = sample.pLight;
  e.n = n_;
  e.primitive = desc_.primitive;
  e.w = -sample.wi;
  if (emissionReadsHit_) placeOnGeometry(e, barycentricsOf(sample.pLight));
  return emission_->radiance(e, lambda);
}

std::optional<LightLiSample> TriangleLight::sampleLi(const Vec3& refPoint, Vec2 u, const Wavelengths& lambda) const {
  std::optional<LightLiSample> s = sampleLiDeferred(refPoint, u, lambda);
  if (s) {
    s->L = deferredRadiance(*s, lambda);
    s->radianceDeferred = false;
  }
  return s;
}

float TriangleLight::pdfLi(const Vec3& refPoint, const Vec3& wi, const EmitterPoint* onLight) const {
  (void)wi;
  if (!onLight || !(area_ > 0.0f)) return 0.0f;
  const Vec3 toLight = onLight->p - refPoint;
  const float dist2 = lengthSquared(toLight);
  if (!(dist2 > 0.0f)) return 0.0f;
  const float cosFront = -dot3(toLight, n_) / std::sqrt(dist2);
  const float cosLight = desc_.twoSided ? std::fabs(cosFront) : cosFront;
  if (!(cosLight > 0.0f)) return 0.0f;
  const float pdfW = areaToSolidAnglePdf(pdfA_, dist2, cosLight);
  return std::isfinite(pdfW) ? pdfW : 0.0f;
}

std::optional<LightLeSample> TriangleLight::sampleLe(Vec2 uPos, Vec2 uDir, const Wavelengths& lambda) const {
  if (!(area_ > 0.0f) || !emission_) return std::nullopt;
  EmitterPoint e = pointAt(sampleUniformTriangle(uPos));
  // A two-sided triangle picks its side with uDir.x (then stretched back to [0,1)).
  Vec3 side = n_;
  float sideProbability = 1.0f;
  if (desc_.twoSided) {
    sideProbability = 0.5f;
    if (uDir.x < 0.5f) {
      uDir.x = 2.0f * uDir.x;
    } else {
      uDir.x = std::min(2.0f * uDir.x - 1.0f, 0x1.fffffep-1f);
      side = -n_;
    }
  }
  const Vec3 wLocal = sampleCosineHemisphere(uDir);
  if (!(wLocal.z > 0.0f)) return std::nullopt;
  LightLeSample s;
  s.ray.origin = e.p;
  s.ray.direction = Frame::fromNormal(side).toWorld(wLocal);
  s.nLight = side;
  e.w = s.ray.direction;
  s.L = emission_->radiance(e, lambda);
  s.pdfPosA = pdfA_;
  s.pdfDirW = sideProbability * cosineHemispherePdfW(wLocal.z);
  return s;
}

void TriangleLight::pdfLe(const Ray& ray, const Vec3& nLight, float& pdfPosA, float& pdfDirW) const {
  (void)nLight;
  pdfPosA = pdfA_;
  const float cosFront = dot3(ray.direction, n_);
  pdfDirW = desc_.twoSided ? 0.5f * cosineHemispherePdfW(std::fabs(cosFront)) : cosineHemispherePdfW(cosFront);
}

std::unique_ptr<Light> makeTriangleLight(const TriangleLightDesc& desc, const EmissionSource* emission) {
  return std::make_unique<TriangleLight>(desc, emission);
}

}  // namespace tex::render
