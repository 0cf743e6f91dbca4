// The read-write cache of the stream model: the one shared mutable structure kernels may use.
// A hashed multimap with lock-free append and concurrent lookup, no ordering guarantee: a
// lookup sees every entry whose insert finished before it started, and maybe some that are
// in flight. It is built for the growing photon map (keys are hashed grid cells, see
// hashGridCell), but knows nothing of photons.
//
// Deterministic mode: every entry carries the sample index that produced it. A kernel at
// index i that only looks at entries produced before epochStart(i), and runs under the
// scheduler's epochs of the same size, sees exactly the same entries whatever the thread
// count or chunking; collectProducedBefore returns them in a canonical order. Then the
// cache's content (snapshotSorted) depends only on the index range processed.
#pragma once
#include <algorithm>
#include <atomic>
#include <bit>
#include <cstdint>
#include <cstring>
#include <memory>
#include <type_traits>
#include <vector>

namespace tex::runtime {

// A 64-bit key for an integer 3-D grid cell (for spatial hashing).
inline uint64_t hashGridCell(int32_t x, int32_t y, int32_t z) {
  uint64_t h = uint64_t(uint32_t(x)) * 0x9e3779b97f4a7c15ull;
  h ^= uint64_t(uint32_t(y)) * 0xc2b2ae3d27d4eb4full + (h << 6) + (h >> 2);
  h ^= uint64_t(uint32_t(z)) * 0x165667b19e3779f9ull + (h << 6) + (h >> 2);
  return h;
}

template <class T>
class RwCache {
  static_assert(std::is_trivially_copyable_v<T>, "cache entries are copied bytewise");

 public:
  struct Entry {
    uint64_t key;
    uint64_t producerIndex;
    T value;
  };

  // bucketCountLog2: the hash table has 2^bucketCountLog2 list heads (it never resizes; lists
  // grow). Capacity is 2^32 - 1 entries.
  explicit RwCache(int bucketCountLog2 = 16)
      : bucketMask_((uint64_t(1) << bucketCountLog2) - 1), heads_(new std::atomic<uint32_t>[bucketMask_ + 1]) {
    for (uint64_t b = 0; b <= bucketMask_; ++b) heads_[b].store(kNone, std::memory_order_relaxed);
    for (auto& s : segments_) s.store(nullptr, std::memory_order_relaxed);
  }
  ~RwCache() {
    for (auto& s : segments_) delete[] s.load(std::memory_order_relaxed);
  }
  RwCache(const RwCache&) = delete;
  RwCache& operator=(const RwCache&) = delete;

  // Lock-free append. Safe to call concurrently with everything but clear().
  void insert(uint64_t key, const T& value, uint64_t producerIndex = 0) {
    const uint32_t id = count_.fetch_add(1, std::memory_order_relaxed);
    Node& node = nodeAt(id, /*allocate=*/true);
    node.entry = Entry{key, producerIndex, value};
    std::atomic<uint32_t>& head = heads_[bucketOf(key)];
    uint32_t expected = head.load(std::memory_order_relaxed);
    do {
      node.next = expected;  // not yet visible to anyone: a plain store is enough
    } while (!head.compare_exchange_weak(expected, id, std::memory_order_release, std::memory_order_relaxed));
  }

  // fn(const Entry&) for every visible entry with this key, in no particular order.
  template <class F>
  void forEach(uint64_t key, F&& fn) const {
    for (uint32_t id = heads_[bucketOf(key)].load(std::memory_order_acquire); id != kNone;) {
      const Node& node = nodeAt(id);
      if (node.entry.key == key) fn(node.entry);
      id = node.next;
    }
  }

  // Deterministic lookup: the entries of `key` produced by sample indices < visibleBefore,
  // sorted by (producer index, bytes). `out` is cleared first.
  void collectProducedBefore(uint64_t key, uint64_t visibleBefore, std::vector<Entry>& out) const {
    out.clear();
    forEach(key, [&](const Entry& e) {
      if (e.producerIndex < visibleBefore) out.push_back(e);
    });
    std::sort(out.begin(), out.end(), canonicalLess);
  }

  // Entries inserted so far (including ones still being linked by a concurrent insert).
  size_t size() const { return std::min<uint64_t>(count_.load(std::memory_order_acquire), kNone); }

  // Every entry, sorted by (key, producer index, bytes): the cache's content as a value.
  // Call when no insert is running.
  std::vector<Entry> snapshotSorted() const {
    std::vector<Entry> all;
    const uint32_t n = uint32_t(size());
    all.reserve(n);
    for (uint32_t id = 0; id < n; ++id) all.push_back(nodeAt(id).entry);
    std::sort(all.begin(), all.end(), canonicalLess);
    return all;
  }

  // Removes everything. Not concurrent with anything.
  void clear() {
    for (uint64_t b = 0; b <= bucketMask_; ++b) heads_[b].store(kNone, std::memory_order_relaxed);
    count_.store(0, std::memory_order_relaxed);
  }

  static bool canonicalLess(const Entry& a, const Entry& b) {
    if (a.key != b.key) return a.key < b.key;
    if (a.producerIndex != b.producerIndex) return a.producerIndex < b.producerIndex;
    return std::memcmp(&a.value, &b.value, sizeof(T)) < 0;
  }

 private:
  struct Node {
    Entry entry;
    uint32_t next;
  };
  static constexpr uint32_t kNone = 0xffffffffu;
  static constexpr int kFirstSegmentLog2 = 10;  // segment s holds 2^(10+s) nodes (s >= 1: doubling)
  static constexpr int kSegmentCount = 32 - kFirstSegmentLog2 + 1;

  uint64_t bucketOf(uint64_t key) const {
    uint64_t h = key * 0xff51afd7ed558ccdull;
    return (h ^ (h >> 32)) & bucketMask_;
  }

  // Node id -> (segment, offset): segment 0 holds ids [0, 2^10), segment s >= 1 holds
  // [2^(9+s), 2^(10+s)). Segments never move, so readers never race with growth.
  static void locate(uint32_t id, int& segment, uint32_t& offset) {
    const uint32_t scaled = id >> kFirstSegmentLog2;
    segment = scaled == 0 ? 0 : std::bit_width(scaled);
    offset = segment == 0 ? id : id - (uint32_t(1) << (kFirstSegmentLog2 + segment - 1));
  }
  static uint32_t segmentSize(int segment) {
    return uint32_t(1) << (segment == 0 ? kFirstSegmentLog2 : kFirstSegmentLog2 + segment - 1);
  }

  Node& nodeAt(uint32_t id, bool allocate) {
    int segment;
    uint32_t offset;
    locate(id, segment, offset);
    Node* nodes = segments_[segment].load(std::memory_order_acquire);
    if (nodes == nullptr && allocate) {
      Node* fresh = new Node[segmentSize(segment)];
      if (segments_[segment].compare_exchange_strong(nodes, fresh, std::memory_order_acq_rel)) {
        nodes = fresh;
      } else {
        delete[] fresh;  // another thread won; `nodes` now holds its segment
      }
    }
    return nodes[offset];
  }
  const Node& nodeAt(uint32_t id) const {
    int segment;
    uint32_t offset;
    locate(id, segment, offset);
    return segments_[segment].load(std::memory_order_acquire)[offset];
  }

  uint64_t bucketMask_;
  std::unique_ptr<std::atomic<uint32_t>[]> heads_;
  std::atomic<Node*> segments_[kSegmentCount];
  std::atomic<uint32_t> count_{0};
};

}  // namespace tex::runtime
