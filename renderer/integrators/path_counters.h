// Per-thread event counters for integrators (rays traced, NaN/Inf samples), summed at the end.
// Each worker thread increments its own cache-line-aligned block: no atomics on the hot path.
#pragma once
#include <atomic>
#include <cstdint>
#include <deque>
#include <mutex>

namespace tex::render {

struct alignas(64) PathCounters {
  uint64_t rays = 0;           // closest-hit and shadow rays
  uint64_t nonFiniteSamples = 0;  // NaN/Inf estimates, replaced by 0 before the film
  uint64_t materialFailures = 0;

  PathCounters& operator+=(const PathCounters& o) {
    rays += o.rays;
    nonFiniteSamples += o.nonFiniteSamples;
    materialFailures += o.materialFailures;
    return *this;
  }
};

class CounterRegistry {
 public:
  CounterRegistry() : id_(nextId().fetch_add(1) + 1) {}
  // This thread's block (registered on first use).
  PathCounters& local() const {
    thread_local uint64_t cachedId = 0;
    thread_local PathCounters* cached = nullptr;
    if (cachedId != id_) {
      std::lock_guard<std::mutex> lock(mutex_);
      cached = &blocks_.emplace_back();
      cachedId = id_;
    }
    return *cached;
  }
  PathCounters total() const {
    std::lock_guard<std::mutex> lock(mutex_);
    PathCounters sum;
    for (const PathCounters& b : blocks_) sum += b;
    return sum;
  }

 private:
  static std::atomic<uint64_t>& nextId() {
    static std::atomic<uint64_t> id{0};
    return id;
  }
  uint64_t id_;
  mutable std::mutex mutex_;
  mutable std::deque<PathCounters> blocks_;
};

}  // namespace tex::render
