#include "renderer/material/closure_lobes.h"

#include <array>
#include <cmath>

#include "renderer/bsdf/microfacet.h"
#include "renderer/bsdf/sheen_albedo.h"
#include "renderer/spectra/rgb_spectrum.h"

namespace tex::render {

namespace {

constexpr int kArenaCapacity = 64;
constexpr int kMaxSpectrumArgs = 8;

enum class ParamUse { Reflectance, Illuminant, Unbounded };

Spectrum paramSpectrum(compiler::ClosureParam kind, const float* params, const Wavelengths& lambda, ParamUse use) {
  if (kind == compiler::ClosureParam::Spectrum) {
    Spectrum s;
    for (int i = 0; i < lambda.count; ++i) s.v[i] = params[i];
    return s;
  }
  if (kind == compiler::ClosureParam::Color) {
    const Vec3 rgb(params[0], params[1], params[2]);
    switch (use) {
      case ParamUse::Reflectance: return rgbReflectanceSpectrum(rgb, lambda);
      case ParamUse::Illuminant: return rgbIlluminantSpectrum(rgb, lambda);
      case ParamUse::Unbounded: return rgbUnboundedSpectrum(rgb, lambda);
    }
  }
  return Spectrum();
}

struct Walker {
  const compiler::ClosureNode* nodes;
  int32_t nodeCount;
  const Wavelengths& lambda;
  Bsdf* bsdf;  // null: only the emission is wanted (area lights), lobes are skipped
  Spectrum& emission;
  ClosureEvaluation result;
  bool underCoat = false;  // inside the base of a layer whose coat the Bsdf holds
  // A cover (a clearcoat or a sheen cover, Bsdf::setClearcoat, setSheenCover) covers every lobe
  // of the Bsdf: once one's base is walked, nothing may be added beside it.
  bool coverClosed = false;
  // Inside the base of a layer whose coat is a sheen: its colour (per lane, in [0, 1]) and alpha.
  // (A pointer to the Layer case's own spectrum: a Spectrum member, 32-byte aligned, padded the
  // Walker to 96 bytes that its constructor cleared with a rep stos at every shading point.)
  bool underSheen = false;
  const Spectrum* sheenColour = nullptr;
  float sheenAlpha = 0;
  // A constant tree's colours fitted once, parallel to `nodes` (null: fit at each use).
  const std::array<FittedColor, 2>* fitted = nullptr;

  Walker(const compiler::ClosureNode* n, int32_t count, const Wavelengths& l, Bsdf* b, Spectrum& e)
      : nodes(n), nodeCount(count), lambda(l), bsdf(b), emission(e) {}

  // A colour or spectrum parameter with a NaN or infinite component: a failed evaluation (the
  // RGB fit sanitises such colours to 0 or 1, so rgb(NaN) had rendered black uncounted).
  mutable bool nonFiniteParam = false;

  // A node's parameter vector (`second`: params2) as a spectrum for `use`.
  Spectrum param(const compiler::ClosureNode& node, ParamUse use, bool second = false) const {
    const compiler::ClosureParam kind = second ? node.param2Kind : node.paramKind;
    const float* raw = second ? node.params2 : node.params;
    const int rawCount = kind == compiler::ClosureParam::Color ? 3 : kind == compiler::ClosureParam::Spectrum ? lambda.count : 0;
    for (int i = 0; i < rawCount; ++i) nonFiniteParam = nonFiniteParam || !std::isfinite(raw[i]);
    if (fitted && kind == compiler::ClosureParam::Color) {
      const FittedColor& colour = fitted[&node - nodes][second ? 1 : 0];
      switch (use) {
        case ParamUse::Reflectance: return reflectanceSpectrum(colour.reflectance, lambda);
        case ParamUse::Illuminant: return illuminantSpectrum(colour.unbounded, lambda);
        case ParamUse::Unbounded: return unboundedSpectrum(colour.unbounded, lambda);
      }
    }
    return paramSpectrum(kind, second ? node.params2 : node.params, lambda, use);
  }

