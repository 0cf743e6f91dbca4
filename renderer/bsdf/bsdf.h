// Surface scattering: BSDF lobes and their weighted mixture at one shading point.
//
// Conventions (as in pbrt-v4 and Veach's thesis):
//  - Directions are unit vectors pointing away from the surface, in the local shading frame
//    (z = shading normal) inside lobes, in world space in Bsdf's interface.
//  - f(wo, wi) is the BSDF value; the measure of pdfs is solid angle (pdfW).
//  - Specular (Dirac) lobes: sample() returns f = R / |cos(wi)| and pdfW = the discrete
//    probability of having picked that event, so f |cos| / pdf is the usual weight; eval()
//    and pdf() of a specular lobe are 0.
//  - TransportMode::Radiance: wo points toward the camera side of the path (the path carries
//    radiance); TransportMode::Importance: the path came from a light. Refraction scales
//    radiance by 1/eta^2 only in Radiance mode (non-symmetric BSDF of refraction, Veach 5.2).
//  - Spectral: every value is per wavelength of the path's group. A lobe whose sampled
//    direction depends on the wavelength (a dielectric whose IOR varies with it: dispersion)
//    samples with the hero wavelength (lane 0) and reports `dispersive`; the integrator then
//    handles the other lanes (terminate them, or spectral MIS in a later issue).
//    SmoothDielectric with etaVaries: only refraction is dispersive; its f has lanes 1.. set to
//    0 (the hero-only estimate), so they cannot be misused. Its reflection is not dispersive
//    (the mirror direction is the same for all wavelengths): every lane carries its own
//    Fresnel R_i / |cos| over the hero's event probability R_0, an unbiased per-lane estimate.
//  - Degenerate geometry (|cos| < 1e-6 with either normal, zero or NaN directions) gives no
//    sample and a value and pdf of 0, never NaN or infinity.
#pragma once
#include <cstdint>
#include <optional>

#include "renderer/core/geometry.h"
#include "renderer/core/spectrum.h"

