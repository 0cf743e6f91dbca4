#include "renderer/film/film_sink.h"

namespace tex {

void FilmSink::begin(int workerSlots) {
  perSlot_.clear();
  perSlot_.resize(workerSlots);
}

void FilmSink::consume(int slot, const runtime::ChunkRecords<SampleRecord>& chunk) {
  std::unique_ptr<FilmAccumulator>& film = perSlot_[slot];
  if (!film) film = std::make_unique<FilmAccumulator>(film_.settings());
  film->add(chunk.records.data(), chunk.records.size());
}

void FilmSink::end(const runtime::SchedulerResult& result) {
  for (const auto& film : perSlot_) {
    if (film) film_.merge(*film);
  }
  perSlot_.clear();
  samples_ += result.samplesDone;
}

}  // namespace tex
