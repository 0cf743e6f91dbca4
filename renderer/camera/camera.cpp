// Pinhole, thin-lens and orthographic cameras (pbrt-v4, PerspectiveCamera and section 5.4.1 for
// importance; OrthographicCamera). Orthographic: film (x, y) -> the world point
// ((2x - 1) halfX, (1 - 2y) halfY, 0) of the camera plane, every ray along -z.
//
// Camera space: x right, y up, looking down -z (glTF). The film [0,1)^2 maps onto the image
// plane at distance 1: film (x, y) -> ((2x - 1) tanHalfX, (1 - 2y) tanHalfY, -1). A thin lens
// focuses that plane, scaled by focusDistance, onto the film; a pinhole is the same with a
// lens of radius 0 (its lens "area" is the Dirac's mass, 1).
#include "renderer/camera/camera.h"

#include <cmath>

#include "renderer/core/warp.h"

namespace tex::render {

namespace {

Vec3 normalizedOr(const Vec3& v, const Vec3& fallback) {
  const float len2 = lengthSquared(v);
  return len2 > 1e-20f ? v / std::sqrt(len2) : fallback;
}

}  // namespace

Camera::Camera(const CameraSettings& settings) : settings_(settings) {
  const Mat4& m = settings.cameraToWorld;
  origin_ = Vec3(m[3]);
  // The matrix may scale (glTF node scales): keep only the directions of its axes, made
  // orthonormal so that We stays normalised even under a slight shear.
  forward_ = normalizedOr(-Vec3(m[2]), Vec3(0, 0, -1));
  up_ = normalizedOr(Vec3(m[1]) - forward_ * dot3(forward_, Vec3(m[1])), Vec3(0, 1, 0));
  right_ = glm::cross(forward_, up_);
  if (dot3(right_, Vec3(m[0])) < 0.0f) right_ = -right_;  // a mirroring matrix keeps its x axis
  tanHalfY_ = std::tan(0.5f * settings.yFovRadians);
  tanHalfX_ = tanHalfY_ * (settings.aspect > 0.0f ? settings.aspect : 1.0f);
  filmAreaAtDistance1_ = 4.0f * tanHalfX_ * tanHalfY_;
  orthoHalfY_ = settings.orthoHalfHeight;
  orthoHalfX_ = orthoHalfY_ * (settings.aspect > 0.0f ? settings.aspect : 1.0f);
  orthoFilmArea_ = 4.0f * orthoHalfX_ * orthoHalfY_;
}

namespace {

// The lens "area" in We and pdfPosA: pi r^2, or the Dirac's mass 1 for a pinhole.
float lensAreaOf(const CameraSettings& s) { return s.lensRadius > 0.0f ? kPi * s.lensRadius * s.lensRadius : 1.0f; }
float focusDistanceOf(const CameraSettings& s) { return s.lensRadius > 0.0f ? s.focusDistance : 1.0f; }

}  // namespace

CameraRay Camera::generateRay(sampling::FilmPosition film, Vec2 uLens) const {
  if (isOrthographic()) {
    CameraRay out;
    out.ray.origin = origin_ + right_ * ((2.0f * film.x - 1.0f) * orthoHalfX_) + up_ * ((1.0f - 2.0f * film.y) * orthoHalfY_);
    out.ray.direction = forward_;
    return out;
  }
  const float px = (2.0f * film.x - 1.0f) * tanHalfX_;
  const float py = (1.0f - 2.0f * film.y) * tanHalfY_;
  CameraRay out;
  if (isPinhole()) {
    out.ray.origin = origin_;
    out.ray.direction = glm::normalize(right_ * px + up_ * py + forward_);
    return out;
  }
  // Every ray through the film point meets the others on the plane of focus.
  const float fd = settings_.focusDistance;
  const Vec2 lens = settings_.lensRadius * sampleConcentricDisk(uLens);
  const Vec3 pLensLocal(lens.x, lens.y, 0.0f);
  const Vec3 pFocusLocal(px * fd, py * fd, -fd);
  const Vec3 d = pFocusLocal - pLensLocal;
  out.ray.origin = origin_ + right_ * lens.x + up_ * lens.y;
  out.ray.direction = glm::normalize(right_ * d.x + up_ * d.y - forward_ * d.z);
  return out;
}

// Where a point of the orthographic camera's plane (relative to its centre) is on the film.
namespace {
bool orthoFilm(const Vec3& local, const Vec3& right, const Vec3& up, float halfX, float halfY,
               sampling::FilmPosition& film) {
  film.x = 0.5f * (dot3(local, right) / halfX + 1.0f);
  film.y = 0.5f * (1.0f - dot3(local, up) / halfY);
  return film.x >= 0.0f && film.x < 1.0f && film.y >= 0.0f && film.y < 1.0f;
}
// The direction a ray must have to carry an orthographic camera's importance (its Dirac),
// to within float rounding of a normalised direction.
constexpr float kOrthoDirectionCos = 1.0f - 1e-6f;
}  // namespace

float Camera::We(const Ray& ray, sampling::FilmPosition* film) const {
  const float cosTheta = dot3(ray.direction, forward_);
  if (!(cosTheta > 0.0f)) return 0.0f;
  if (isOrthographic()) {
    sampling::FilmPosition f;
    if (!(cosTheta >= kOrthoDirectionCos)) return 0.0f;
    const Vec3 local = ray.origin - origin_;
    if (!orthoFilm(local - forward_ * dot3(local, forward_), right_, up_, orthoHalfX_, orthoHalfY_, f)) return 0.0f;
    if (film) *film = f;
    return 1.0f / orthoFilmArea_;
  }
  // Where the ray crosses the plane of focus, seen from the lens centre, is its film point.
  const float fd = focusDistanceOf(settings_);
  const Vec3 pFocus = ray.origin + ray.direction * (fd / cosTheta) - origin_;
  const float px = dot3(pFocus, right_) / fd, py = dot3(pFocus, up_) / fd;
  const float fx = 0.5f * (px / tanHalfX_ + 1.0f);
  const float fy = 0.5f * (1.0f - py / tanHalfY_);
  if (!(fx >= 0.0f && fx < 1.0f && fy >= 0.0f && fy < 1.0f)) return 0.0f;
  if (film) *film = {fx, fy};
  const float cos2 = cosTheta * cosTheta;
  return 1.0f / (filmAreaAtDistance1_ * lensAreaOf(settings_) * cos2 * cos2);
}

void Camera::pdfWe(const Ray& ray, float& pdfPosA, float& pdfDirW) const {
  pdfPosA = 0.0f;
  pdfDirW = 0.0f;
  if (We(ray, nullptr) == 0.0f) return;
  if (isOrthographic()) {
    pdfPosA = 1.0f / orthoFilmArea_;
    pdfDirW = 1.0f;  // the Dirac in direction
    return;
  }
  const float cosTheta = dot3(ray.direction, forward_);
  pdfPosA = 1.0f / lensAreaOf(settings_);
  // Uniform film points on a plane at distance d: pdfA = 1/(A d^2), dA -> dw by d^2/cos^3.
  pdfDirW = 1.0f / (filmAreaAtDistance1_ * cosTheta * cosTheta * cosTheta);
}

std::optional<CameraWiSample> Camera::sampleWi(const Vec3& refPoint, Vec2 uLens) const {
  if (isOrthographic()) {
    // The only connection is along the view direction, to the point of the film plane that
    // the reference point projects to.
    const Vec3 local = refPoint - origin_;
    const float distance = dot3(local, forward_);
    CameraWiSample s;
    if (!(distance > 0.0f) || !orthoFilm(local - forward_ * distance, right_, up_, orthoHalfX_, orthoHalfY_, s.film))
      return std::nullopt;
    s.pLens = refPoint - forward_ * distance;
    s.wi = -forward_;
    s.distance = distance;
    s.We = 1.0f / orthoFilmArea_;
    s.pdfW = 1.0f;
    return s;
  }
  Vec3 pLens = origin_;
  if (!isPinhole()) {
    const Vec2 lens = settings_.lensRadius * sampleConcentricDisk(uLens);
    pLens += right_ * lens.x + up_ * lens.y;
  }
  Vec3 wi = pLens - refPoint;
  const float dist2 = lengthSquared(wi);
  if (!(dist2 > 0.0f)) return std::nullopt;
  const float dist = std::sqrt(dist2);
  wi /= dist;
  CameraWiSample s;
  s.We = We(Ray{pLens, -wi}, &s.film);
  if (s.We == 0.0f) return std::nullopt;
  s.wi = wi;
  s.pLens = pLens;
  s.distance = dist;
  // Lens area density converted to solid angle at refPoint (pbrt-v4 PerspectiveCamera::SampleWi).
  s.pdfW = dist2 / (absDot(forward_, wi) * lensAreaOf(settings_));
  return s;
}

}  // namespace tex::render