namespace tex::render {

enum class TransportMode : uint8_t { Radiance, Importance };

enum class LobeKind : uint8_t {
  Lambertian,         // albedo = weight
  SmoothDielectric,   // eta = a (interior IOR over exterior, per wavelength); weight scales both R and T;
                      // b is what the transmission loses at each crossing, 1 - its tint (0: clear)
  SmoothConductor,    // complex IOR eta + i k: eta = a, k = b; weight scales the Fresnel reflectance
  // The materials issue's lobes (renderer/bsdf/microfacet*.cpp, glossy_lobe.cpp):
  RoughConductor,     // GGX, alpha = roughness; eta = a, k = b
  RoughDielectric,    // GGX reflection and transmission, alpha = roughness; eta = a, and b what
                      // the transmission loses, 1 - its tint (0: clear; as for SmoothDielectric)
  ThinDielectric,     // a thin slab (both interfaces, internal bounces summed); eta = a, b tints
                      // the transmission only (1: untinted)
  RoughThinDielectric,  // a rough thin slab (GGX, alpha = roughness); eta = a, transmission tint b
  GlossyReflection,   // the glossy model (docs/glossy-model.md): exponent n, reflectance = weight
  GlossyDielectric,   // the glossy model around both the mirror and the refracted direction; eta = a
  // Sheen (renderer/bsdf/sheen_lobe.h): the Charlie sheen, colour = weight, alpha = roughness; and
  // a Lambertian base under one: albedo = weight, the sheen's colour = a, its alpha = roughness.
  Sheen,
  LambertianUnderSheen,
};

// One lobe with its weight. Kinds are native renderer code; materials select them through the
// closure tree a compiled .tex material returns (renderer/material/).
struct Lobe {
  LobeKind kind = LobeKind::Lambertian;
  bool etaVaries = false;  // eta differs between the group's wavelengths (dielectrics)
  Spectrum weight;         // multiplies the lobe's value (albedo of Lambertian)
  Spectrum a, b;           // kind-specific parameters (above)
  float roughness = 0;     // GGX alpha (Rough*); with roughnessY, alpha along the anisotropy axis
  float roughnessY = 0;    // Rough* GGX alpha across the axis (0: isotropic, roughness in every direction)
  float anisotropyRotationRad = 0;  // the axis: local x turned toward y by this angle
  float exponent = 0;      // glossiness exponent n (Glossy*)
  bool underCoat = false;  // a base lobe of a layer: attenuated by the Bsdf's coat (setCoat)
};

struct BsdfSample {
  Spectrum f;             // BSDF value (see specular convention above)
  Vec3 wi;                // sampled direction
  float pdfW = 0;         // solid-angle density (or discrete probability for specular)
  bool specular = false;  // a Dirac event: skip NEE/MIS at this vertex
  bool transmission = false;
  bool dispersive = false;  // direction chosen with the hero wavelength only (see above); for
                            // non-specular samples: the density differs between lanes (a rough
                            // or glossy lobe with etaVaries), f carries every lane's own value
                            // and Bsdf::pdfForLane gives each lane's density
  float etaScale = 1;       // relative IOR crossed (for Russian roulette bookkeeping): 1 if reflected
  // Through a smooth thin wall, not under a coat: the ray goes on unchanged (wi = -wo) and the
  // event's expected weight is Bsdf::straightThrough, what shadow rays take when they pass such
  // a wall (the path tracer MISes the two ways to such a path).
  bool straight = false;
};

// Single-lobe routines in the local frame (z = normal). u2 picks the direction, uc picks a
// discrete event (reflection vs refraction).
Spectrum lobeEval(const Lobe& lobe, const Vec3& wo, const Vec3& wi, TransportMode mode);
float lobePdf(const Lobe& lobe, const Vec3& wo, const Vec3& wi, TransportMode mode);
std::optional<BsdfSample> lobeSample(const Lobe& lobe, const Vec3& wo, float uc, Vec2 u2, TransportMode mode);
inline bool lobeIsSpecular(LobeKind kind) {
  return kind == LobeKind::SmoothDielectric || kind == LobeKind::SmoothConductor || kind == LobeKind::ThinDielectric;
}
// The density lobeSample would have had for wi if lane `lane`'s parameters (its eta) had
// chosen the direction instead of the hero's (lane 0): spectral MIS over the group needs it.
// Equal to lobePdf for lobes that do not depend on the wavelength.
float lobePdfForLane(const Lobe& lobe, const Vec3& wo, const Vec3& wi, TransportMode mode, int lane);

// Fresnel reflectance of a dielectric interface for cosThetaI (relative to the side the light
// arrives from; negative = from inside) and relative IOR eta = n_inside / n_outside.
float fresnelDielectric(float cosThetaI, float eta);
// Fresnel reflectance of a conductor, unpolarised, for complex IOR eta + i k (per lane).
Spectrum fresnelConductor(float cosThetaI, const Spectrum& eta, const Spectrum& k);

// A mixture of up to kMaxLobes weighted lobes at one shading point, with the shading frame
// and the geometric normal (for the adjoint shading-normal correction and for leaks: an
// evaluated direction must be on a side that agrees with both normals' reflect/transmit
// classification).
class Bsdf {
 public:
  static constexpr int kMaxLobes = 8;

  Bsdf() = default;
  Bsdf(const Frame& shadingFrame, const Vec3& geometricNormal) : frame_(shadingFrame), ng_(geometricNormal) {}

