// The scheduler: splits an index range into fixed chunks and runs them on oneTBB workers.
// Chunk k covers [begin + k*chunkSize, begin + (k+1)*chunkSize) clipped to the range (per
// epoch, if epochs are used), so the partition depends only on the range and the options,
// never on the thread count. Workers take chunks in increasing order from a shared counter, so a stopped run has done (nearly)
// a prefix; whatever it did is reported exactly as a set of index ranges.
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <vector>

#include "runtime/index_range.h"

namespace tex::runtime {

class ProgressReporter;

struct SchedulerOptions {
  uint64_t chunkSize = 16384;        // samples per chunk (the unit of work and of output)
  int threads = 0;                   // 0: all hardware threads
  double timeBudgetSeconds = 0;      // 0: none; otherwise no chunk starts after the budget
  const std::atomic<bool>* cancel = nullptr;  // polled before each chunk
  ProgressReporter* progress = nullptr;       // counts samples of finished chunks
  // Epochs (0: none): the range is processed in consecutive epochs, aligned to multiples of
  // this many samples, with a barrier between them (chunks never straddle an epoch);
  // onEpochEnd runs on the calling thread after each complete epoch. This is what the read-write cache's deterministic mode
  // needs: everything of epoch e is visible before epoch e+1 starts.
  uint64_t epochSize = 0;
  std::function<void(uint64_t epochIndex, IndexRange epoch)> onEpochEnd;
};

struct SchedulerResult {
  std::vector<IndexRange> completed;  // merged, sorted ranges of finished chunks
  uint64_t samplesDone = 0;
  bool cancelled = false;
  bool timeBudgetReached = false;
  double seconds = 0;
  int workerSlots = 0;
};

// processChunk(slot, chunkIndex, indices): called once per chunk, concurrently for different
// slots; calls with the same slot never overlap (one slot is one worker's private buffers).
using ChunkFunction = std::function<void(int slot, uint64_t chunkIndex, IndexRange indices)>;

// The number of worker slots a run with these options uses (for sizing per-slot state).
int workerSlotCount(const SchedulerOptions& options);

SchedulerResult runChunks(IndexRange range, const SchedulerOptions& options, const ChunkFunction& processChunk);

}  // namespace tex::runtime
