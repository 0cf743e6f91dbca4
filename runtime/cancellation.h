// Cancellation: a flag that workers poll between chunks, and a scope that sets it on Ctrl-C.
#pragma once
#include <atomic>

namespace tex::runtime {

// While alive, SIGINT sets `flag` (and only that: the run stops at the next chunk boundary
// and the sinks keep everything delivered). A second SIGINT restores the previous handler's
// behaviour by re-raising with it installed. The previous handler is restored on destruction.
// One instance at a time (a process has one SIGINT disposition).
class ScopedSigintCancellation {
 public:
  explicit ScopedSigintCancellation(std::atomic<bool>& flag);
  ~ScopedSigintCancellation();
  ScopedSigintCancellation(const ScopedSigintCancellation&) = delete;
  ScopedSigintCancellation& operator=(const ScopedSigintCancellation&) = delete;

  // True if a SIGINT arrived while this scope was installed.
  bool interrupted() const;

 private:
  struct Saved;
  Saved* saved_;
};

}  // namespace tex::runtime
