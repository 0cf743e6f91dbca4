// The glossy model (the thesis's tenth contribution; formulas and properties in
// docs/glossy-model.md): a reciprocal, energy-conserving glossy lobe parameterised by a
// glossiness exponent n, importance-sampled exactly, around the mirror direction
// (GlossyReflection) and around both the mirror and the refracted direction of a dielectric
// interface (GlossyDielectric, eta = lobe.a per wavelength; dispersive when lobe.etaVaries).
// The lobe is the kernel (1 - |q|^2)^(n/2) of the tangential momentum mismatch
// q = eta_o wo_t + eta_i wi_t in the projected-disk plane (renderer/bsdf/glossy_kernel.h),
// normalised symmetrically by the max of wo's and wi's share of the kernel that scatters
// somewhere; GlossyReflection adds a reciprocal energy-compensation lobe
// (renderer/bsdf/glossy_albedo.h); GlossyDielectric weights reflection and refraction by the
// mean Fresnel reflectance of the pair, F^ and 1 - F^, which sum to 1 at every q.
// Lobe-level entry points dispatched from lobes.cpp; conventions of bsdf.h (local frame, z up).
#pragma once
#include <optional>

#include "renderer/bsdf/bsdf.h"

namespace tex::render {

Spectrum glossyLobeEval(const Lobe& lobe, const Vec3& wo, const Vec3& wi, TransportMode mode);
float glossyLobePdf(const Lobe& lobe, const Vec3& wo, const Vec3& wi, TransportMode mode);
std::optional<BsdfSample> glossyLobeSample(const Lobe& lobe, const Vec3& wo, float uc, Vec2 u2, TransportMode mode);

// The density glossyLobeSample would have at wi had lane `lane`'s IOR been the hero's (for
// spectral MIS over the group's wavelengths). Equals glossyLobePdf for lane 0 and for lobes
// whose sampling does not depend on the wavelength.
float glossyLobePdfForLane(const Lobe& lobe, const Vec3& wo, const Vec3& wi, TransportMode mode, int lane);

// Directional albedo of GlossyReflection (glossy + compensation lobe) with unit weight at
// cos(theta_o) (for tests, docs and energy bookkeeping of layers): 1 up to the table's margin
// (<= 1). Deterministic quadrature (a few ms): not for per-sample use.
float glossyReflectionAlbedo(float exponent, float cosThetaO);

}  // namespace tex::render
