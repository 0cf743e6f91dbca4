// Cameras emit importance (design contract 3). The film is the continuous square [0,1)^2
// (x right, y down) mapped onto the image plane; resolution exists only at reconstruction, so
// a camera knows its aspect ratio but not a pixel count.
//
// Measures: pdfPosA is per unit area of the lens (Dirac for a pinhole: reported as 1 and
// flagged), pdfDirW per solid angle. Importance We is normalised so that the film integral of
// a measurement is the pixel value: We(ray) = 1 / (A_film cos^4(theta)) for the image plane
// at distance 1 with area A_film, times 1/(lens area) for a thin lens (pbrt-v4, section 5.4.1).
// An orthographic camera is the other way round: rays leave a film rectangle of area A (world
// units) uniformly, all along the view direction (a Dirac in direction, reported as 1):
// We = 1 / A per unit area, for that one direction.
#pragma once
#include <memory>
#include <optional>

#include "renderer/core/geometry.h"
#include "renderer/sampling/sampler.h"

namespace tex::render {

struct CameraRay {
  Ray ray;
  float weight = 1;  // We cos / (pdfPosA pdfDirW): 1 for the cameras here
};

// A direction from a reference point toward the camera (for light tracing / BDPT splats).
struct CameraWiSample {
  sampling::FilmPosition film;  // where the point lands on the film
  Vec3 wi;                      // from the reference point toward the lens point
  Vec3 pLens;                   // the lens point
  float distance = 0;
  float We = 0;                 // importance arriving at the reference point along -wi
  float pdfW = 0;               // solid-angle density at the reference point (pinhole: the Dirac's mass as 1;
                                // orthographic: 1, the Dirac in direction, with no 1/distance^2)
};

struct CameraSettings {
  Mat4 cameraToWorld{1.0f};  // camera looks down its local -z, y up (glTF convention)
  float yFovRadians = 0.8f;  // vertical field of view
  float aspect = 1.0f;       // width / height of the film
  float lensRadius = 0.0f;   // 0: pinhole
  float focusDistance = 1.0f;
  // > 0: orthographic, with a film this many world units from its centre to its top edge
  // (glTF's ymag; the width follows the aspect); yFovRadians and the lens are then unused.
  float orthoHalfHeight = 0.0f;
};

class Camera {
 public:
  explicit Camera(const CameraSettings& settings);

  const CameraSettings& settings() const { return settings_; }
  bool isOrthographic() const { return settings_.orthoHalfHeight > 0.0f; }
  bool isPinhole() const { return !isOrthographic() && settings_.lensRadius <= 0.0f; }
  // Whether generateRay and sampleWi read uLens (a thin lens; pinhole and orthographic cameras
  // leave those sampler dimensions free).
  bool usesLens() const { return !isOrthographic() && settings_.lensRadius > 0.0f; }
  Vec3 position() const { return origin_; }
  Vec3 forward() const { return forward_; }

  // The primary ray through a film position; uLens picks the lens point (ignored by a pinhole).
  CameraRay generateRay(sampling::FilmPosition film, Vec2 uLens) const;
  // Importance carried by a ray leaving the lens point `ray.origin` in `ray.direction`, and the
  // film position it comes from (nullopt: outside the film or behind the camera).
  float We(const Ray& ray, sampling::FilmPosition* film) const;
  // Densities of generateRay for `ray`: lens area and direction solid angle.
  void pdfWe(const Ray& ray, float& pdfPosA, float& pdfDirW) const;
  // Samples a lens point and returns the connection toward `refPoint`.
  std::optional<CameraWiSample> sampleWi(const Vec3& refPoint, Vec2 uLens) const;

 private:
  CameraSettings settings_;
  Vec3 origin_, right_, up_, forward_;
  float tanHalfY_ = 0, tanHalfX_ = 0, filmAreaAtDistance1_ = 0;
  float orthoHalfX_ = 0, orthoHalfY_ = 0, orthoFilmArea_ = 0;  // orthographic: the film in world units
};

}  // namespace tex::render
