// Placeholder until the glossy model lands (docs/glossy-model.md): the lobes sample nothing and
// evaluate to zero, so a material using them renders black rather than wrong.
#include "renderer/bsdf/glossy_lobe.h"

namespace tex::render {

Spectrum glossyLobeEval(const Lobe&, const Vec3&, const Vec3&, TransportMode) { return Spectrum(); }
float glossyLobePdf(const Lobe&, const Vec3&, const Vec3&, TransportMode) { return 0.0f; }
std::optional<BsdfSample> glossyLobeSample(const Lobe&, const Vec3&, float, Vec2, TransportMode) { return std::nullopt; }
float glossyLobePdfForLane(const Lobe&, const Vec3&, const Vec3&, TransportMode, int) { return 0.0f; }
float glossyReflectionAlbedo(float, float) { return 0.0f; }

}  // namespace tex::render
