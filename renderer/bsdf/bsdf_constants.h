// Thresholds shared by the BSDF lobes and the mixture (private to renderer/bsdf/).
#pragma once

namespace tex::render {

// Directions closer to grazing than this (|cos| below it) are degenerate: no sample, value 0.
// Dirac lobes divide by |cos|; below 1e-6 the lost share of a cosine-weighted hemisphere is
// ~1e-12, far below any estimator's noise.
inline constexpr float kMinCosTheta = 1e-6f;

// The largest float below 1, for remapped uniform numbers that must stay in [0, 1).
inline constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;

}  // namespace tex::render