  // Adds a lobe (its weight already includes mix weights). Returns false when full.
  bool add(const Lobe& lobe);
  // Layered coat (docs/layering.md; an energy-aware approximation, not a simulation of the
  // layer): a SmoothDielectric or RoughDielectric interface (eta = a, alpha = roughness,
  // weight scales its reflection) over the lobes added with `underCoat`. The coat contributes
  // its reflection only; base lobes are scaled by (1 - F(cos_o)) (1 - F(cos_i)) / (1 - F_avg)
  // per lane, evaluated at the unrefracted directions (a white Lambertian under a smooth coat
  // then has albedo exactly 1; a rough coat loses what single-scattering GGX loses). Sampling
  // picks the coat with share F_hero(cos_o) of its weight and the coated lobes with share
  // 1 - F_hero(cos_o) of theirs. One coat per Bsdf: returns false for a second coat or
  // another kind. Lobes flagged underCoat without a coat are not attenuated.
  bool setCoat(const Lobe& coat);
  // setCoat for a coat present on a fraction `coverage` (per lane, in [0, 1]) of the surface
  // (covers.h: the base lobes take (1 - k) + k T; the coat's weight should carry k): glTF's
  // KHR_materials_specular factor, `layer(scale_material(dielectric(..), k), base)`.
  bool setPartialCoat(const Lobe& coat, const Spectrum& coverage);
  bool hasCoat() const { return hasCoat_; }
  // Layers over every lobe and the coat (covers.h; glTF's clearcoat and sheen over a layered
  // base). setClearcoat: a SmoothDielectric or RoughDielectric interface (eta = a, alpha =
  // roughness; weight scales its reflection and should carry the coverage) on a fraction
  // `coverage` of the surface; false for a second one or another kind. It shades in the Bsdf's
  // frame unless setClearcoatFrame gives its own (glTF's clearcoatNormalTexture).
  bool setClearcoat(const Lobe& interface, const Spectrum& coverage);
  void setClearcoatFrame(const Frame& worldFrame);
  bool hasClearcoat() const { return covered_ && covers_.c.hasClearcoat; }
  // What reaches wo (world) of an emission under the clearcoat: 1 - k F(cos) per lane, the
  // coat's Fresnel at wo's cosine with its own normal (KHR_materials_clearcoat: "coated_emission
  // = emission (1 - clearcoat clearcoat_fresnel)", with the exact Fresnel as the coat's other
  // factors). 1 without a clearcoat.
  Spectrum clearcoatEmissionFactor(const Vec3& woWorld) const;
  const Lobe& clearcoat() const { return covers_.c.clearcoat; }
  // A sheen cover: every lobe but the Sheen lobes (the sheen itself, added as a lobe) and the
  // coat are scaled by what a sheen of this colour (per lane) and alpha does not reflect.
  bool setSheenCover(const Spectrum& colour, float alpha);
  bool hasSheenCover() const { return covered_ && covers_.c.hasSheenCover; }
  // Replaces this Bsdf's lobes and coat by `other`'s, keeping its own frame and normal: a
  // Bsdf without lobes then behaves as if `other`'s had been added to it (replaying a memoised
  // material evaluation, renderer/material/material_memo.h). Storage past the lobe count, and
  // the coat's without a coat, is not copied (nothing reads it).
  void copyLobesFrom(const Bsdf& other);
  const Lobe& coat() const { return coat_; }
  int lobeCount() const { return count_; }
  const Lobe& lobe(int i) const { return storage_.lobes[i]; }
  // No lobe and no coat (a coat over a black base, whose lobe was dropped, still reflects).
  bool empty() const { return count_ == 0 && !hasCoat_ && !hasClearcoat(); }
  bool hasNonSpecular() const { return hasNonSpecular_; }
  // A non-specular lobe whose density differs between the group's lanes (rough or glossy
  // dispersive: etaVaries).
  bool hasDispersiveDensity() const { return hasDispersiveDensity_; }
  const Frame& frame() const { return frame_; }
  const Vec3& geometricNormal() const { return ng_; }

  // World-space interface. eval includes no cosine; the integrator multiplies |cos| with the
  // shading normal. In Importance mode the shading-normal correction
  // |wo.ns| |wi.ng| / (|wo.ng| |wi.ns|) is applied (Veach 1997, section 5.3). Directions on
  // which the two normals disagree (reflection by one, transmission by the other: a leak) have
  // f = 0 and pdf = 0, and sample() drops them, so pdf() is the density sample() really has.
  Spectrum eval(const Vec3& woWorld, const Vec3& wiWorld, TransportMode mode) const;
  float pdf(const Vec3& woWorld, const Vec3& wiWorld, TransportMode mode) const;
  // eval() and pdf() of one pair of directions at once (next-event estimation needs both): one
  // change of frame and one side test; each value bit for bit the one eval() / pdf() returns.
  Spectrum evalWithPdf(const Vec3& woWorld, const Vec3& wiWorld, TransportMode mode, float& pdfW) const;
  // pdf() as if lane `lane` had been the hero wavelength (lobePdfForLane per lobe).
  float pdfForLane(const Vec3& woWorld, const Vec3& wiWorld, TransportMode mode, int lane) const;
  // Chooses a lobe with probability proportional to its selection weight (the mean of |weight|
  // over the group, computed as the sum over all 8 lanes since unused lanes are zero), samples
  // it, and returns the mixture's f and pdf for the chosen direction (for non-specular choices:
  // all non-specular lobes' f and their selection-weighted pdfs summed; for a specular choice:
  // that lobe's f and its event probability times its selection probability). uc picks the
  // lobe and is then stretched back to [0,1) for the lobe's own discrete choice.
  std::optional<BsdfSample> sample(const Vec3& woWorld, float uc, Vec2 u2, TransportMode mode) const;
  // What passes straight through along wWorld (either way), unbent, as a Dirac event: the
  // smooth thin walls' transmission weight (1 - R') tint, summed; 0 for everything else (and
  // for lobes under a coat). A shadow ray toward a point or directional light, which no BSDF
  // sample can find, goes on through such a surface with this factor.
  Spectrum straightThrough(const Vec3& wWorld) const;
  // The surface sits in a medium of IOR `outside` (per lane; 1 in unused lanes) instead of air:
  // every interface's IOR becomes relative to it (dielectric lobes, thin walls and the coat
  // divide eta by it, conductors eta and k), so that water in glass refracts by 1.33 / 1.5.
  // `outsideVaries`: the medium is dispersive, so the relative IORs vary between lanes.
  void immerse(const Spectrum& outside, bool outsideVaries);

