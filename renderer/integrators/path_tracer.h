// The spectral path tracer: a stream kernel from a sample index to one sample record.
// Unidirectional paths from the camera with next-event estimation to one light per vertex
// (chosen by the light sampler: docs/light-sampling.md) and multiple importance sampling (power heuristic) between light and BSDF
// sampling (Veach 1997, chapter 9); Russian roulette on the path throughput after
// `rouletteDepth` bounces; `maxDepth` bounces at most. A path carries a group of wavelengths;
// a dispersive scattering event samples its direction with the hero wavelength; the other
// wavelengths are kept and weighted by multiple importance sampling over the group (the
// one-sample balance heuristic over "which lane was the hero": each lane's estimate is divided
// by the group's mean path pdf instead of the hero's), or dropped (SpectralMode).
// Non-finite estimates are replaced by zero and counted.
#pragma once
#include <cstdint>
#include <optional>
#include <string>

#include "renderer/film/sample_record.h"
#include "renderer/integrators/camera_media.h"
#include "renderer/integrators/medium_stack.h"
#include "renderer/integrators/path_counters.h"
#include "renderer/integrators/render_scene.h"
#include "renderer/sampling/sampler.h"
#include "runtime/stream.h"

namespace tex::render {

// What a path does with its wavelength group at wavelength-dependent (dispersive) events.
enum class SpectralMode : uint8_t {
  Mis,        // keep every wavelength: weight each by MIS over the group's pdfs (the thesis);
              // a perfectly specular dispersive interface still keeps only the hero
  Terminate,  // keep only the hero from the first dispersive event on (pbrt-v4)
  Single,     // one wavelength per path from the start
};
const char* spectralModeName(SpectralMode mode);
std::optional<SpectralMode> parseSpectralMode(const std::string& name);

struct PathTracerSettings {
  int maxDepth = 8;       // scattering events; 1 = direct lighting only
  int rouletteDepth = 3;  // Russian roulette may end a path after this many scattering events
  int wavelengths = 4;    // 4 or 8
  // false: BSDF sampling only (emission found by hitting it, weight 1) — the reference the MIS
  // estimator is tested against; it cannot see point or directional lights.
  bool nextEventEstimation = true;
  SpectralMode spectralMode = SpectralMode::Mis;
  // How next-event estimation chooses a light: by its estimated contribution at the point
  // (the light BVH) or by power alone (renderer/lights/light_sampler.h).
  LightSelection lightSelection = LightSelection::Bvh;
  // The camera image's pixel grid, for the pixel footprint of camera rays (ray differentials at
  // the first hit; textures filter with it). 0: no differentials.
  int filmWidth = 0, filmHeight = 0;
  // The window of the camera image the film covers (fractions of it, x right, y down): the
  // samples' film positions span the window, and their records' positions are relative to it.
  // The whole image by default; filmWidth/filmHeight stay the whole image's pixels.
  struct Window {
    float x0 = 0, y0 = 0, x1 = 1, y1 = 1;
  } crop;
};

class PathTracer {
 public:
  PathTracer(const RenderScene& scene, const sampling::Sampler& sampler, const PathTracerSettings& settings)
      : scene_(scene),
        sampler_(sampler),
        settings_(settings),
        straightRaysPass_(scene.materials().anyMayPassStraightRays()),
        volumes_(scene.materials().anyTransmitsIntoAVolume()),
        cameraMedia_(volumes_ ? mediaAroundPoint(scene.geometry(), scene.materials(), scene.camera().position(), scene.camera().forward()) : MediumStack()) {}

  SampleRecord record(uint64_t index) const;
  void operator()(uint64_t index, runtime::Emitter<SampleRecord>& out) const { out.emit(record(index)); }
  PathCounters counters() const { return counters_.total(); }

  // Sampler dimensions, laid out so that every 2D pair is the first two of one of the sampler's
  // groups of four (padded_sobol.h: Sobol dimensions 0 and 1, a (0,m,2)-net per pixel): film
  // 0-1 and wavelengths 2 (shared), the hero lane 3, the lens 4-5, then from 8 every bounce
  // takes kDimensionsPerBounce = 8: light 2D (+0, +1), light choice (+2), roulette (+3); BSDF
  // 2D (+4, +5), lobe choice (+6), one unused.
  static constexpr int kHeroLaneDimension = sampling::kFirstKernelDimension;
  static constexpr int kLensDimension = 4;
  static constexpr int kFirstBounceDimension = 8;
  static constexpr int kDimensionsPerBounce = 8;
  static constexpr int kLight2D = 0, kLightChoice = 2, kRoulette = 3, kBsdf2D = 4, kLobeChoice = 6;
  // IndexSampler::independent streams: the light choice's low bits, one per bounce from here.
  static constexpr uint64_t kLightChoiceLowBitsStream = 0x4c49474854ull << 8;

 private:
  // Where the camera ray started, so that the first hit can trace the neighbouring pixels'
  // rays (only paths that hit something need them).
  struct PixelFootprint {
    sampling::FilmPosition film;
    Vec2 uLens{0.0f};
  };
  Spectrum radiance(const sampling::IndexSampler& samples, const Ray& primary, const PixelFootprint& footprint, Wavelengths& lambda,
                    PathCounters& counters) const;

  const RenderScene& scene_;
  sampling::Sampler sampler_;
  PathTracerSettings settings_;
  // Some material may let straight rays through (thin walls): shadow rays toward delta lights
  // then look at what stops them.
  bool straightRaysPass_;
  // Some material transmits into a volume (the medium stack can only fill then).
  bool volumes_;
  // The volumes the camera is inside: every path starts in them.
  MediumStack cameraMedia_;
  CounterRegistry counters_;
};

}  // namespace tex::render
