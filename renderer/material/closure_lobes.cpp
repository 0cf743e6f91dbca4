#include "renderer/material/closure_lobes.h"

#include <array>

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
  const compiler::ClosureArena& arena;
  const Wavelengths& lambda;
  Bsdf& bsdf;
  Spectrum& emission;
  ClosureEvaluation result;

  void walk(int32_t index, const Spectrum& weight, int depth) {
    if (index < 0 || index >= arena.count || depth > kArenaCapacity) {
      result.ok = false;
      return;
    }
    const compiler::ClosureNode& node = arena.nodes[index];
    switch (node.kind) {
      case compiler::ClosureKind::Diffuse: {
        Lobe lobe;
        lobe.kind = LobeKind::Lambertian;
        lobe.weight = weight * clampZero(paramSpectrum(node.paramKind, node.params, lambda, ParamUse::Reflectance));
        if (!lobe.weight.isBlack() && !bsdf.add(lobe)) result.ok = false;
        return;
      }
      case compiler::ClosureKind::Emission:
        result.sawEmission = true;
        emission += weight * clampZero(paramSpectrum(node.paramKind, node.params, lambda, ParamUse::Illuminant));
        return;
      case compiler::ClosureKind::Mix: {
        const float w = std::clamp(node.weight, 0.0f, 1.0f);
        if (w < 1.0f) walk(node.a, weight * (1.0f - w), depth + 1);
        if (w > 0.0f) walk(node.b, weight * w, depth + 1);
        return;
      }
      case compiler::ClosureKind::Dielectric: {
        Lobe lobe;
        lobe.kind = LobeKind::SmoothDielectric;
        lobe.weight = weight;
        lobe.a = paramSpectrum(node.paramKind, node.params, lambda, ParamUse::Unbounded);
        for (int i = 0; i < lambda.count; ++i)
          if (!(lobe.a.v[i] > 0.0f)) lobe.a.v[i] = 1.0f;  // no IOR at or below 0: index-matched
        // The compiler decides statically whether the IOR depends on the wavelength; an IOR
        // that merely happens to be equal across the group is not dispersive either.
        bool differs = false;
        for (int i = 1; i < lambda.count; ++i) differs = differs || lobe.a.v[i] != lobe.a.v[0];
        lobe.etaVaries = (node.flags & compiler::kClosureVariesWithWavelength) != 0 && differs;
        if (!lobe.weight.isBlack() && !bsdf.add(lobe)) result.ok = false;
        return;
      }
      case compiler::ClosureKind::Conductor: {
        Lobe lobe;
        lobe.kind = LobeKind::SmoothConductor;
        lobe.weight = weight;
        lobe.a = paramSpectrum(node.paramKind, node.params, lambda, ParamUse::Unbounded);
        lobe.b = clampZero(paramSpectrum(node.param2Kind, node.params2, lambda, ParamUse::Unbounded));
        if (!lobe.weight.isBlack() && !bsdf.add(lobe)) result.ok = false;
        return;
      }
      default:
        result.ok = false;  // a kind this renderer does not know (docs/abi.md: kinds only grow)
        return;
    }
  }
};

}  // namespace

ClosureEvaluation evaluateBinding(const CompiledBinding& binding, const ShadingPoint& point, const Wavelengths& lambda,
                                  Bsdf& bsdf, Spectrum& emission) {
  thread_local std::array<compiler::ClosureNode, kArenaCapacity> nodes;
  compiler::ClosureArena arena{nodes.data(), kArenaCapacity, 0, 0};
  compiler::ShadingContext ctx{};
  for (int i = 0; i < lambda.count; ++i) ctx.lambdaNm[i] = lambda.lambdaNm[i];
  ctx.wavelengthCount = lambda.count;
  ctx.arena = &arena;

  float args[18 + kMaxSpectrumArgs * compiler::kMaxWavelengths] = {};
  auto* hit = reinterpret_cast<compiler::HitAbi*>(args);
  for (int k = 0; k < 3; ++k) {
    hit->n[k] = point.ns[k];
    hit->p[k] = point.p[k];
  }
  hit->uv[0] = point.uv.x;
  hit->uv[1] = point.uv.y;
  ClosureEvaluation result;
  if (binding.spectrumArgs.size() > size_t(kMaxSpectrumArgs)) {
    result.ok = false;
    return result;
  }
  for (size_t a = 0; a < binding.spectrumArgs.size(); ++a) {
    const Spectrum s = binding.spectrumArgs[a].sample(lambda);
    for (int i = 0; i < lambda.count; ++i) args[18 + a * size_t(lambda.count) + size_t(i)] = s.v[i];
  }
  int32_t root = -1;
  binding.entry(args, &root, &ctx);
  if (arena.overflow || root < 0) {
    result.ok = false;
    return result;
  }
  Walker walker{arena, lambda, bsdf, emission, {}};
  walker.walk(root, Spectrum(1.0f), 0);
  return walker.result;
}

}  // namespace tex::render
