// The stream model: an input stream of sample indices [a, b), one kernel that maps each index
// to zero or more output records, and sinks that consume the records chunk by chunk. The
// kernel must be a pure function of its index (and of read-only state and the read-write
// cache); then the set of records is a function of the index range alone, whatever the thread
// count or chunking. The runtime knows nothing of light transport: Record is any type.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "runtime/chunk_scheduler.h"
#include "runtime/index_range.h"

namespace tex::runtime {

// The records one chunk produced, in index order (or one part of a chunk, for sinks that
// accept parts: then `indices` is the part's sub-range of the chunk).
template <class Record>
struct ChunkRecords {
  uint64_t chunkIndex = 0;
  IndexRange indices;
  std::span<const Record> records;
};

// A consumer of records. consume() is called concurrently from different worker slots (one
// call per chunk); calls with the same slot are sequential. Everything delivered to consume()
// before a cancellation is final: end() still runs and must keep it.
template <class Record>
class Sink {
 public:
  virtual ~Sink() = default;
  // Before the first chunk, with the number of worker slots.
  virtual void begin(int workerSlots) { (void)workerSlots; }
  virtual void consume(int slot, const ChunkRecords<Record>& chunk) = 0;
  // True if the sink does not need a chunk's records in one call: when every sink of a run
  // says so, the runtime runs each chunk as consecutive parts of kStreamPartSize indices and
  // delivers each part as soon as the kernel has produced it, so the record buffer stays small
  // enough for the core's caches (a chunk of 16384 records of 80 bytes would not). Parts of a
  // chunk arrive in order, on the chunk's slot, with the same chunkIndex; a chunk is still
  // done (reported, counted) only when all its parts are, so end() and cancellation are as for
  // whole chunks.
  virtual bool acceptsChunkParts() const { return false; }
  // After the last chunk (also after a cancellation or time-budget stop).
  virtual void end(const SchedulerResult& result) { (void)result; }
};

// What a kernel writes into: the current worker's chunk buffer.
template <class Record>
class Emitter {
 public:
  explicit Emitter(std::vector<Record>& buffer) : buffer_(buffer) {}
  void emit(const Record& record) { buffer_.push_back(record); }
  Record& emplace() { return buffer_.emplace_back(); }

 private:
  std::vector<Record>& buffer_;
};

// Indices per part when every sink accepts chunk parts (see Sink::acceptsChunkParts).
inline constexpr uint64_t kStreamPartSize = 1024;

// Runs kernel(index, emitter) for every index of the range (in chunks, on TBB workers) and
// delivers each chunk's records to every sink. Kernel: void(uint64_t index, Emitter<Record>&).
template <class Record, class Kernel>
SchedulerResult runStream(IndexRange range, const SchedulerOptions& options, Kernel&& kernel,
                          std::span<Sink<Record>* const> sinks) {
  const int slots = workerSlotCount(options);
  for (Sink<Record>* sink : sinks) sink->begin(slots);
  // Per-worker output buffers, one cache line pair each: the kernel's emit writes the vector's
  // end pointer for every record, and two workers writing into one line would make every
  // record a cache-line transfer between cores (false sharing).
  struct alignas(128) SlotBuffer {
    std::vector<Record> records;
  };
  std::vector<SlotBuffer> buffers(slots);
  bool parts = !sinks.empty();
  for (Sink<Record>* sink : sinks) parts = parts && sink->acceptsChunkParts();
  const uint64_t partSize = parts ? kStreamPartSize : UINT64_MAX;
  SchedulerResult result = runChunks(range, options, [&](int slot, uint64_t chunkIndex, IndexRange indices) {
    std::vector<Record>& buffer = buffers[slot].records;
    for (uint64_t begin = indices.begin; begin < indices.end;) {
      const uint64_t end = indices.end - begin > partSize ? begin + partSize : indices.end;
      buffer.clear();
      Emitter<Record> emitter(buffer);
      for (uint64_t i = begin; i < end; ++i) kernel(i, emitter);
      const ChunkRecords<Record> chunk{chunkIndex, {begin, end}, std::span<const Record>(buffer)};
      for (Sink<Record>* sink : sinks) sink->consume(slot, chunk);
      begin = end;
    }
  });
  for (Sink<Record>* sink : sinks) sink->end(result);
  return result;
}

}  // namespace tex::runtime
