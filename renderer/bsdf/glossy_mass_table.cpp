// The table behind tabulatedMassInDisk (glossy_mass_table.h): lazily filled rows of the
// quadrature kernelMassInDisk, Catmull-Rom interpolation, a measured margin on top.
#include "renderer/bsdf/glossy_mass_table.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <mutex>
#include <vector>

#include "renderer/bsdf/glossy_kernel.h"

namespace tex::render::glossy {
namespace {

// Grid axes. s and log2 R extend one step beyond the domain on each side, so that every query
// inside the domain has its full 4-tap Catmull-Rom stencil.
constexpr double kSLow = 2.75, kSStep = 0.25;
constexpr int kSNodes = 71;  // s in [2.75, 20.25]
constexpr double kLogRLow = -1.25, kLogRStep = 1.0 / 16.0;
constexpr int kRNodes = 49;  // log2 R in [-1.25, 1.75]
constexpr int kDNodes = 129;  // d over [R - w, R + w]

// Beyond this radius the kernel's mass is < 1e-16 (the quadrature's own cut-off).
double effectiveRadius(double n) { return sampleKernelRadius(n, 1e-16); }

class MassTable {
 public:
  MassTable() : values_(size_t(kSNodes) * kRNodes * kDNodes), ready_(new std::atomic<bool>[kSNodes * kRNodes]) {
    for (int r = 0; r < kSNodes * kRNodes; ++r) ready_[r].store(false, std::memory_order_relaxed);
  }

  // Row (i, j): M at n_i, R_j over the transition zone, computed on first use.
  const float* row(int i, int j) {
    const int r = i * kRNodes + j;
    float* out = &values_[size_t(r) * kDNodes];
    if (!ready_[r].load(std::memory_order_acquire)) {
      std::lock_guard<std::mutex> lock(fill_);
      if (!ready_[r].load(std::memory_order_relaxed)) {
        const double n = std::exp2(kSLow + i * kSStep) - 1.0, R = std::exp2(kLogRLow + j * kLogRStep);
        const double w = effectiveRadius(n);
        // The zone may reach d < 0 (small disks): M is even in d.
        for (int k = 0; k < kDNodes; ++k)
          out[k] = float(kernelMassInDisk(n, std::fabs(R - w + 2.0 * w * k / (kDNodes - 1)), R));
        ready_[r].store(true, std::memory_order_release);
      }
    }
    return out;
  }

 private:
  std::vector<float> values_;
  std::unique_ptr<std::atomic<bool>[]> ready_;
  std::mutex fill_;
};

MassTable& table() {
  static MassTable t;
  return t;
}

// Catmull-Rom taps (i - 1 .. i + 2, clamped to the axis) and weights at fractional index f.
struct Stencil {
  int index[4];
  double weight[4];
};
Stencil catmullRom(double f, int nodes) {
  f = std::clamp(f, 0.0, double(nodes - 1));
  const int i = std::min(int(f), nodes - 2);
  const double t = f - i, t2 = t * t, t3 = t2 * t;
  Stencil s;
  s.weight[0] = 0.5 * (-t3 + 2.0 * t2 - t);
  s.weight[1] = 0.5 * (3.0 * t3 - 5.0 * t2 + 2.0);
  s.weight[2] = 0.5 * (-3.0 * t3 + 4.0 * t2 + t);
  s.weight[3] = 0.5 * (t3 - t2);
  for (int m = 0; m < 4; ++m) s.index[m] = std::clamp(i - 1 + m, 0, nodes - 1);
  return s;
}

}  // namespace

bool massTableCovers(double n, double R) {
  return n >= kMassTableMinExponent && n <= kMassTableMaxExponent && R >= kMassTableMinRadius &&
         R <= kMassTableMaxRadius;
}

double massTableMargin(double n) {
  // Measured worst interpolation error per band of n (bench/glossy_albedo.cpp, masscheck:
  // 5.0e-5 and 1.56e-5), rounded up. Smaller n interpolate worse: the kernel (1 - r^2)^(n/2) is
  // only C^(n/2) at its support's edge, whose contact with the rim moves with R.
  return n < 63.0 ? 7.0e-5 : 2.5e-5;
}

namespace {

// What depends on n alone, remembered per thread: a lobe looks up the same n many times.
struct ExponentTerms {
  double n = -1.0, reach = 0.0;
  Stencil stencil;
};
const ExponentTerms& exponentTerms(double n) {
  thread_local ExponentTerms t;
  if (n != t.n) {
    t.n = n;
    t.reach = effectiveRadius(n);
    t.stencil = catmullRom((std::log2(1.0 + n) - kSLow) / kSStep, kSNodes);
  }
  return t;
}

double interpolate(const ExponentTerms& e, double d, double R) {
  const Stencil& ss = e.stencil;
  const Stencil sr = catmullRom((std::log2(R) - kLogRLow) / kLogRStep, kRNodes);
  const Stencil sd = catmullRom((d - (R - e.reach)) / (2.0 * e.reach) * (kDNodes - 1), kDNodes);
  MassTable& t = table();
  double sum = 0.0;
  for (int a = 0; a < 4; ++a) {
    if (ss.weight[a] == 0.0) continue;
    for (int b = 0; b < 4; ++b) {
      if (sr.weight[b] == 0.0) continue;
      const float* row = t.row(ss.index[a], sr.index[b]);
      double along = 0.0;
      for (int c = 0; c < 4; ++c) along += sd.weight[c] * double(row[sd.index[c]]);
      sum += ss.weight[a] * sr.weight[b] * along;
    }
  }
  return sum;
}

}  // namespace

double interpolatedMassInDisk(double n, double d, double R) { return interpolate(exponentTerms(n), d, R); }

double tabulatedMassInDisk(double n, double d, double R) {
  d = std::fabs(d);
  if (d + 1.0 <= R) return 1.0;  // the kernel's whole support is inside
  if (!massTableCovers(n, R)) return kernelMassInDisk(n, d, R);
  const ExponentTerms& e = exponentTerms(n);
  if (d <= R - e.reach) return 1.0;  // clear of the rim: what the quadrature returns, rounded up
  if (d >= R + e.reach) return 0.0;
  return std::clamp(interpolate(e, d, R) + massTableMargin(n), 0.0, 1.0);
}

}  // namespace tex::render::glossy
