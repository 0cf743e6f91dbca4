// The stream runtime: every index of a range is processed exactly once in fixed chunks,
// sinks get each chunk's records in index order, and cancellation, time budgets and epochs
// stop or order work as documented.
#include <gtest/gtest.h>

#include <cstdio>

#include <atomic>
#include <chrono>
#include <csignal>
#include <map>
#include <mutex>
#include <thread>

#include "runtime/cancellation.h"
#include "runtime/progress.h"
#include "runtime/stream.h"

namespace tex::runtime {
namespace {

struct IndexRecord {
  uint64_t index;
  uint64_t value;
};

// Records every chunk it gets; checks order within a chunk.
class RecordingSink : public Sink<IndexRecord> {
 public:
  void begin(int slots) override { slots_ = slots; }
  void consume(int slot, const ChunkRecords<IndexRecord>& chunk) override {
    EXPECT_GE(slot, 0);
    EXPECT_LT(slot, slots_);
    uint64_t previous = chunk.indices.begin;
    for (const IndexRecord& r : chunk.records) {
      EXPECT_GE(r.index, previous);  // index order (a kernel may emit 0..n records per index)
      EXPECT_LT(r.index, chunk.indices.end);
      previous = r.index;
      sum.fetch_add(r.value, std::memory_order_relaxed);
    }
    std::lock_guard<std::mutex> lock(mutex);
    ranges.push_back(chunk.indices);
  }
  void end(const SchedulerResult& result) override { ended = true, endResult = result; }