  // By reference: a by-value Lobe was copied once more through the stack, its 16-byte loads
  // stalling on the byte and float stores that had just built it.
  void addLobe(Lobe& lobe) {
    // A non-finite colour or weight (a NaN albedo from the material's code) is a failed
    // evaluation, counted and reported, not a lobe (it used to render black silently).
    if (lobe.weight.hasNaNOrInf()) {
      result.ok = false;
      return;
    }
    if (lobe.weight.isBlack()) return;
    if (coverClosed) {
      result.ok = false;  // a lobe beside a clearcoat or sheen cover, which covers every lobe
      return;
    }
    lobe.underCoat = underCoat;
    if (!bsdf->add(lobe)) result.ok = false;
  }

  // An IOR parameter: positive per lane (0 or less would be meaningless: index-matched), and
  // dispersive when the compiler says it depends on the wavelength and it differs in the group.
  void iorLanes(const compiler::ClosureNode& node, Lobe& lobe) const {
    lobe.a = param(node, ParamUse::Unbounded);
    for (int i = 0; i < lambda.count; ++i)
      if (!(lobe.a.v[i] > 0.0f)) lobe.a.v[i] = 1.0f;
    bool differs = false;
    for (int i = 1; i < lambda.count; ++i) differs = differs || lobe.a.v[i] != lobe.a.v[0];
    lobe.etaVaries = (node.flags & compiler::kClosureVariesWithWavelength) != 0 && differs;
  }

  // A node's scalar (roughness, exponent): NaN or infinite is a failed evaluation, counted
  // like a non-finite colour (a NaN roughness had rendered as the smooth lobe, a NaN glossy
  // exponent black, both uncounted).
  float scalarOf(const compiler::ClosureNode& node) const {
    const float r = node.scalars[0];
    nonFiniteParam = nonFiniteParam || !std::isfinite(r);
    return r;
  }

  // GGX roughness from the language (clamped: negative means smooth, above 1 is 1; documented
  // in docs/language.md). Below alpha 1e-3 a GGX lobe is a mirror for every practical purpose
  // (and its density would be a spike): treat it as the smooth lobe.
  float roughnessOf(const compiler::ClosureNode& node) const {
    const float r = scalarOf(node);
    return r >= 1e-3f ? std::min(r, 1.0f) : 0.0f;
  }

  // A Dielectric's or Conductor's roughness into the lobe: roughnessOf, or with
  // kClosureAnisotropic the two alphas (each clamped as roughnessOf does; smooth when both are
  // below 1e-3, else neither below kMinGgxAlpha: no lobe is a mirror along one axis only) and
  // the axis' rotation. Returns whether the lobe is rough.
  bool roughnessInto(const compiler::ClosureNode& node, Lobe& lobe) const {
    lobe.roughness = roughnessOf(node);
    if (!(node.flags & compiler::kClosureAnisotropic)) return lobe.roughness > 0.0f;
    const float rv = node.scalars[1], rotation = node.scalars[2];
    nonFiniteParam = nonFiniteParam || !std::isfinite(rv) || !std::isfinite(rotation);
    const float alphaV = rv >= 1e-3f ? std::min(rv, 1.0f) : 0.0f;
    if (lobe.roughness == 0.0f && alphaV == 0.0f) return false;
    lobe.roughness = std::max(lobe.roughness, kMinGgxAlpha);
    lobe.roughnessY = std::max(alphaV, kMinGgxAlpha);
    lobe.anisotropyRotationRad = std::isfinite(rotation) ? rotation : 0.0f;
    return true;
  }

  // The sheen's colour as a reflectance and its alpha (sheen::clampRoughness: [0.01, 1]).
  Spectrum sheenReflectance(const compiler::ClosureNode& node) const {
    return clampZero(param(node, ParamUse::Reflectance));
  }
  // The glossy model's exponent n: negative is 0, and above 1e15 (a mirror for every
  // practical purpose) it is 1e15: glossy_dielectric lost its whole transmission at n = 1e19
  // (float overflow in the lobe), uncounted.
  float glossyExponentOf(const compiler::ClosureNode& node) const {
    return std::min(std::max(scalarOf(node), 0.0f), 1e15f);
  }

