#include "renderer/material/material_memo.h"

#include <array>
#include <atomic>
#include <cstring>

namespace tex::render {

namespace {

// Direct-mapped by material and mode: scenes with more materials only evict more often.
constexpr unsigned kEntries = 32;

MaterialMemoEntry& entryFor(int slot, bool withBsdf) {
  thread_local std::array<MaterialMemoEntry, kEntries> entries;
  return entries[(unsigned(slot) * 2u + (withBsdf ? 1u : 0u)) % kEntries];
}

}  // namespace

uint64_t newMaterialMemoId() {
  static std::atomic<uint64_t> next{1};
  return next.fetch_add(1, std::memory_order_relaxed);
}

const MaterialMemoEntry* materialMemoFind(uint64_t system, int slot, bool withBsdf, const Wavelengths& lambda) {
  const MaterialMemoEntry& e = entryFor(slot, withBsdf);
  static_assert(sizeof e.lambdaNm == sizeof lambda.lambdaNm);
  const bool match = e.system == system && e.slot == slot && e.withBsdf == withBsdf && e.count == lambda.count &&
                     std::memcmp(e.lambdaNm, lambda.lambdaNm.data(), sizeof e.lambdaNm) == 0;
  return match ? &e : nullptr;
}

void materialMemoStore(uint64_t system, int slot, const Wavelengths& lambda, bool ok, const Spectrum& emission,
                       const Bsdf* bsdf) {
  MaterialMemoEntry& e = entryFor(slot, bsdf != nullptr);
  e.system = system;
  e.slot = slot;
  e.withBsdf = bsdf != nullptr;
  e.count = lambda.count;
  std::memcpy(e.lambdaNm, lambda.lambdaNm.data(), sizeof e.lambdaNm);
  e.ok = ok;
  e.emission = emission;
  if (bsdf) e.bsdf.copyLobesFrom(*bsdf);
}

}  // namespace tex::render
