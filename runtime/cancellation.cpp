#include "runtime/cancellation.h"

#include <csignal>

namespace tex::runtime {

namespace {
// Signal handlers may only touch lock-free atomics and volatile sig_atomic_t.
std::atomic<bool>* gFlag = nullptr;
volatile std::sig_atomic_t gCount = 0;
struct sigaction gPrevious;

extern "C" void onSigint(int signal) {
  gCount = gCount + 1;
  if (gCount == 1 && gFlag != nullptr) {
    gFlag->store(true, std::memory_order_relaxed);
    return;
  }
  // Second Ctrl-C: the user insists; behave as without us.
  sigaction(SIGINT, &gPrevious, nullptr);
  std::raise(signal);
}
}  // namespace

struct ScopedSigintCancellation::Saved {
  bool installed = false;
};

ScopedSigintCancellation::ScopedSigintCancellation(std::atomic<bool>& flag) : saved_(new Saved) {
  static_assert(std::atomic<bool>::is_always_lock_free);
  gFlag = &flag;
  gCount = 0;
  struct sigaction action {};
  action.sa_handler = onSigint;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  saved_->installed = sigaction(SIGINT, &action, &gPrevious) == 0;
}

ScopedSigintCancellation::~ScopedSigintCancellation() {
  if (saved_->installed) sigaction(SIGINT, &gPrevious, nullptr);
  gFlag = nullptr;
  delete saved_;
}

bool ScopedSigintCancellation::interrupted() const { return gCount > 0; }

}  // namespace tex::runtime
