#include "runtime/progress.h"

#include <unistd.h>

#include <cmath>

namespace tex::runtime {

namespace {
std::string humanCount(double n) {
  char buffer[32];
  if (n >= 1e9) std::snprintf(buffer, sizeof buffer, "%.2f G ", n / 1e9);
  else if (n >= 1e6) std::snprintf(buffer, sizeof buffer, "%.2f M ", n / 1e6);
  else if (n >= 1e3) std::snprintf(buffer, sizeof buffer, "%.2f k ", n / 1e3);
  else std::snprintf(buffer, sizeof buffer, "%.0f ", n);
  return buffer;
}
}  // namespace

ProgressReporter::ProgressReporter(std::string label, uint64_t total, double timeBudgetSeconds, FILE* out)
    : label_(std::move(label)), total_(total), timeBudgetSeconds_(timeBudgetSeconds), out_(out) {
  tty_ = out_ != nullptr && isatty(fileno(out_));
  start_ = lastPrint_ = std::chrono::steady_clock::now();
}

ProgressReporter::~ProgressReporter() { finish(); }

void ProgressReporter::start() {
  start_ = lastPrint_ = std::chrono::steady_clock::now();
  if (out_ == nullptr || started_) return;
  started_ = true;
  thread_ = std::thread([this] { loop(); });
}

double ProgressReporter::elapsedSeconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

std::string ProgressReporter::formatLine(uint64_t done, uint64_t total, double seconds, double timeBudgetSeconds, bool withEta) {
  const double rate = seconds > 0 ? double(done) / seconds : 0.0;
  std::string line = humanCount(double(done)) + "samples, " + humanCount(rate) + "samples/s";
  double eta = -1;
  if (total > 0) {
    char pct[16];
    std::snprintf(pct, sizeof pct, ", %.0f%%", 100.0 * double(done) / double(total));
    line += pct;
    if (rate > 0) eta = double(total - std::min(done, total)) / rate;
  }
  if (timeBudgetSeconds > 0) {
    const double left = std::max(0.0, timeBudgetSeconds - seconds);
    eta = eta < 0 ? left : std::min(eta, left);
  }
  if (withEta && eta >= 0) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, ", ETA %.0f s", std::ceil(eta));
    line += buffer;
  }
  return line;
}

void ProgressReporter::print(bool final) {
  reported_ = true;
  const std::string line = formatLine(done(), total_, elapsedSeconds(), final ? 0.0 : timeBudgetSeconds_, !final);
  if (tty_) {
    std::fprintf(out_, "\r%s: %s\033[K%s", label_.c_str(), line.c_str(), final ? "\n" : "");
  } else {
    std::fprintf(out_, "%s: %s\n", label_.c_str(), line.c_str());
  }
  std::fflush(out_);
}

void ProgressReporter::loop() {
  const auto period = tty_ ? std::chrono::milliseconds(200) : std::chrono::milliseconds(5000);
  std::unique_lock<std::mutex> lock(mutex_);
  while (!wake_.wait_for(lock, period, [this] { return stop_; })) print(false);
}

void ProgressReporter::finish(bool onlyIfReported) {
  if (!started_) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  if (!onlyIfReported || reported_) print(true);
  started_ = false;
}

}  // namespace tex::runtime
