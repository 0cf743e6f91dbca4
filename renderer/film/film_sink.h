// The film as a stream sink: private accumulators for the worker slots (no atomics on the hot
// path), merged by exact integer addition when the run ends. Films are fixed-point integer sums,
// so any split of the records over accumulators merges to the same bits: slots share a bounded
// number of them (each under a mutex) so that large images do not need one full film per thread
// (a 4096^2 film is about 1 GB; every thread had its own). The merged film adopts the first
// accumulator instead of adding it into a zeroed film of its own (which held the image's sums
// twice: 530 MB more at 4K).
#pragma once
#include <cstddef>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "renderer/film/film.h"
#include "runtime/stream.h"

namespace tex {

class FilmSink : public runtime::Sink<SampleRecord> {
 public:
  // `memoryBudgetBytes`: at most this much for the slots' accumulators together (at least one).
  explicit FilmSink(const FilmSettings& settings, size_t memoryBudgetBytes = kDefaultMemoryBudgetBytes)
      : settings_(settings), memoryBudgetBytes_(memoryBudgetBytes) {}

  static constexpr size_t kDefaultMemoryBudgetBytes = size_t(1) << 30;

  void begin(int workerSlots) override;
  void consume(int slot, const runtime::ChunkRecords<SampleRecord>& chunk) override;
  void end(const runtime::SchedulerResult& result) override;
  // The film only adds records up, so it takes chunks in parts (smaller record buffers).
  bool acceptsChunkParts() const override { return true; }

  // Valid after end(): the merged film (empty before any record) and the number of sample
  // indices it holds.
  const FilmAccumulator& film() const { return merged(); }
  FilmAccumulator& film() { return merged(); }
  uint64_t samples() const { return samples_; }
  // The accumulators the last run's slots shared (one per slot unless the budget was short).
  int accumulatorCount() const { return accumulatorCount_; }

 private:
  struct Shared {
    std::mutex mutex;
    std::unique_ptr<FilmAccumulator> film;  // created on its first chunk
  };
  FilmAccumulator& merged() const {
    if (!film_) film_.emplace(settings_);
    return *film_;
  }
  FilmSettings settings_;
  mutable std::optional<FilmAccumulator> film_;  // created by the first end() with records, or on demand
  size_t memoryBudgetBytes_;
  std::vector<std::unique_ptr<Shared>> accumulators_;
  int accumulatorCount_ = 0;
  uint64_t samples_ = 0;
};

}  // namespace tex
