#include "renderer/integrators/path_tracer.h"

#include <cmath>

#include "renderer/core/warp.h"
#include "renderer/integrators/light_context.h"
#include "renderer/integrators/medium_stack.h"

namespace tex::render {

namespace {

// Keeps only the hero wavelength's estimate (scaled by the group size so that the group's
// average stays unbiased): after a dispersive event only lane 0's direction is right.
void terminateSecondaryWavelengths(Spectrum& beta, int count) {
  beta.v[0] *= float(count);
  for (int i = 1; i < kLanes; ++i) beta.v[i] = 0.0f;
}

// Ray differentials at the first hit (Igehy 1999, as in pbrt-v4 section 10.1): where the
// camera rays of the neighbouring pixels meet the hit's tangent plane, and the uv change that
// goes with it (least squares on dpdu, dpdv).
void addPixelFootprint(ShadingPoint& sp, const Ray& dx, const Ray& dy) {
  const Vec3 n = sp.ng;
  const float d = dot3(n, sp.p);
  const auto onPlane = [&](const Ray& r, Vec3& out) {
    const float denom = dot3(n, r.direction);
    if (std::fabs(denom) < 1e-8f) return false;
    const float t = (d - dot3(n, r.origin)) / denom;
    if (!(t > 0.0f) || !std::isfinite(t)) return false;
    out = r.origin + r.direction * t;
    return true;
  };
  Vec3 px, py;
  if (!onPlane(dx, px) || !onPlane(dy, py)) return;
  sp.dpdx = px - sp.p;
  sp.dpdy = py - sp.p;
  const float a00 = dot3(sp.dpdu, sp.dpdu), a01 = dot3(sp.dpdu, sp.dpdv), a11 = dot3(sp.dpdv, sp.dpdv);
  const float det = a00 * a11 - a01 * a01;
  if (!(std::fabs(det) > 1e-20f)) return;
  const float inv = 1.0f / det;
  const auto solve = [&](const Vec3& dp) {
    const float b0 = dot3(sp.dpdu, dp), b1 = dot3(sp.dpdv, dp);
    return Vec2((a11 * b0 - a01 * b1) * inv, (a00 * b1 - a01 * b0) * inv);
  };
  sp.duvdx = solve(sp.dpdx);
  sp.duvdy = solve(sp.dpdy);
  if (!std::isfinite(sp.duvdx.x + sp.duvdx.y + sp.duvdy.x + sp.duvdy.y)) sp.duvdx = sp.duvdy = Vec2(0.0f);
}

// How a shadow ray along wi from a surface (material, geometric normal ng, the path arriving
// from wo) crosses it: not at all (wi on wo's side, or through a thin wall, which keeps wo's
// medium), into this object's volume (a .tex solid counts: it absorbs nothing), or out of it.
enum class ShadowCrossing { None, Enters, Leaves };
ShadowCrossing shadowCrossing(const MaterialSystem& materials, int material, const Vec3& ng, const Vec3& wo, const Vec3& wi) {
  const bool entering = dot3(wi, ng) < 0.0f;
  if (entering == (dot3(wo, ng) < 0.0f)) return ShadowCrossing::None;
  if (!entering) return ShadowCrossing::Leaves;
  return materials.transmitsIntoAVolume(material) || !materials.mayPassStraightRays(material) ? ShadowCrossing::Enters
                                                                                                 : ShadowCrossing::None;
}

// Beer-Lambert transmittance of an unoccluded shadow ray from a surface (material, geometric
// normal ng, path arriving from wo through segmentMedium) to a light sample. On wo's side it
// travels in segmentMedium; through the surface, into this object's volume when it enters one,
// else into the volume around this object.
Spectrum shadowTransmittance(const MaterialSystem& materials, const MediumStack& media, int material, int segmentMedium,
                             const Vec3& ng, const Vec3& wo, const LightLiSample& ls, const Wavelengths& lambda) {
  int medium = segmentMedium;
  const ShadowCrossing crossing = shadowCrossing(materials, material, ng, wo, ls.wi);
  if (crossing == ShadowCrossing::Enters) medium = material;  // into this object
  else if (crossing == ShadowCrossing::Leaves && media.contains(material))
    medium = media.innermostOutside(material);  // out of it, into what surrounds it
  Spectrum sigmaA;
  if (medium < 0 || !materials.interiorAbsorption(medium, lambda, sigmaA)) return Spectrum(1.0f);
  if (!std::isfinite(ls.distance)) return Spectrum();  // to a light at infinity from inside a volume
  return exp(sigmaA * -ls.distance);
}

// The media a shadow ray from this surface travels through (shadowTransmittance's rule): the
// path's, plus this object's volume when the ray enters it, less it when the ray leaves it.
MediumStack mediaAlongShadowRay(const MaterialSystem& materials, const MediumStack& media, int material, const Vec3& ng,
                                const Vec3& wo, const Vec3& wi) {
  MediumStack along = media;
  const ShadowCrossing crossing = shadowCrossing(materials, material, ng, wo, wi);
  if (crossing == ShadowCrossing::Enters) along.enter(material);
  else if (crossing == ShadowCrossing::Leaves) along.leave(material);
  return along;
}

// Bsdf::immerse in the medium on the other side of this surface from the object's interior,
// when that medium has a known IOR (glTF and pbr solids). Hit from outside: the medium the path
// is in (the same material nested in itself: a null interface). Hit from inside: what surrounds
// the object once it is left; but an object hidden inside a volume entered later (overlaps: the
// one entered last holds the overlap) is immersed in itself, a null interface.
void immerseInOutsideMedium(const MaterialSystem& materials, const MediumStack& media, int material, bool backFace,
                            const Wavelengths& lambda, Bsdf& bsdf) {
  int outside;
  if (!backFace) outside = media.innermost();
  else if (media.innermost() == material || !media.contains(material)) outside = media.innermostOutside(material);
  else outside = material;
  Spectrum eta;
  if (outside < 0 || !materials.interiorIor(outside, lambda, eta)) return;
  bool varies = false;
  for (int i = 1; i < lambda.count; ++i) varies = varies || eta.v[i] != eta.v[0];
  bsdf.immerse(eta, varies);
}

// Writes the continuation ray into the path's own Ray: a returned Ray was assembled on the
// stack in 8- and 4-byte pieces and copied with 16-byte loads, which stalled on store forwarding.
void spawnRayInto(Ray& r, const Vec3& p, const Vec3& ng, const Vec3& pError, const Vec3& direction) {
  r.origin = offsetRayOrigin(p, ng, direction, pError);
  r.direction = direction;
  r.tMax = kInfinity;
}

// A shadow ray from a surface point to a point on a light (offset off the light as well), or to
// infinity for lights at infinity. Toward a point it aims from the offset origin at the offset
// target (pbrt-v4's SpawnRayTo: direction target - origin, unnormalised, tMax 1 - epsilon in
// its parameter): along wi from the offset origin the segment ran parallel to p -> pLight,
// crossed an area light's own plane short of its end at grazing angles and was shadowed by the
// light itself.
Ray shadowRay(const Vec3& p, const Vec3& ng, const Vec3& pError, const LightLiSample& ls) {
  Ray r;
  r.origin = offsetRayOrigin(p, ng, ls.wi, pError);
  r.direction = ls.wi;
  if (!std::isfinite(ls.distance)) {
    r.tMax = kInfinity;
    return r;
  }
  Vec3 target = ls.pLight;
  if (ls.nLight != Vec3(0.0f)) target = offsetRayOrigin(ls.pLight, ls.nLight, -ls.wi, Vec3(ls.pLightError));
  r.direction = target - r.origin;
  r.tMax = 1.0f - 1e-4f;
  if (!(lengthSquared(r.direction) > 0.0f)) {  // the light point is the origin: nothing in between
    r.direction = ls.wi;
    r.tMax = 0.0f;
  }
  return r;
}

// At most this many smooth thin walls in a row are passed as one straight segment, by shadow
// rays and (for MIS) by BSDF-sampled paths alike.
constexpr int kMaxStraightWalls = 16;

// A shadow ray that something stops: when every surface in the way is one a straight ray may
// pass (smooth thin walls: windows), the light arrives times what they let through
// (Bsdf::straightThrough, each wall immersed in the medium around it as the path's own hit
// would be). No BSDF sample can reach a point or directional light, so without this a sun
// behind a window lit nothing; area and environment lights behind a window were found by BSDF
// sampling alone (the path tracer MISes the two: a BSDF sample through a wall keeps the vertex
// before it as the one whose light sampling could have made the path). False when something
// else stops the ray, or after maxWalls walls.
bool passStraightThrough(const SceneGeometry& geometry, const MaterialSystem& materials, const MediumStack& media, Ray ray,
                         const Wavelengths& lambda, int maxWalls, Spectrum& through, PathCounters& counters) {
  const bool toPoint = std::isfinite(ray.tMax);     // else toward a light at infinity
  const Vec3 target = ray.origin + ray.direction;   // toward a point: the segment's end, t = 1
  const Vec3 unit = normalize(ray.direction);
  through = Spectrum(1.0f);
  SurfaceHit wall;
  for (int k = 0;; ++k) {
    ++counters.rays;
    if (!geometry.intersect(ray, wall)) return true;
    if (k >= maxWalls) return false;
    const int material = materials.materialOfPrimitive(wall.primitive);
    if (!materials.mayPassStraightRays(material)) return false;
    Bsdf bsdf(Frame::fromNormalTangent(wall.ns, wall.dpdu), wall.ng);
    Spectrum emission;
    if (!materials.shade(material, RenderScene::shadingPoint(wall), lambda, bsdf, emission)) return false;
    if (!media.empty()) immerseInOutsideMedium(materials, media, material, dot3(unit, wall.ng) > 0.0f, lambda, bsdf);
    through *= bsdf.straightThrough(unit);
    if (through.isBlack()) return false;
    ray.origin = offsetRayOrigin(wall.p, wall.ng, unit, wall.pError);
    if (toPoint) {
      ray.direction = target - ray.origin;
      if (!(dot3(ray.direction, unit) > 0.0f)) return true;  // the wall was at the light
    }
  }
}

}  // namespace

const char* spectralModeName(SpectralMode mode) {
  switch (mode) {
    case SpectralMode::Mis: return "mis";
    case SpectralMode::Terminate: return "terminate";
    case SpectralMode::Single: return "single";
  }
  return "?";
}

std::optional<SpectralMode> parseSpectralMode(const std::string& name) {
  if (name == "mis") return SpectralMode::Mis;
  if (name == "terminate") return SpectralMode::Terminate;
  if (name == "single") return SpectralMode::Single;
  return std::nullopt;
}

SampleRecord PathTracer::record(uint64_t index) const {
  PathCounters& counters = counters_.local();
  SampleRecord rec;
  const sampling::IndexSampler samples(sampler_, index);
  const sampling::FilmPosition film = samples.filmPosition();
  rec.filmX = film.x;
  rec.filmY = film.y;
  rec.weight = 1.0f;
  rec.technique = kTechniqueCamera;
  // The hero lane is picked by dimension 3, stratified jointly with the group's dimension 2.
  // Only a lens reads its dimensions (each group of them costs its set-up: padded_sobol.h).
  const Vec2 uLens = scene_.camera().usesLens() ? Vec2(samples.get(kLensDimension), samples.get(kLensDimension + 1)) : Vec2(0.5f);
  const float uHero = samples.get(kHeroLaneDimension);
  Wavelengths lambda =
      color::sampleWavelengthGroupStratified(samples.get(sampling::kWavelengthDimension), uHero, settings_.wavelengths);
  rec.wavelengthCount = uint8_t(lambda.count);
  // Where the sample lies on the camera's image (the same position without a crop window:
  // 0 + x * 1 is exact).
  const PathTracerSettings::Window& w = settings_.crop;
  const sampling::FilmPosition onImage{w.x0 + film.x * (w.x1 - w.x0), w.y0 + film.y * (w.y1 - w.y0)};
  const CameraRay cr = scene_.camera().generateRay(onImage, uLens);
  Spectrum L;
  if (cr.weight > 0.0f) L = radiance(samples, cr.ray, PixelFootprint{onImage, uLens}, lambda, counters) * cr.weight;
  bool finite = true;
  for (int j = 0; j < lambda.count; ++j) {
    rec.lambdaNm[j] = lambda.lambdaNm[j];
    const float v = lambda.pdfLambda[j] > 0.0f ? L.v[j] / lambda.pdfLambda[j] : 0.0f;
    finite = finite && std::isfinite(v);
    rec.values[j] = v;
  }
  if (!finite) {
    ++counters.nonFiniteSamples;
    for (int j = 0; j < lambda.count; ++j) rec.values[j] = 0.0f;
  }
  return rec;
}

Spectrum PathTracer::radiance(const sampling::IndexSampler& samples, const Ray& primary, const PixelFootprint& footprint, Wavelengths& lambda,
                              PathCounters& counters) const {
  const SceneGeometry& geometry = scene_.geometry();
  const MaterialSystem& materials = scene_.materials();
  const LightSampler& lightSampler = scene_.lightSampler();
  const auto& lights = scene_.lights();
  const int n = lambda.count;

  Spectrum L;
  Spectrum beta;  // throughput divided by the hero's (lane 0's) sampling densities
  for (int i = 0; i < n; ++i) beta.v[i] = 1.0f;
  // Field by field: the camera writes the primary ray with 8-, 4- and 16-byte stores, and the
  // struct copy's 16-byte load of origin + direction.x spanned three of them (a store-forwarding
  // stall per path).
  Ray ray;
  ray.origin = primary.origin;
  ray.direction = primary.direction;
  ray.tMax = primary.tMax;
  bool specularBounce = true;  // the camera vertex counts as specular: emission seen directly
  float prevPdfW = 0.0f;       // the BSDF technique's density of the last direction (for MIS)
  Vec3 prevP = primary.origin;
  Vec3 prevN{0.0f};  // the normal of prevP's light-choice context (light_context.h), for MIS
  bool terminated = false;
  if (settings_.spectralMode == SpectralMode::Single && n > 1) {
    terminateSecondaryWavelengths(beta, n);
    terminated = true;
  }
  // Spectral MIS (one-sample balance heuristic over which lane is the hero): pathPdfRatio[k] is
  // the product over dispersive vertices of pdf_k / pdf_hero, and every contribution is
  // multiplied by spectralWeight = n / sum_k pathPdfRatio[k] (the hero's pdf over the mean).
  float pathPdfRatio[kLanes];
  for (int k = 0; k < kLanes; ++k) pathPdfRatio[k] = 1.0f;
  float spectralWeight = 1.0f;
  // The product of eta_rel^2 over the refractions so far: radiance's 1 / eta_rel^2 is a change
  // of units, not a loss, so Russian roulette judges beta x etaSquared (pbrt-v4's etaScale).
  // Without it paths inside dense glass were ended with probability 1 - 1 / eta^2 and the
  // survivors carried eta^2 (3.5x the noise in a diamond, 5.5x at IOR 3).
  float etaSquared = 1.0f;
  MediumStack media = cameraMedia_;
  int wallsInARow = 0;  // smooth thin walls passed straight since the last vertex that scattered

  // Declared once per path: its default initialisation (a 96-byte rep stos) at every bounce
  // showed in the profile, and intersect() overwrites every field it reports on a hit.
  SurfaceHit hit;
  for (int depth = 0;; ++depth) {
    ++counters.rays;
    if (!geometry.intersect(ray, hit)) {
      for (int li : scene_.environmentLights()) {
        const Spectrum Le = lights[size_t(li)]->Le(ray, lambda);
        if (Le.isBlack()) continue;
        if (specularBounce || !settings_.nextEventEstimation) {
          L += beta * Le * spectralWeight;
        } else {
          const float pdfLight = lightSampler.pmf(settings_.lightSelection, {prevP, prevN}, li) *
                                 lights[size_t(li)]->pdfLi(prevP, ray.direction, nullptr);
          L += beta * Le * (spectralWeight * powerHeuristic(prevPdfW, pdfLight));
        }
      }
      break;
    }
    ShadingPoint sp = RenderScene::shadingPoint(hit);
    const int material = materials.materialOfPrimitive(hit.primitive);
    // The footprint costs two more camera rays: only for materials that can read it.
    if (depth == 0 && settings_.filmWidth > 0 && settings_.filmHeight > 0 && materials.readsPixelFootprint(material)) {
      const sampling::FilmPosition f = footprint.film;
      const CameraRay rx = scene_.camera().generateRay({f.x + 1.0f / float(settings_.filmWidth), f.y}, footprint.uLens);
      const CameraRay ry = scene_.camera().generateRay({f.x, f.y + 1.0f / float(settings_.filmHeight)}, footprint.uLens);
      if (rx.weight > 0.0f && ry.weight > 0.0f) addPixelFootprint(sp, rx.ray, ry.ray);
    }
    const Vec3 wo = -ray.direction;
    Bsdf bsdf(Frame::fromNormalTangent(hit.ns, hit.dpdu), hit.ng);
    Spectrum Le;
    if (!materials.shade(material, sp, lambda, bsdf, Le)) ++counters.materialFailures;
    // Emission under a glTF clearcoat leaves through it (before immersion, as light samples see
    // it; the same predicate as theirs: a .tex material's emission under a coat is not darkened).
    if (!Le.isBlack() && bsdf.hasClearcoat() && materials.emissionUnderClearcoat(material))
      Le *= bsdf.clearcoatEmissionFactor(wo);
    // Inside a volume, this surface's interfaces are with that volume's medium, not air (water
    // in a glass bends light by 1.33 / 1.5; immerseInOutsideMedium says which medium).
    const bool backFace = dot3(ray.direction, hit.ng) > 0.0f;
    if (!media.empty()) immerseInOutsideMedium(materials, media, material, backFace, lambda, bsdf);
    // The cosine is the BSDF's own shading normal's: a normal map replaces the frame, and with
    // the mesh's interpolated normal it had almost no effect on diffuse shading.
    const Vec3 shadingNormal = bsdf.frame().n;
    // Absorption along the segment that ended here (KHR_materials_volume): inside the innermost
    // volume the path entered, or, having entered none (a camera inside glass), inside the
    // object whose back the ray reached. Shadow rays leaving on wo's side travel in it too.
    const int segmentMedium = !media.empty() ? media.innermost() : backFace ? material : -1;
    Spectrum sigmaA;
    const bool absorbing = segmentMedium >= 0 && materials.interiorAbsorption(segmentMedium, lambda, sigmaA);
    if (absorbing) beta *= exp(sigmaA * -hit.t);

    // Emission seen by this path: MIS against the light sampling of the previous vertex.
    if (!Le.isBlack() && (dot3(wo, hit.ng) > 0.0f || materials.emitsBothSides(material))) {
      if (specularBounce || !settings_.nextEventEstimation) {
        L += beta * Le * spectralWeight;
      } else {
        const int li = scene_.areaLightAt(hit);
        float pdfLight = 0.0f;
        if (li >= 0) {
          EmitterPoint ep{hit.p, hit.ng, hit.primitive};
          pdfLight = lightSampler.pmf(settings_.lightSelection, {prevP, prevN}, li) *
                     lights[size_t(li)]->pdfLi(prevP, ray.direction, &ep);
        }
        L += beta * Le * (spectralWeight * powerHeuristic(prevPdfW, pdfLight));
      }
    }
    if (depth >= settings_.maxDepth || bsdf.empty()) break;

    // Whether this vertex's BSDF density differs between the group's lanes (a rough
    // dispersive lobe) and the path still carries them all: then the BSDF technique's density
    // for MIS against light sampling is the mean over the lanes.
    const bool mixLanes = settings_.spectralMode == SpectralMode::Mis && !terminated && n > 1 && bsdf.hasDispersiveDensity();
    const auto bsdfTechniquePdf = [&](const Vec3& wi, float heroPdfW) {
      if (!mixLanes) return heroPdfW;
      float sum = heroPdfW;
      for (int k = 1; k < n; ++k) sum += bsdf.pdfForLane(wo, wi, TransportMode::Radiance, k);
      return sum / float(n);
    };

    const int dim = kFirstBounceDimension + depth * kDimensionsPerBounce;
    // Next-event estimation: one light, chosen for this point (or by power).
    // The light-choice context's normal, kept for MIS at the emitter the path finds next. Only
    // a vertex that samples a light needs it: after any other the next emitter takes weight 1.
    Vec3 lightContextN{0.0f};
    if (settings_.nextEventEstimation && bsdf.hasNonSpecular() && lightSampler.size() > 0) {
      const LightSampleContext lightContext = nextEventContext(bsdf, hit.p, wo);
      lightContextN = lightContext.n;
      // Both choices need more than the sampler's 24 bits (AliasTable::sample, LightBvh::sample):
      // independent low bits below the stratified ones.
      const double uChoice = double(samples.get(dim + kLightChoice)) +
                             double(samples.independent(kLightChoiceLowBitsStream + uint64_t(depth))) * 0x1p-24;
      const auto choice = lightSampler.sample(settings_.lightSelection, lightContext, uChoice);
      if (choice) {
        const Light& light = *lights[size_t(choice->first)];
        const Vec2 u(samples.get(dim + kLight2D), samples.get(dim + kLight2D + 1));
        // The light's radiance (an area light's material emission) only once the sample is
        // known to be visible: most of its cost is spent on samples that are not.
        const std::optional<LightLiSample> ls = light.sampleLiDeferred(hit.p, u, lambda);
        if (ls && ls->pdfW > 0.0f && (ls->radianceDeferred || !ls->L.isBlack())) {
          float bsdfPdfW = 0.0f;  // the BSDF technique's density of wi, for MIS
          const Spectrum f = bsdf.evalWithPdf(wo, ls->wi, TransportMode::Radiance, bsdfPdfW) * absDot(ls->wi, shadingNormal);
          if (!f.isBlack()) {
            ++counters.rays;
            const Ray shadow = shadowRay(hit.p, hit.ng, hit.pError, *ls);
            const bool visible = !geometry.occluded(shadow);
            // Walls passed count as bounces: at most as many as a BSDF-sampled path from here
            // could pass and still reach the light (MIS needs both techniques to reach the
            // same paths).
            const int wallBudget = std::min(kMaxStraightWalls, settings_.maxDepth - depth - 1);
            Spectrum throughWalls;
            const bool pastWalls =
                !visible && straightRaysPass_ && wallBudget > 0 &&
                passStraightThrough(geometry, materials, mediaAlongShadowRay(materials, media, material, hit.ng, wo, ls->wi), shadow,
                                    lambda, wallBudget, throughWalls, counters);
            if (visible || pastWalls) {
              Spectrum Li = ls->radianceDeferred ? light.deferredRadiance(*ls, lambda) : ls->L;
              if (pastWalls) Li *= throughWalls;
              // An unoccluded shadow ray crosses no surface: it travels in one medium, wo's
              // unless it leaves through this surface into another.
              // (Also from outside an absorbing volume, through its rough surface, to a light in it.)
              if (!media.empty() || absorbing || (volumes_ && materials.transmitsIntoAVolume(material)))
                Li *= shadowTransmittance(materials, media, material, segmentMedium, hit.ng, wo, *ls, lambda);
              if (!Li.isBlack()) {
                const float pdfLight = choice->second * ls->pdfW;
                const float weight =
                    ls->delta ? 1.0f
                              : powerHeuristic(pdfLight, bsdfTechniquePdf(ls->wi, bsdfPdfW));
                L += beta * f * Li * (spectralWeight * weight / pdfLight);
              }
            }
          }
        }
      }
    }

    // Continue the path by sampling the BSDF.
    const Vec2 u(samples.get(dim + kBsdf2D), samples.get(dim + kBsdf2D + 1));
    const std::optional<BsdfSample> bs = bsdf.sample(wo, samples.get(dim + kLobeChoice), u, TransportMode::Radiance);
    if (!bs || !(bs->pdfW > 0.0f) || bs->f.isBlack()) break;
    beta *= bs->f * (absDot(bs->wi, shadingNormal) / bs->pdfW);
    if (bs->transmission) {
      etaSquared *= bs->etaScale * bs->etaScale;
      if (bs->etaScale != 1.0f || materials.transmitsIntoAVolume(material)) {
        if (dot3(bs->wi, hit.ng) < 0.0f) media.enter(material);
        else media.leave(material);
      }
    }
    // Straight through a smooth thin wall: the vertex before the wall stays the one whose light
    // sampling (through the wall, passStraightThrough) could have made this path, so an emitter
    // found next is weighted against it; the wall itself is no vertex for MIS. At most
    // kMaxStraightWalls in a row, as shadow rays.
    const bool throughWall =
        bs->straight && straightRaysPass_ && wallsInARow < kMaxStraightWalls && materials.mayPassStraightRays(material);
    wallsInARow = throughWall ? wallsInARow + 1 : 0;
    if (!throughWall) prevPdfW = bs->pdfW;
    if (bs->dispersive && !terminated && n > 1) {
      if (settings_.spectralMode == SpectralMode::Mis && !bs->specular) {
        float sum = 0.0f;
        for (int k = 0; k < n; ++k) {
          if (k > 0) pathPdfRatio[k] *= bsdf.pdfForLane(wo, bs->wi, TransportMode::Radiance, k) / bs->pdfW;
          sum += pathPdfRatio[k];
        }
        spectralWeight = sum > 0.0f ? float(n) / sum : 0.0f;
        prevPdfW = bsdfTechniquePdf(bs->wi, bs->pdfW);
      } else {
        // A Dirac dispersive event (or the terminate mode): only the hero's direction exists.
        // From here the path is the hero's alone (times n), whose estimate f_h / pdf_h takes no
        // spectral MIS weight: one kept from an earlier rough dispersive vertex (n pdf_h / sum_k
        // pdf_k) made each lane's expectation the integral of f_j n pdf_j / sum_k pdf_k (a glass
        // ball in a white furnace reflected 1.1-1.2 of the sky).
        terminateSecondaryWavelengths(beta, n);
        terminated = true;
        spectralWeight = 1.0f;
      }
    }
    if (!throughWall) {  // past a wall, the vertex before it keeps its light-choice context too
      specularBounce = bs->specular;
      prevP = hit.p;
      prevN = lightContextN;
    }
    spawnRayInto(ray, hit.p, hit.ng, hit.pError, bs->wi);

    if (beta.hasNaNOrInf()) {
      ++counters.nonFiniteSamples;
      break;
    }
    if (depth + 1 >= settings_.rouletteDepth) {
      const float survive = std::min(1.0f, beta.maxValue() * spectralWeight * etaSquared);
      if (samples.get(dim + kRoulette) >= survive) break;
      beta = beta / survive;
    }
  }
  return L;
}

}  // namespace tex::render
