// Layers over a whole Bsdf (docs/layering.md, "Covers"): what glTF's KHR_materials_clearcoat
// and KHR_materials_sheen put on top of a material whose base is itself layered (a coat over a
// diffuse base, a metal). Private to renderer/bsdf/ (Bsdf::setClearcoat, setSheenCover and
// setPartialCoat are the public entry points). Factors are per lane; cosines are |cos| with
// the normal of the layer in question.
//  - Coverage k of a coat (a scaled coat, `layer(scale_material(dielectric(..), k), base)`):
//    the coat is present on a fraction k, so every factor below is (1 - k) + k T, and the
//    coat's reflection carries k. A white Lambertian base keeps albedo exactly 1.
//  - Clearcoat: a dielectric interface over every lobe and over the Bsdf's own coat. Lambertian
//    lobes take the Lambertian transmittance of layer.h; lobes under the Bsdf's coat too take
//    the transmittance of the two interfaces together (twoCoatTransmittance below), so a white
//    Lambertian under both smooth coats has albedo exactly 1; other lobes and the inner coat's
//    reflection take the directional 1 - max(F(cos_o), F(cos_i)).
//  - Sheen cover: a sheen of colour a (per lane) and alpha over every other lobe and the
//    coat, which it scales by 1 - a max(Eb(cos_o), Eb(cos_i)) (the albedo scaling of
//    KHR_materials_sheen, per lane instead of with max(sheenColor); Eb = min(1, E)).
#pragma once
#include "renderer/bsdf/bsdf.h"

namespace tex::render {

// A coat's factor for base lobes spread over the hemisphere / near the mirror direction, with
// coverage k (layer.h's transmittances at k = 1).
Spectrum coveredTransmittance(const Lobe& coat, const Spectrum& coverage, float cosO, float cosI);
Spectrum coveredTransmittanceDirectional(const Lobe& coat, const Spectrum& coverage, float cosO, float cosI);

// Per lane, 2 int_0^1 (1 - F_outer(mu)) (1 - F_inner(mu)) mu dmu: what a Lambertian base
// receives, cosine-averaged, through both interfaces (outer, inner: SmoothDielectric or
// RoughDielectric coats; the inner's coverage k_in: 1 - k_in F_inner).
Spectrum twoCoatAverageTransmission(const Lobe& outer, const Lobe& inner, const Spectrum& innerCoverage);

// The factor of a Lambertian lobe under the inner coat and the clearcoat: (1 - k) T_inner +
// k T_both, T_both = (1 - F_o(o))(1 - F_i(o))(1 - F_o(i))(1 - F_i(i)) / average (the average of
// twoCoatAverageTransmission); the outer's cosines first, then the inner's.
Spectrum twoCoatTransmittance(const Lobe& outer, const Spectrum& outerCoverage, const Lobe& inner,
                              const Spectrum& innerCoverage, const Spectrum& average, float outerCosO,
                              float outerCosI, float cosO, float cosI);

// 1 - a max(Eb(alpha, cos_o), Eb(alpha, cos_i)) per lane (a clamped to [0, 1]).
Spectrum sheenCoverFactor(const Spectrum& colour, float alpha, float cosO, float cosI);

}  // namespace tex::render
