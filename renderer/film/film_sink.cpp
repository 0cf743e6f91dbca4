#include "renderer/film/film_sink.h"

#include <algorithm>

namespace tex {

void FilmSink::begin(int workerSlots) {
  const size_t filmBytes =
      std::max<size_t>(1, size_t(std::max(settings_.width, 0)) * size_t(std::max(settings_.height, 0)) *
                              size_t(FilmAccumulator::sumsPerPixelFor(settings_)) * sizeof(int64_t));
  const size_t affordable = std::max<size_t>(1, memoryBudgetBytes_ / filmBytes);
  accumulatorCount_ = int(std::min<size_t>(size_t(std::max(workerSlots, 1)), affordable));
  accumulators_.clear();
  for (int i = 0; i < accumulatorCount_; ++i) accumulators_.push_back(std::make_unique<Shared>());
}

void FilmSink::consume(int slot, const runtime::ChunkRecords<SampleRecord>& chunk) {
  Shared& shared = *accumulators_[size_t(slot) % accumulators_.size()];
  std::lock_guard<std::mutex> lock(shared.mutex);  // uncontended unless slots share it
  if (!shared.film) shared.film = std::make_unique<FilmAccumulator>(settings_);
  shared.film->add(chunk.records.data(), chunk.records.size());
}

void FilmSink::end(const runtime::SchedulerResult& result) {
  for (const auto& shared : accumulators_) {
    if (!shared->film) continue;
    if (!film_) film_.emplace(std::move(*shared->film));  // integer sums: adopting is merging into zeros
    else film_->merge(*shared->film);
  }
  accumulators_.clear();
  samples_ += result.samplesDone;
}

}  // namespace tex