  float sheenRoughnessOf(const compiler::ClosureNode& node) const {
    return float(sheen::clampRoughness(scalarOf(node)));
  }

  // Under a sheen coat only Lambertian bases are scaled (sheen_lobe.h); trees of them through
  // mix, scale and add, and emission, are fine.
  static bool allowedUnderSheen(compiler::ClosureKind kind) {
    return kind == compiler::ClosureKind::Diffuse || kind == compiler::ClosureKind::Emission ||
           kind == compiler::ClosureKind::Mix || kind == compiler::ClosureKind::Scale ||
           kind == compiler::ClosureKind::Add;
  }

  // Whether the subtree at `index` holds a node for which `pred` holds (a bounded search: trees
  // are at most kArenaCapacity nodes, shared nodes are searched again within the budget).
  template <class Pred>
  bool subtreeHas(int32_t index, Pred pred, int depth = 0) const {
    if (index < 0 || index >= nodeCount || depth > kArenaCapacity) return false;
    const compiler::ClosureNode& node = nodes[index];
    if (pred(node)) return true;
    switch (node.kind) {
      case compiler::ClosureKind::Mix:
      case compiler::ClosureKind::Add:
      case compiler::ClosureKind::Layer: return subtreeHas(node.a, pred, depth + 1) || subtreeHas(node.b, pred, depth + 1);
      case compiler::ClosureKind::Scale: return subtreeHas(node.a, pred, depth + 1);
      default: return false;
    }
  }

  // A layer's coat, looking through a scale_material: the dielectric node (-1: another kind) and
  // the scale's weight as a coverage in [0, 1] per lane (`partial`: there was a scale).
  int32_t coatInterface(int32_t c, Spectrum& coverage, bool& partial) const {
    partial = false;
    if (c < 0 || c >= nodeCount) return -1;
    if (nodes[c].kind == compiler::ClosureKind::Scale) {
      const compiler::ClosureNode& scale = nodes[c];
      coverage = clampZero(param(scale, ParamUse::Reflectance));
      for (int i = 0; i < kLanes; ++i) coverage.v[i] = std::min(coverage.v[i], 1.0f);
      // Lanes past the group hold lane 0's value: the covers' per-lane work can then share it.
      for (int i = lambda.count; i < kLanes; ++i) coverage.v[i] = coverage.v[0];
      partial = true;
      c = scale.a;
      if (c < 0 || c >= nodeCount) return -1;
    }
    const bool dielectric = nodes[c].kind == compiler::ClosureKind::Dielectric ||
                            nodes[c].kind == compiler::ClosureKind::GlossyDielectric;
    return dielectric ? c : -1;
  }

  // Whether a sheen layer is a cover (covers.h): its base holds more than diffuse materials.
  bool sheenIsACover(const compiler::ClosureNode& layer) const {
    return subtreeHas(layer.b, [](const compiler::ClosureNode& n) { return !allowedUnderSheen(n.kind); });
  }
  // Whether a layer takes the Bsdf's coat or a cover: all but sheens over diffuse bases.
  bool needsTheCoat(const compiler::ClosureNode& layer) const {
    const bool sheen = layer.a >= 0 && layer.a < nodeCount && nodes[layer.a].kind == compiler::ClosureKind::Sheen;
    return !sheen || sheenIsACover(layer);
  }

  // Whether a cover may start here: it must hold every lobe the Bsdf will have.
  bool coverMayStart() const { return !underCoat && !underSheen && !coverClosed && bsdf->lobeCount() == 0 && !bsdf->hasCoat(); }

  // Nodes may be shared (`add_material(m, m)` refers to m twice), so a tree of 64 nodes can
  // stand for 2^63 paths through it: the walk visits at most kVisitBudget nodes, far more than
  // any material that fits the Bsdf's lobes needs, and fails beyond (it hung at 2^30).
  static constexpr int kVisitBudget = 4 * kArenaCapacity;
  int visits = 0;

