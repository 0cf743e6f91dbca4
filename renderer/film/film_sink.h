// The film as a stream sink: one private accumulator per worker slot (no sharing, no atomics
// on the hot path), merged by exact integer addition when the run ends.
#pragma once
#include <memory>
#include <vector>

#include "renderer/film/film.h"
#include "runtime/stream.h"

namespace tex {

class FilmSink : public runtime::Sink<SampleRecord> {
 public:
  explicit FilmSink(const FilmSettings& settings) : film_(settings) {}

  void begin(int workerSlots) override;
  void consume(int slot, const runtime::ChunkRecords<SampleRecord>& chunk) override;
  void end(const runtime::SchedulerResult& result) override;
  // The film only adds records up, so it takes chunks in parts (smaller record buffers).
  bool acceptsChunkParts() const override { return true; }

  // Valid after end(): the merged film and the number of sample indices it holds.
  const FilmAccumulator& film() const { return film_; }
  FilmAccumulator& film() { return film_; }
  uint64_t samples() const { return samples_; }

 private:
  FilmAccumulator film_;
  std::vector<std::unique_ptr<FilmAccumulator>> perSlot_;  // created on a slot's first chunk
  uint64_t samples_ = 0;
};

}  // namespace tex