 private:
  // The helpers below are inline (defined in bsdf.cpp, the only file that calls them): as calls,
  // with their results passed back through memory, they cost 0.5 % of a Cornell render.
  static inline float selectionWeight(const Lobe& lobe);
  // Selection weights for this wo of the lobes and, at index count_, of the coat; the total.
  inline float componentWeights(const Vec3& wo, float* weights) const;
  // Picks the component sample() uses for uc (-1: no weight at this wo); fills the weights
  // and total of componentWeights and uc stretched to the chosen component's interval.
  inline int chooseComponent(const Vec3& wo, float uc, float* weights, float& total, float& ucLobe) const;
  // One Lambertian lobe and no coat: the mixture's f and pdf are the lobe's own.
  bool isLoneLambertian() const {
    return count_ == 1 && !hasCoat_ && !covered_ && storage_.lobes[0].kind == LobeKind::Lambertian;
  }
  // The covered counterparts (covers.h), used when covered_: the paths above stay as they were.
  Spectrum localEvalCovered(const Vec3& wo, const Vec3& wi, TransportMode mode) const;
  float componentWeightsCovered(const Vec3& wo, float* weights) const;
  // The factor of a specular sample of component `chosen` (a lobe, or count_: the coat).
  Spectrum coverFactorOfSpecular(int chosen, const Vec3& wo, const Vec3& wi) const;
  std::optional<BsdfSample> clearcoatSample(const Vec3& wo, Vec2 u2) const;
  Vec3 toClearcoat(const Vec3& local) const;
  Vec3 fromClearcoat(const Vec3& clearcoatLocal) const;
  void startCovers();
  void updateTwoCoatAverage();
  // Sum of the non-specular lobes' values (base lobes attenuated by the coat) and the coat's.
  inline Spectrum localEval(const Vec3& wo, const Vec3& wi, TransportMode mode) const;
  // Selection-weighted density of the non-specular components (lane: which eta is the hero),
  // for componentWeights' weights and total at this wo.
  inline float localPdf(const Vec3& wo, const Vec3& wi, TransportMode mode, int lane, const float* weights, float total) const;
  inline float localPdf(const Vec3& wo, const Vec3& wi, TransportMode mode, int lane) const;
  Frame frame_;
  Vec3 ng_{0, 0, 1};
  // The lobes, [0, count_) in use. The storage is not initialised: a Bsdf is built at every
  // hit, and zeroing all kMaxLobes lobes (1.3 KB of its 1.6) showed in the path tracer profile.
  union LobeStorage {
    LobeStorage() {}
    Lobe lobes[kMaxLobes];
  } storage_;
  int count_ = 0;
  Lobe coat_;
  bool hasCoat_ = false;
  // What add() and setCoat() learn once instead of at every query: each lobe's selection
  // weight (selectionWeight), the coat's, and the flags the integrator asks for per vertex.
  float selection_[kMaxLobes] = {};
  float coatSelection_ = 0;
  bool hasNonSpecular_ = false;
  bool hasDispersiveDensity_ = false;  // a non-specular lobe with etaVaries
  // The layers over the whole mixture (covers.h). Left unconstructed unless covered_ (as the
  // lobes are: most Bsdfs have none, and are built at every hit).
  struct Covers {
    Spectrum coatCoverage;  // k of the coat (1 without setPartialCoat)
    bool hasClearcoat;
    Lobe clearcoat;
    Spectrum clearcoatCoverage;
    float clearcoatSelection;
    bool clearcoatOwnFrame;
    Frame clearcoatFrame;     // in the Bsdf's local coordinates
    Spectrum twoCoatAverage;  // twoCoatAverageTransmission, with a coat and a clearcoat
    bool hasSheenCover;
    Spectrum sheenColour;
    float sheenAlpha;
  };
  union CoverStorage {
    CoverStorage() {}
    Covers c;
  } covers_;
  bool covered_ = false;
};

}  // namespace tex::render
