// The read-write cache: concurrent inserts and lookups lose nothing and never show torn
// entries; in deterministic mode its content depends only on the index range processed.
#include <gtest/gtest.h>

#include <thread>

#include "runtime/rw_cache.h"
#include "runtime/stream.h"

namespace tex::runtime {
namespace {

struct Photon {
  uint64_t a, b;  // b = 3 * a + 1 always: a reader seeing anything else saw a torn entry
};

TEST(RwCache, InsertAndLookup) {
  RwCache<Photon> cache(4);
  for (uint64_t i = 0; i < 5000; ++i) cache.insert(i % 10, {i, 3 * i + 1}, i);
  EXPECT_EQ(cache.size(), 5000u);
  for (uint64_t key = 0; key < 10; ++key) {
    size_t n = 0;
    cache.forEach(key, [&](const RwCache<Photon>::Entry& e) {
      EXPECT_EQ(e.key, key);
      EXPECT_EQ(e.value.a % 10, key);
      ++n;
    });
    EXPECT_EQ(n, 500u);
  }
  size_t none = 0;
  cache.forEach(12345, [&](const auto&) { ++none; });
  EXPECT_EQ(none, 0u);
  EXPECT_NE(hashGridCell(1, 2, 3), hashGridCell(3, 2, 1));
}

TEST(RwCache, StressConcurrentInsertAndLookupWithManyThreads) {
  RwCache<Photon> cache(8);  // few buckets: long lists and heavy CAS contention
  const int writers = 8, readers = 4;
  const uint64_t perWriter = 60000;
  std::atomic<bool> writing{true};
  std::atomic<int> readersStarted{0};
  std::atomic<uint64_t> torn{0}, seen{0};
  std::vector<std::thread> threads;
  // Readers look up while the writers insert, then sweep every key once more: on a machine with
  // fewer cores than threads a reader may not be scheduled at all while the writers run (the
  // check that readers saw entries failed on 2 cores), and the last sweep still reads lists that
  // were built under contention.
  for (int r = 0; r < readers; ++r) {
    threads.emplace_back([&, r] {
      const auto lookUp = [&](uint64_t key) {
        cache.forEach(key % 97, [&](const RwCache<Photon>::Entry& e) {
          if (e.value.b != 3 * e.value.a + 1 || e.key != e.value.a % 97) torn.fetch_add(1);
          seen.fetch_add(1, std::memory_order_relaxed);
        });
      };
      readersStarted.fetch_add(1);
      for (uint64_t key = uint64_t(r); writing.load(); ++key) lookUp(key);
      for (uint64_t key = 0; key < 97; ++key) lookUp(key);
    });
  }
  while (readersStarted.load() < readers) std::this_thread::yield();  // writers start on running readers
  std::vector<std::thread> writerThreads;
  for (int w = 0; w < writers; ++w) {
    writerThreads.emplace_back([&, w] {
      for (uint64_t k = 0; k < perWriter; ++k) {
        const uint64_t a = uint64_t(w) * perWriter + k;
        cache.insert(a % 97, {a, 3 * a + 1}, a);
      }
    });
  }
  for (auto& t : writerThreads) t.join();
  writing = false;
  for (auto& t : threads) t.join();
  EXPECT_EQ(torn.load(), 0u);
  EXPECT_GT(seen.load(), 0u);
  ASSERT_EQ(cache.size(), writers * perWriter);
  // Every inserted entry is reachable from its bucket exactly once.
  std::vector<uint8_t> found(writers * perWriter, 0);
  for (uint64_t key = 0; key < 97; ++key) {
    cache.forEach(key, [&](const RwCache<Photon>::Entry& e) { found[e.value.a]++; });
  }
  for (size_t i = 0; i < found.size(); ++i) ASSERT_EQ(found[i], 1) << i;
}

// A kernel whose inserts depend on what it reads: at index i it reads the entries of one cell
// produced before its epoch, and inserts a value computed from them.
std::vector<RwCache<Photon>::Entry> runFeedbackKernel(std::vector<IndexRange> ranges, int threads, uint64_t chunk) {
  const uint64_t epochSize = 512;
  RwCache<Photon> cache(6);
  for (const IndexRange& range : ranges) {
    SchedulerOptions options;
    options.threads = threads;
    options.chunkSize = chunk;
    options.epochSize = epochSize;
    runChunks(range, options, [&](int, uint64_t, IndexRange indices) {
      std::vector<RwCache<Photon>::Entry> visible;
      for (uint64_t i = indices.begin; i < indices.end; ++i) {
        const uint64_t cell = hashGridCell(int(i % 7), int(i % 5), 0);
        cache.collectProducedBefore(cell, i / epochSize * epochSize, visible);
        uint64_t h = i;
        for (const auto& e : visible) h = h * 31 + e.value.a;  // order-sensitive on purpose
        if (i % 3 == 0) cache.insert(hashGridCell(int(h % 7), int(i % 5), 0), {h, 3 * h + 1}, i);
      }
    });
  }
  return cache.snapshotSorted();
}

bool sameContent(const std::vector<RwCache<Photon>::Entry>& x, const std::vector<RwCache<Photon>::Entry>& y) {
  if (x.size() != y.size()) return false;
  for (size_t i = 0; i < x.size(); ++i) {
    if (x[i].key != y[i].key || x[i].producerIndex != y[i].producerIndex || x[i].value.a != y[i].value.a) return false;
  }
  return true;
}

TEST(RwCache, DeterministicModeContentDependsOnlyOnTheRange) {
  const auto reference = runFeedbackKernel({{0, 6000}}, 1, 4096);
  ASSERT_EQ(reference.size(), 2000u);
  EXPECT_TRUE(sameContent(reference, runFeedbackKernel({{0, 6000}}, 2, 37)));
  EXPECT_TRUE(sameContent(reference, runFeedbackKernel({{0, 6000}}, 4, 1)));
  // The range split at an epoch boundary and processed in two runs.
  EXPECT_TRUE(sameContent(reference, runFeedbackKernel({{0, 2048}, {2048, 6000}}, 2, 100)));
  // A different range gives different content (the test can fail).
  EXPECT_FALSE(sameContent(reference, runFeedbackKernel({{1, 6001}}, 1, 4096)));
}

}  // namespace
}  // namespace tex::runtime
