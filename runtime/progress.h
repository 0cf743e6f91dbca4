// Progress reporting: samples done, samples/s and ETA on stderr. On a terminal one line is
// rewritten in place (carriage return); otherwise a line is printed at most every few
// seconds so logs stay short. A background thread polls the counter the workers bump.
#pragma once
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <string>
#include <thread>

namespace tex::runtime {

class ProgressReporter {
 public:
  // total: samples expected (0 if only a time budget bounds the run); timeBudgetSeconds > 0
  // makes the ETA the earlier of the two. out = nullptr silences it (counters still work).
  ProgressReporter(std::string label, uint64_t total, double timeBudgetSeconds = 0, FILE* out = stderr);
  ~ProgressReporter();

  void start();
  void add(uint64_t samples) { done_.fetch_add(samples, std::memory_order_relaxed); }
  // Stops the thread and prints the final line (with onlyIfReported, only when a progress
  // line was printed before: short runs whose caller prints its own summary stay quiet).
  void finish(bool onlyIfReported = false);

  uint64_t done() const { return done_.load(std::memory_order_relaxed); }
  double elapsedSeconds() const;

  // "1.23 M samples, 45.6 M samples/s, 62%, ETA 3 s" (exposed for tests).
  // withEta false: the final line, after which nothing is left to wait for (a stopped run's
  // last line had shown the ETA of the work it would no longer do).
  static std::string formatLine(uint64_t done, uint64_t total, double seconds, double timeBudgetSeconds, bool withEta = true);

 private:
  void loop();
  void print(bool final);

  std::string label_;
  uint64_t total_;
  double timeBudgetSeconds_;
  FILE* out_;
  bool tty_ = false;
  std::atomic<uint64_t> done_{0};
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point lastPrint_;
  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  bool started_ = false;
  bool reported_ = false;  // a progress line was printed (loop thread; read after join)
};

}  // namespace tex::runtime
