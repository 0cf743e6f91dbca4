// The glossy model (the thesis's tenth contribution; formulas and properties in
// docs/glossy-model.md): a reciprocal, energy-conserving glossy lobe parameterised by a
// glossiness exponent n, importance-sampled (near) exactly, around the mirror direction
// (GlossyReflection) and around both the mirror and the refracted direction of a dielectric
// interface (GlossyDielectric, eta = lobe.a per wavelength; dispersive when lobe.etaVaries).
// Lobe-level entry points dispatched from lobes.cpp; conventions of bsdf.h (local frame, z up).
#pragma once
#include <optional>

#include "renderer/bsdf/bsdf.h"

namespace tex::render {

Spectrum glossyLobeEval(const Lobe& lobe, const Vec3& wo, const Vec3& wi, TransportMode mode);
float glossyLobePdf(const Lobe& lobe, const Vec3& wo, const Vec3& wi, TransportMode mode);
std::optional<BsdfSample> glossyLobeSample(const Lobe& lobe, const Vec3& wo, float uc, Vec2 u2, TransportMode mode);

// The density glossyLobeSample would have had for wi had lane `lane`'s eta chosen it.
float glossyLobePdfForLane(const Lobe& lobe, const Vec3& wo, const Vec3& wi, TransportMode mode, int lane);

// Directional albedo of the reflection lobe with unit weight at cos(theta_o) (for tests, docs
// and energy bookkeeping of layers).
float glossyReflectionAlbedo(float exponent, float cosThetaO);

}  // namespace tex::render