  void walk(int32_t index, const Spectrum& weight, int depth) {
    if (index < 0 || index >= nodeCount || depth > kArenaCapacity || ++visits > kVisitBudget) {
      result.ok = false;
      return;
    }
    const compiler::ClosureNode& node = nodes[index];
    if (underSheen && bsdf && !allowedUnderSheen(node.kind)) {
      result.ok = false;  // other bases under a sheen are not supported yet
      return;
    }
    switch (node.kind) {
      case compiler::ClosureKind::Diffuse: {
        if (!bsdf) return;
        Lobe lobe;
        lobe.kind = underSheen ? LobeKind::LambertianUnderSheen : LobeKind::Lambertian;
        lobe.weight = weight * clampZero(param(node, ParamUse::Reflectance));
        if (underSheen) {
          lobe.a = *sheenColour;
          lobe.roughness = sheenAlpha;
        }
        addLobe(lobe);
        return;
      }
      case compiler::ClosureKind::Sheen: {
        if (!bsdf) return;
        Lobe lobe;
        lobe.kind = LobeKind::Sheen;
        lobe.roughness = sheenRoughnessOf(node);
        lobe.weight = weight * sheenReflectance(node);
        addLobe(lobe);
        return;
      }
      case compiler::ClosureKind::Emission:
        result.sawEmission = true;
        emission += weight * clampZero(param(node, ParamUse::Illuminant));
        return;
      case compiler::ClosureKind::Mix: {
        if (!std::isfinite(node.weight)) {  // both branches were skipped: black, uncounted
          result.ok = false;
          return;
        }
        const float w = std::clamp(node.weight, 0.0f, 1.0f);
        if (w < 1.0f) walk(node.a, weight * (1.0f - w), depth + 1);
        if (w > 0.0f) walk(node.b, weight * w, depth + 1);
        return;
      }
      case compiler::ClosureKind::Dielectric: {
        if (!bsdf) return;
        Lobe lobe;
        lobe.kind = roughnessInto(node, lobe) ? LobeKind::RoughDielectric : LobeKind::SmoothDielectric;
        lobe.weight = weight;
        iorLanes(node, lobe);
        // The transmission's tint, a filter in [0, 1] per wavelength, kept as what it takes
        // away (b = 1 - tint: lobes made elsewhere, such as coats, stay clear with b = 0).
        const Spectrum tint = clampZero(param(node, ParamUse::Reflectance, true));
        for (int i = 0; i < kLanes; ++i) lobe.b.v[i] = 1.0f - std::min(tint.v[i], 1.0f);
        addLobe(lobe);
        return;
      }
      case compiler::ClosureKind::Conductor: {
        if (!bsdf) return;
        Lobe lobe;
        lobe.kind = roughnessInto(node, lobe) ? LobeKind::RoughConductor : LobeKind::SmoothConductor;
        lobe.weight = weight;
        lobe.a = param(node, ParamUse::Unbounded);
        lobe.b = clampZero(param(node, ParamUse::Unbounded, true));
        addLobe(lobe);
        return;
      }
      case compiler::ClosureKind::ThinDielectric: {
        if (!bsdf) return;
        Lobe lobe;
        const float roughness = roughnessOf(node);
        lobe.kind = roughness > 0.0f ? LobeKind::RoughThinDielectric : LobeKind::ThinDielectric;
        lobe.roughness = roughness;
        lobe.weight = weight;
        // A thin slab does not bend light: a varying IOR changes each lane's R', never a
        // direction (the lobes take every lane's own R' over the hero's event probability).
        iorLanes(node, lobe);
        // The transmission's tint, a filter: in [0, 1] per wavelength (above 1 it would add energy).
        lobe.b = clampZero(param(node, ParamUse::Reflectance, true));
        for (int i = 0; i < kLanes; ++i) lobe.b.v[i] = std::min(lobe.b.v[i], 1.0f);
        addLobe(lobe);
        return;
      }
      case compiler::ClosureKind::Glossy: {
        if (!bsdf) return;
        Lobe lobe;
        lobe.kind = LobeKind::GlossyReflection;
        lobe.exponent = glossyExponentOf(node);
        lobe.weight = weight * clampZero(param(node, ParamUse::Reflectance));
        addLobe(lobe);
        return;
      }
      case compiler::ClosureKind::GlossyDielectric: {
        if (!bsdf) return;
        Lobe lobe;
        lobe.kind = LobeKind::GlossyDielectric;
        lobe.exponent = glossyExponentOf(node);
        lobe.weight = weight;
        iorLanes(node, lobe);
        addLobe(lobe);
        return;
      }
      case compiler::ClosureKind::Layer: {
        if (!bsdf) {
          walk(node.b, weight, depth + 1);  // the base may emit
          return;
        }
        const int32_t c = node.a;
        if (c >= 0 && c < nodeCount && nodes[c].kind == compiler::ClosureKind::Sheen) {
          const compiler::ClosureNode& sheenNode = nodes[c];
          if (sheenIsACover(node)) {
            // A sheen over other bases (glTF's sheen over its layered material): a cover,
            // scaling every lobe below by what the sheen does not reflect (covers.h).
            // Every lobe of the Bsdf but the sheen is scaled: one sheen, over all of them.
            if (!coverMayStart() ||
                subtreeHas(node.b, [](const compiler::ClosureNode& n) { return n.kind == compiler::ClosureKind::Sheen; })) {
              result.ok = false;
              return;
            }
            walk(c, weight, depth + 1);
            Spectrum colour = sheenReflectance(sheenNode);
            for (int i = 0; i < kLanes; ++i) colour.v[i] = std::min(colour.v[i], 1.0f);
            if (!bsdf->setSheenCover(colour, sheenRoughnessOf(sheenNode))) {
              result.ok = false;
              return;
            }
            walk(node.b, weight, depth + 1);
            coverClosed = true;
            return;
          }
          // A sheen over Lambertian bases: the sheen lobe, and the bases scaled by what it
          // does not reflect (LambertianUnderSheen, sheen_lobe.h). Not nested.
          walk(c, weight, depth + 1);
          underSheen = true;
          Spectrum colour = sheenReflectance(sheenNode);
          for (int i = 0; i < kLanes; ++i) colour.v[i] = std::min(colour.v[i], 1.0f);
          sheenColour = &colour;
          sheenAlpha = sheenRoughnessOf(sheenNode);
          walk(node.b, weight, depth + 1);
          underSheen = false;
          sheenColour = nullptr;
          return;
        }
        // The coat must be a dielectric interface (smooth or rough), or one scaled by a
        // coverage (scale_material); the base's lobes are attenuated by its Fresnel
        // transmission (Bsdf::setCoat, docs/layering.md).
        Spectrum coverage(1.0f);
        bool partial = false;
        const int32_t interfaceNode = coatInterface(c, coverage, partial);
        // A coat over a base that needs the Bsdf's coat itself (a dielectric layer, or a sheen
        // cover) is a clearcoat, over everything (covers.h).
        const bool clearcoat = interfaceNode >= 0 && subtreeHas(node.b, [this](const compiler::ClosureNode& n) {
                                 return n.kind == compiler::ClosureKind::Layer && needsTheCoat(n);
                               });
        if (interfaceNode < 0 || underCoat || (clearcoat && !coverMayStart())) {
          result.ok = false;  // coats of other kinds, or nested coats not over everything, are not supported
          return;
        }
        const compiler::ClosureNode& coatNode = nodes[interfaceNode];
        Lobe coat;
        // A glossy-model coat is layered as the GGX coat of matching width (alpha =
        // sqrt(2 / (n + 2)), the usual Phong-to-Beckmann/GGX correspondence): the layering's
        // energy bookkeeping is written for the GGX interface (docs/layering.md).
        bool rough;
        if (coatNode.kind == compiler::ClosureKind::GlossyDielectric) {
          coat.roughness = std::sqrt(2.0f / (std::max(scalarOf(coatNode), 0.0f) + 2.0f));
          rough = coat.roughness > 0.0f;
        } else {
          rough = roughnessInto(coatNode, coat);  // an anisotropic coat keeps its two alphas
        }
        coat.kind = rough ? LobeKind::RoughDielectric : LobeKind::SmoothDielectric;
        coat.weight = partial ? weight * coverage : weight;
        // The coat reflects, so its direction never depends on the IOR; a varying IOR still
        // gives each lane its own Fresnel reflectance and transmittance (layer.cpp).
        iorLanes(coatNode, coat);
        if (clearcoat) {
          if (!bsdf->setClearcoat(coat, coverage)) {
            result.ok = false;
            return;
          }
          walk(node.b, weight, depth + 1);
          coverClosed = true;
          return;
        }
        if (coverClosed || !(partial ? bsdf->setPartialCoat(coat, coverage) : bsdf->setCoat(coat))) {
          result.ok = false;
          return;
        }
        underCoat = true;
        walk(node.b, weight, depth + 1);
        underCoat = false;
        return;
      }
      case compiler::ClosureKind::Scale: {
        const bool bounded = node.paramKind != compiler::ClosureParam::Color ||
                             (node.params[0] <= 1.0f && node.params[1] <= 1.0f && node.params[2] <= 1.0f);
        const Spectrum w = clampZero(param(node, bounded ? ParamUse::Reflectance : ParamUse::Unbounded));
        walk(node.a, weight * w, depth + 1);
        return;
      }
      case compiler::ClosureKind::Add:
        walk(node.a, weight, depth + 1);
        walk(node.b, weight, depth + 1);
        return;
      default:
        result.ok = false;  // a kind this renderer does not know (docs/abi.md: kinds only grow)
        return;
    }
  }
};

}  // namespace

namespace {

// Calls a compiled entry into `arena` (as evaluateEntry): the root, or -1 when the arguments
// do not fit, the arena overflowed or the entry built no material.
int32_t callEntry(compiler::EntryFn entry, const float* extraArgs, int extraWords, const ShadingPoint& point,
                  const Wavelengths& lambda, compiler::ClosureArena& arena) {
  constexpr int kHitWords = int(sizeof(compiler::HitAbi) / sizeof(float));
  constexpr int kMaxExtraWords = kMaxSpectrumArgs * compiler::kMaxWavelengths;
  if (extraWords < 0 || extraWords > kMaxExtraWords) return -1;
  compiler::ShadingContext ctx{};
  for (int i = 0; i < lambda.count; ++i) ctx.lambdaNm[i] = lambda.lambdaNm[i];
  ctx.wavelengthCount = lambda.count;
  ctx.arena = &arena;

  float args[kHitWords + kMaxExtraWords];
  auto* hit = reinterpret_cast<compiler::HitAbi*>(args);
  for (int k = 0; k < 3; ++k) {
    hit->n[k] = point.ns[k];
    hit->p[k] = point.p[k];
    hit->dpdx[k] = point.dpdx[k];
    hit->dpdy[k] = point.dpdy[k];
  }
  for (int k = 0; k < 2; ++k) {
    hit->uv[k] = point.uv[k];
    hit->duvdx[k] = point.duvdx[k];
    hit->duvdy[k] = point.duvdy[k];
  }
  std::copy(extraArgs, extraArgs + extraWords, args + kHitWords);
  int32_t root = -1;
  entry(args, &root, &ctx);
  return arena.overflow ? -1 : root;
}

ClosureEvaluation walkTree(const compiler::ClosureNode* nodes, int32_t count, int32_t root, const Wavelengths& lambda,
                           Bsdf* bsdf, Spectrum& emission, const std::array<FittedColor, 2>* fitted = nullptr) {
  Walker walker(nodes, count, lambda, bsdf, emission);
  walker.fitted = fitted;
  // Unit weight in the group's lanes only: lanes past the count stay zero (spectrum.h), so that
  // lobes with constant weights (conductors, dielectrics, coats) carry no phantom lanes, which
  // had doubled their share of the Bsdf's selection weights (sums over every nonzero lane)
  // against colour-weighted lobes in groups of 4.
  Spectrum unit;
  for (int i = 0; i < lambda.count; ++i) unit.v[i] = 1.0f;
  walker.walk(root, unit, 0);
  if (walker.nonFiniteParam) walker.result.ok = false;
  return walker.result;
}

// The binding's Spectrum arguments at these wavelengths, packed lane-count words each.
bool spectrumArguments(const CompiledBinding& binding, const Wavelengths& lambda, float* extra) {
  if (binding.spectrumArgs.size() > size_t(kMaxSpectrumArgs)) return false;
  for (size_t a = 0; a < binding.spectrumArgs.size(); ++a) {
    const Spectrum s = binding.spectrumArgs[a].sample(lambda);
    for (int i = 0; i < lambda.count; ++i) extra[a * size_t(lambda.count) + size_t(i)] = s.v[i];
  }
  return true;
}

thread_local std::array<compiler::ClosureNode, kArenaCapacity> tArenaNodes;

}  // namespace

ClosureEvaluation evaluateEntry(compiler::EntryFn entry, const float* extraArgs, int extraWords, const ShadingPoint& point,
                                const Wavelengths& lambda, Bsdf* bsdf, Spectrum& emission) {
  compiler::ClosureArena arena{tArenaNodes.data(), kArenaCapacity, 0, 0};
  const int32_t root = callEntry(entry, extraArgs, extraWords, point, lambda, arena);
  if (root < 0) {
    ClosureEvaluation failed;
    failed.ok = false;
    return failed;
  }
  return walkTree(arena.nodes, arena.count, root, lambda, bsdf, emission);
}

ClosureEvaluation evaluateBinding(const CompiledBinding& binding, const ShadingPoint& point, const Wavelengths& lambda,
                                  Bsdf* bsdf, Spectrum& emission) {
  float extra[kMaxSpectrumArgs * compiler::kMaxWavelengths];
  if (!spectrumArguments(binding, lambda, extra)) {
    ClosureEvaluation failed;
    failed.ok = false;
    return failed;
  }
  return evaluateEntry(binding.entry, extra, int(binding.spectrumArgs.size()) * lambda.count, point, lambda, bsdf, emission);
}

bool captureConstantClosure(const CompiledBinding& binding, const ShadingPoint& point, const Wavelengths& lambda,
                            ConstantClosure& tree) {
  tree = ConstantClosure();
  if (!binding.hitIndependent) return false;
  float extra[kMaxSpectrumArgs * compiler::kMaxWavelengths];
  if (!spectrumArguments(binding, lambda, extra)) return false;
  compiler::ClosureArena arena{tArenaNodes.data(), kArenaCapacity, 0, 0};
  const int32_t root =
      callEntry(binding.entry, extra, int(binding.spectrumArgs.size()) * lambda.count, point, lambda, arena);
  if (root < 0) return false;
  for (int32_t i = 0; i < arena.count; ++i)
    if (arena.nodes[i].flags & compiler::kClosureVariesWithWavelength) return false;
  tree.nodes.assign(arena.nodes, arena.nodes + arena.count);
  const auto fit = [](compiler::ClosureParam kind, const float* params) {
    FittedColor colour;
    if (kind != compiler::ClosureParam::Color) return colour;
    const Vec3 rgb(params[0], params[1], params[2]);
    colour.reflectance = rgbToSigmoid(rgb);
    colour.unbounded = rgbToUnbounded(rgb);
    return colour;
  };
  for (const compiler::ClosureNode& node : tree.nodes)
    tree.fitted.push_back({fit(node.paramKind, node.params), fit(node.param2Kind, node.params2)});
  tree.root = root;
  tree.wavelengthCount = lambda.count;
  return true;
}

ClosureEvaluation walkConstantClosure(const ConstantClosure& tree, const Wavelengths& lambda, Bsdf* bsdf,
                                      Spectrum& emission) {
  return walkTree(tree.nodes.data(), int32_t(tree.nodes.size()), tree.root, lambda, bsdf, emission, tree.fitted.data());
}

}  // namespace tex::render