  int slots_ = 0;
  std::atomic<uint64_t> sum{0};
  std::mutex mutex;
  std::vector<IndexRange> ranges;
  bool ended = false;
  SchedulerResult endResult;
};

uint64_t valueOf(uint64_t i) { return (i * 2654435761u) % 1000003u; }

TEST(Stream, EveryIndexExactlyOnceForAnyThreadCountAndChunkSize) {
  const IndexRange range{1000, 1000 + 100003};
  for (int threads : {1, 2, 4}) {
    for (uint64_t chunk : {1ull, 97ull, 4096ull, 1000000ull}) {
      std::vector<std::atomic<uint8_t>> hits(range.size());
      RecordingSink sink;
      Sink<IndexRecord>* sinks[] = {&sink};
      SchedulerOptions options;
      options.threads = threads;
      options.chunkSize = chunk;
      SchedulerResult result = runStream<IndexRecord>(
          range, options,
          [&](uint64_t i, Emitter<IndexRecord>& out) {
            hits[i - range.begin].fetch_add(1);
            out.emit({i, valueOf(i)});
          },
          std::span<Sink<IndexRecord>* const>(sinks));
      for (size_t k = 0; k < hits.size(); ++k) ASSERT_EQ(hits[k].load(), 1) << "index " << range.begin + k;
      EXPECT_EQ(result.completed, std::vector<IndexRange>{range});
      EXPECT_EQ(result.samplesDone, range.size());
      EXPECT_FALSE(result.cancelled);
      EXPECT_TRUE(sink.ended);
      EXPECT_EQ(mergeRanges(sink.ranges), std::vector<IndexRange>{range});
      for (const IndexRange& r : sink.ranges) EXPECT_LE(r.size(), chunk);
    }
  }
}

// A sink that takes chunks in parts: records each (chunk, part) and checks the parts of one
// chunk arrive in order on one slot.
class PartSink : public RecordingSink {
 public:
  bool acceptsChunkParts() const override { return true; }
  void consume(int slot, const ChunkRecords<IndexRecord>& part) override {
    RecordingSink::consume(slot, part);
    std::lock_guard<std::mutex> lock(partMutex);
    auto [it, fresh] = lastPart.try_emplace(part.chunkIndex, std::pair{slot, part.indices});
    if (!fresh) {
      EXPECT_EQ(it->second.first, slot) << "parts of chunk " << part.chunkIndex << " on two slots";
      EXPECT_EQ(it->second.second.end, part.indices.begin) << "parts of chunk " << part.chunkIndex << " out of order";
      it->second.second = part.indices;
    }
    maxPart = std::max(maxPart, part.indices.size());
  }
  std::mutex partMutex;
  std::map<uint64_t, std::pair<int, IndexRange>> lastPart;
  uint64_t maxPart = 0;
};

TEST(Stream, SinksThatAcceptPartsGetChunksInOrderedParts) {
  const IndexRange range{7, 7 + 3 * kStreamPartSize * 5 + 123};
  for (int threads : {1, 2}) {
    PartSink parts;
    Sink<IndexRecord>* sinks[] = {&parts};
    SchedulerOptions options;
    options.threads = threads;
    options.chunkSize = 3 * kStreamPartSize + 17;
    const SchedulerResult result = runStream<IndexRecord>(
        range, options, [](uint64_t i, Emitter<IndexRecord>& out) { out.emit({i, valueOf(i)}); },
        std::span<Sink<IndexRecord>* const>(sinks));
    EXPECT_EQ(result.completed, std::vector<IndexRange>{range});
    EXPECT_EQ(mergeRanges(parts.ranges), std::vector<IndexRange>{range});
    EXPECT_EQ(parts.maxPart, kStreamPartSize);  // chunks were split
    EXPECT_GT(parts.ranges.size(), parts.lastPart.size());
    uint64_t expected = 0;
    for (uint64_t i = range.begin; i < range.end; ++i) expected += valueOf(i);
    EXPECT_EQ(parts.sum.load(), expected);

    // With a sink that needs whole chunks in the run, every sink gets whole chunks.
    PartSink alsoParts;
    RecordingSink whole;
    Sink<IndexRecord>* mixed[] = {&alsoParts, &whole};
    runStream<IndexRecord>(range, options, [](uint64_t i, Emitter<IndexRecord>& out) { out.emit({i, valueOf(i)}); },
                           std::span<Sink<IndexRecord>* const>(mixed));
    EXPECT_EQ(alsoParts.maxPart, options.chunkSize);
    EXPECT_EQ(alsoParts.ranges.size(), alsoParts.lastPart.size());
    EXPECT_EQ(whole.sum.load(), expected);
  }
}

TEST(Stream, RuntimeOutputIsDeterministicAcrossThreadCounts) {
  uint64_t reference = 0;
  for (int threads : {1, 2, 3}) {
    RecordingSink sink;
    Sink<IndexRecord>* sinks[] = {&sink};
    SchedulerOptions options;
    options.threads = threads;
    options.chunkSize = 333;
    runStream<IndexRecord>({0, 50000}, options,
                           [](uint64_t i, Emitter<IndexRecord>& out) {
                             for (uint64_t k = 0; k < i % 3; ++k) out.emit({i, valueOf(i + k)});
                           },
                           std::span<Sink<IndexRecord>* const>(sinks));
    if (threads == 1) reference = sink.sum;
    EXPECT_EQ(sink.sum.load(), reference);
  }
  EXPECT_GT(reference, 0u);
}

TEST(Stream, EmptyRangeRunsNothingButEndsSinks) {
  RecordingSink sink;
  Sink<IndexRecord>* sinks[] = {&sink};
  SchedulerResult result = runStream<IndexRecord>({5, 5}, SchedulerOptions{}, [](uint64_t, Emitter<IndexRecord>&) { FAIL(); },
                                                  std::span<Sink<IndexRecord>* const>(sinks));
  EXPECT_TRUE(result.completed.empty());
  EXPECT_TRUE(sink.ended);
}

// Runs [0, end) in chunks of 100 on `threads`, raising the cancel flag while at index cancelAt.
SchedulerResult runCancellingAt(uint64_t end, int threads, uint64_t cancelAt, RecordingSink& sink) {
  std::atomic<bool> cancel{false};
  Sink<IndexRecord>* sinks[] = {&sink};
  SchedulerOptions options;
  options.threads = threads;
  options.chunkSize = 100;
  options.cancel = &cancel;
  return runStream<IndexRecord>(
      {0, end}, options,
      [&](uint64_t i, Emitter<IndexRecord>& out) {
        if (i == cancelAt) cancel = true;
        out.emit({i, 1});
      },
      std::span<Sink<IndexRecord>* const>(sinks));
}

TEST(Stream, CancellationKeepsExactlyTheDeliveredChunks) {
  for (int threads : {1, 2}) {
    RecordingSink sink;
    const SchedulerResult result = runCancellingAt(1000000, threads, 5050, sink);
    EXPECT_TRUE(result.cancelled);
    EXPECT_LT(result.samplesDone, 1000000u);
    EXPECT_GE(result.samplesDone, 5100u);  // the chunk that set the flag finishes
    // The result's ranges are exactly what the sink got, and the sink's sum matches.
    EXPECT_EQ(mergeRanges(sink.ranges), result.completed);
    EXPECT_EQ(sink.sum.load(), result.samplesDone);
    EXPECT_TRUE(sink.ended);
    EXPECT_TRUE(sink.endResult.cancelled);
  }
}

// A stop that comes after the last chunk was taken cost nothing: the run is complete, not
// interrupted (a finished render had reported "interrupted" and exited 130). And chunks near
// the top of the index space do not wrap (begin + chunkSize overflowed to an empty chunk).
TEST(Stream, AStopAfterTheLastChunkLeavesTheRunCompleteAndChunksDoNotWrap) {
  for (int threads : {1, 2}) {
    RecordingSink sink;
    const SchedulerResult result = runCancellingAt(100, threads, 99, sink);  // during the only chunk
    EXPECT_EQ(result.samplesDone, 100u);
    EXPECT_FALSE(result.cancelled);
    EXPECT_FALSE(sink.endResult.cancelled);
  }
  const uint64_t top = ~uint64_t(0) - 10;
  SchedulerOptions options;
  options.threads = 1;
  options.chunkSize = uint64_t(1) << 63;
  std::atomic<uint64_t> count{0};
  RecordingSink sink;
  Sink<IndexRecord>* sinks[] = {&sink};
  const SchedulerResult result = runStream<IndexRecord>(
      {top - 1000, top}, options,
      [&](uint64_t i, Emitter<IndexRecord>& out) {
        ++count;
        out.emit({i, 1});
      },
      std::span<Sink<IndexRecord>* const>(sinks));
  EXPECT_EQ(result.samplesDone, 1000u);
  EXPECT_EQ(count.load(), 1000u);
}

TEST(Stream, SigintCancelsTheRunAndTheHandlerIsRestored) {
  struct sigaction before {};
  sigaction(SIGINT, nullptr, &before);
  std::atomic<bool> cancel{false};
  SchedulerResult result;
  {
    ScopedSigintCancellation scope(cancel);
    RecordingSink sink;
    Sink<IndexRecord>* sinks[] = {&sink};
    SchedulerOptions options;
    options.threads = 2;
    options.chunkSize = 64;
    options.cancel = &cancel;
    result = runStream<IndexRecord>(
        {0, 10000000}, options,
        [&](uint64_t i, Emitter<IndexRecord>& out) {
          if (i == 1000) std::raise(SIGINT);
          out.emit({i, 1});
        },
        std::span<Sink<IndexRecord>* const>(sinks));
    EXPECT_TRUE(scope.interrupted());
    EXPECT_EQ(sink.sum.load(), result.samplesDone);
  }
  EXPECT_TRUE(result.cancelled);
  EXPECT_LT(result.samplesDone, 10000000u);
  struct sigaction after {};
  sigaction(SIGINT, nullptr, &after);
  EXPECT_EQ(after.sa_handler, before.sa_handler);
}

TEST(Stream, TimeBudgetStopsStartingChunks) {
  SchedulerOptions options;
  options.threads = 2;
  options.chunkSize = 10;
  options.timeBudgetSeconds = 0.2;
  RecordingSink sink;
  Sink<IndexRecord>* sinks[] = {&sink};
  const auto start = std::chrono::steady_clock::now();
  SchedulerResult result = runStream<IndexRecord>(
      {0, 1000000}, options,
      [](uint64_t i, Emitter<IndexRecord>& out) {
        if (i % 10 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(2));
        out.emit({i, 1});
      },
      std::span<Sink<IndexRecord>* const>(sinks));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_TRUE(result.timeBudgetReached);
  EXPECT_FALSE(result.cancelled);
  EXPECT_GT(result.samplesDone, 0u);
  EXPECT_LT(result.samplesDone, 1000000u);
  EXPECT_LT(seconds, 2.0);
  EXPECT_EQ(sink.sum.load(), result.samplesDone);
}

TEST(Stream, EpochsAreBarriersAlignedToMultiples) {
  const uint64_t epochSize = 1000;
  std::atomic<uint64_t> finished{0};
  std::vector<IndexRange> epochsSeen;
  SchedulerOptions options;
  options.threads = 4;
  options.chunkSize = 64;
  options.epochSize = epochSize;
  options.onEpochEnd = [&](uint64_t, IndexRange epoch) { epochsSeen.push_back(epoch); };
  const IndexRange range{1500, 5200};
  std::atomic<bool> violated{false};
  runChunks(range, options, [&](int, uint64_t, IndexRange indices) {
    // Every index of earlier epochs is done before a chunk of a later epoch starts.
    const uint64_t epochStart = std::max(range.begin, indices.begin / epochSize * epochSize);
    if (finished.load() < epochStart - range.begin) violated = true;
    if (indices.begin / epochSize != (indices.end - 1) / epochSize) violated = true;  // no straddling
    finished.fetch_add(indices.size());
  });
  EXPECT_FALSE(violated.load());
  const std::vector<IndexRange> expected = {{1500, 2000}, {2000, 3000}, {3000, 4000}, {4000, 5000}, {5000, 5200}};
  EXPECT_EQ(epochsSeen, expected);
}

TEST(Progress, FormatsRateAndEta) {
  EXPECT_EQ(ProgressReporter::formatLine(2000000, 4000000, 2.0, 0), "2.00 M samples, 1.00 M samples/s, 50%, ETA 2 s");
  EXPECT_EQ(ProgressReporter::formatLine(500, 0, 1.0, 10.0), "500 samples, 500 samples/s, ETA 9 s");
  // The final line of a stopped run has no ETA.
  EXPECT_EQ(ProgressReporter::formatLine(1000000, 4000000, 2.0, 0, false), "1.00 M samples, 500.00 k samples/s, 25%");
  ProgressReporter silent("test", 100, 0, nullptr);
  silent.start();
  silent.add(40);
  silent.add(2);
  EXPECT_EQ(silent.done(), 42u);
  silent.finish();
}

// finish(true) prints the final line only after a progress line: a short run whose caller
// prints its own summary (tex eval) stays quiet; finish() always closes with one.
TEST(Progress, FinishOnlyIfReportedStaysQuietOnShortRuns) {
  for (bool onlyIfReported : {true, false}) {
    FILE* out = std::tmpfile();
    ASSERT_NE(out, nullptr);
    ProgressReporter quick("test", 100, 0, out);
    quick.start();
    quick.add(100);
    quick.finish(onlyIfReported);
    const long written = std::ftell(out);
    std::fclose(out);
    if (onlyIfReported) EXPECT_EQ(written, 0L);
    else EXPECT_GT(written, 0L);
  }
}

TEST(IndexRanges, MergeOverlapAndFormat) {
  EXPECT_EQ(mergeRanges({{5, 7}, {0, 2}, {2, 4}, {6, 9}, {3, 3}}), (std::vector<IndexRange>{{0, 4}, {5, 9}}));
  EXPECT_TRUE(rangesOverlap({{0, 5}, {4, 6}}));
  EXPECT_FALSE(rangesOverlap({{0, 5}, {5, 6}}));
  EXPECT_EQ(totalSize({{0, 4}, {5, 9}}), 8u);
  EXPECT_EQ(formatRanges({{0, 4}, {5, 9}}), "[0, 4) [5, 9)");
}

}  // namespace
}  // namespace tex::runtime
