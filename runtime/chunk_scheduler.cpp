#include "runtime/chunk_scheduler.h"

#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/info.h>
#include <oneapi/tbb/task_arena.h>
#include <oneapi/tbb/task_group.h>

#include <algorithm>
#include <chrono>
#include <optional>

#include "runtime/progress.h"

namespace tex::runtime {

int workerSlotCount(const SchedulerOptions& options) {
  if (options.threads > 0) return options.threads;
  return std::max(1, tbb::info::default_concurrency());
}

namespace {

// Epochs are aligned to absolute multiples of epochSize (so a range split at an epoch
// boundary sees the same epochs as the whole range); without epochs the range is one epoch.
std::vector<IndexRange> splitIntoEpochs(IndexRange range, uint64_t epochSize) {
  std::vector<IndexRange> epochs;
  if (range.empty()) return epochs;
  if (epochSize == 0) return {range};
  for (uint64_t begin = range.begin; begin < range.end;) {
    const uint64_t boundary = (begin / epochSize + 1) * epochSize;  // next multiple
    const uint64_t end = boundary > begin && boundary < range.end ? boundary : range.end;
    epochs.push_back({begin, end});
    begin = end;
  }
  return epochs;
}

}  // namespace

SchedulerResult runChunks(IndexRange range, const SchedulerOptions& options, const ChunkFunction& processChunk) {
  SchedulerResult result;
  result.workerSlots = workerSlotCount(options);
  const auto start = std::chrono::steady_clock::now();
  const uint64_t chunkSize = std::max<uint64_t>(1, options.chunkSize);

  std::atomic<bool> stop{false};
  std::atomic<bool> cancelled{false};
  std::atomic<bool> timeUp{false};
  std::vector<std::vector<IndexRange>> doneBySlot(result.workerSlots);

  auto shouldStop = [&] {
    if (stop.load(std::memory_order_relaxed)) return true;
    if (options.cancel != nullptr && options.cancel->load(std::memory_order_relaxed)) {
      cancelled = true;
      stop = true;
    } else if (options.timeBudgetSeconds > 0 &&
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >=
                   options.timeBudgetSeconds) {
      timeUp = true;
      stop = true;
    }
    return stop.load(std::memory_order_relaxed);
  };

  // More threads than cores, when asked for: TBB's global worker limit (the core count) would
  // otherwise run 2 of 16 requested slots, with a warning, while the summary said 16.
  std::optional<tbb::global_control> allowMore;
  if (result.workerSlots > tbb::info::default_concurrency())
    allowMore.emplace(tbb::global_control::max_allowed_parallelism, size_t(result.workerSlots));
  tbb::task_arena arena(result.workerSlots);
  uint64_t chunkBase = 0;  // global index of the epoch's first chunk
  const std::vector<IndexRange> epochs = splitIntoEpochs(range, options.epochSize);
  for (size_t e = 0; e < epochs.size() && !stop; ++e) {
    const IndexRange epoch = epochs[e];
    const uint64_t chunkCount = epoch.size() / chunkSize + (epoch.size() % chunkSize != 0);
    std::atomic<uint64_t> next{0};
    auto work = [&](int slot) {
      while (!shouldStop()) {
        const uint64_t chunk = next.fetch_add(1, std::memory_order_relaxed);
        if (chunk >= chunkCount) break;
        const uint64_t begin = epoch.begin + chunk * chunkSize;
        // (begin + chunkSize can wrap near 2^64.)
        const IndexRange indices{begin, epoch.end - begin <= chunkSize ? epoch.end : begin + chunkSize};
        processChunk(slot, chunkBase + chunk, indices);
        doneBySlot[slot].push_back(indices);
        if (options.progress != nullptr) options.progress->add(indices.size());
      }
    };
    if (result.workerSlots == 1) {
      work(0);
    } else {
      arena.execute([&] {
        tbb::task_group group;
        for (int slot = 1; slot < result.workerSlots; ++slot) group.run([&work, slot] { work(slot); });
        work(0);
        group.wait();
      });
    }
    chunkBase += chunkCount;
    // A chunk once taken always finishes, so the epoch is complete iff every chunk was taken.
    const bool complete = next.load() >= chunkCount;
    if (options.onEpochEnd && complete) options.onEpochEnd(e, epoch);
  }

  std::vector<IndexRange> ranges;
  for (const auto& slotRanges : doneBySlot) ranges.insert(ranges.end(), slotRanges.begin(), slotRanges.end());
  result.completed = mergeRanges(std::move(ranges));
  result.samplesDone = totalSize(result.completed);
  // A stop seen only after the last chunk was taken cost nothing: the run is complete.
  const bool complete = result.samplesDone == range.size();
  result.cancelled = cancelled && !complete;
  result.timeBudgetReached = timeUp && !complete;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace tex::runtime
