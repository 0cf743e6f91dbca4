// The context at which next-event estimation chooses a light (light_sampler.h): the shading
// point and a normal bounding which lights the BSDF can use. A BSDF that only reflects passes
// its shading normal turned toward wo (it gives 0 for directions on the other side of it,
// bsdf.h); one that may transmit passes no normal, so that lights behind the surface stay
// reachable. Emitters hit by BSDF sampling are weighted (MIS) with the pmf of the same
// context, kept from the vertex that sampled them.
#pragma once
#include "renderer/bsdf/bsdf.h"
#include "renderer/lights/light_bounds.h"

namespace tex::render {

inline bool lobeOnlyReflects(LobeKind kind) {
  switch (kind) {
    case LobeKind::Lambertian:
    case LobeKind::SmoothConductor:
    case LobeKind::RoughConductor:
    case LobeKind::GlossyReflection:
    case LobeKind::Sheen:
    case LobeKind::LambertianUnderSheen:
      return true;
    default:  // dielectrics and thin walls transmit
      return false;
  }
}

// The coat (Bsdf::setCoat) contributes its reflection only, so it does not count.
inline bool bsdfOnlyReflects(const Bsdf& bsdf) {
  for (int i = 0; i < bsdf.lobeCount(); ++i)
    if (!lobeOnlyReflects(bsdf.lobe(i).kind)) return false;
  return true;
}

inline LightSampleContext nextEventContext(const Bsdf& bsdf, const Vec3& p, const Vec3& wo) {
  LightSampleContext ctx;
  ctx.p = p;
  if (bsdfOnlyReflects(bsdf)) {
    const Vec3& ns = bsdf.frame().n;
    ctx.n = dot3(wo, ns) < 0.0f ? -ns : ns;
  }
  return ctx;
}

}  // namespace tex::render
