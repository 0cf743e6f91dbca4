// A per-thread memo of Hit-independent material evaluations (hit_dependence.h). A path keeps
// its wavelength group from the camera to its end, so its later hits on one material, and the
// emission its light samples see, repeat one evaluation exactly: the memo keeps the latest
// result per material and mode, keyed by the group's wavelengths (bit patterns), and the
// caller replays it (lobes, emission, success) bit for bit instead of running the material.
// This holds while an evaluation reads nothing but the entry's arguments and the wavelengths:
// the closure walk (closure_lobes.cpp) must not read the shading point itself.
#pragma once
#include <cstdint>

#include "renderer/bsdf/bsdf.h"
#include "renderer/core/spectrum.h"

namespace tex::render {

struct MaterialMemoEntry {
  // The key: which material system (a process-unique id, 0 for none), slot and mode, and the
  // wavelengths.
  uint64_t system = 0;
  int slot = -1;
  bool withBsdf = false;  // shade() (lobes and emission) or emission() alone
  int count = 0;
  float lambdaNm[color::kMaxWavelengths] = {};  // every lane, compared bit for bit
  // The evaluation.
  bool ok = false;
  Spectrum emission;
  Bsdf bsdf;  // its lobes and coat (withBsdf)
};

// A process-unique id for a material system (never reused, so a destroyed system's entries
// cannot match a new one's).
uint64_t newMaterialMemoId();

// The calling thread's evaluation of (system, slot, withBsdf) at these wavelengths, or null.
const MaterialMemoEntry* materialMemoFind(uint64_t system, int slot, bool withBsdf, const Wavelengths& lambda);
// Records an evaluation, replacing the thread's entry for this material and mode. `bsdf`:
// the lobes shade() produced (withBsdf), or null for an emission() evaluation.
void materialMemoStore(uint64_t system, int slot, const Wavelengths& lambda, bool ok, const Spectrum& emission,
                       const Bsdf* bsdf);

}  // namespace tex::render
