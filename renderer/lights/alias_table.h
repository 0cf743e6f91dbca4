// A discrete distribution sampled in O(1) by Walker's alias method (Vose's construction, "A
// linear algorithm for generating random numbers with a given distribution", 1991): u picks a
// bin uniformly and, within it, either the bin's own entry or its alias. The power light
// sampler uses it: a binary search over a CDF of 200 k lights was a fifth of a render.
#pragma once
#include <algorithm>
#include <cmath>
#include <optional>
#include <span>
#include <utility>
#include <vector>

namespace tex::render {

class AliasTable {
 public:
  AliasTable() = default;
  // Weights must be >= 0 (others count as 0); entries of weight 0 are never chosen. `labels`
  // (one per weight, or none: the indices) are what sample() reports for each entry.
  explicit AliasTable(std::span<const float> weights, std::span<const int> labels = {});

  // The chosen entry's label and its probability (pmf); nullopt when every weight is 0. u in
  // [0, 1), in double: the bin takes log2(n) of u's bits and the keep test the rest, so a
  // sampler's 24-bit float left a table of 65536 entries 8 bits for it (an entry kept with
  // probability 0.01 was kept 3/256 of the time: 17 % too often; a point light, which only
  // light sampling finds, was that much too bright). Callers extend their variate's precision
  // (the path tracer: independent low bits).
  std::optional<std::pair<int, float>> sample(double u) const {
    int label;
    float pmf;
    if (!choose(u, label, pmf)) return std::nullopt;
    return std::make_pair(label, pmf);
  }
  // sample() with plain results (false: nothing to choose), for callers that assemble their
  // own result: an optional pair copied between branches went through memory (a
  // store-forwarding stall per choice).
  bool choose(double u, int& label, float& pmf) const {
    if (bins_.empty()) return false;
    const double scaled = u * double(bins_.size());
    // A NaN or negative u picks the first bin rather than indexing out of the table.
    const int i = scaled > 0.0 ? std::min(int(scaled), int(bins_.size()) - 1) : 0;
    const Bin& bin = bins_[size_t(i)];
    const bool keep = scaled - double(i) < double(bin.keep);
    label = keep ? bin.label : bin.aliasLabel;
    pmf = keep ? bin.pmf : bin.aliasPmf;
    return true;
  }
  // The probability of entry `index` (not of a label).
  float pmf(int index) const {
    return index >= 0 && size_t(index) < bins_.size() ? bins_[size_t(index)].pmf : 0.0f;
  }
  int size() const { return int(bins_.size()); }
  bool empty() const { return bins_.empty(); }

 private:
  // Both candidates' labels and probabilities travel with the choice (one cache line read).
  struct Bin {
    float keep = 1;      // probability of keeping this bin's own entry
    int alias = 0;       // the other entry
    float pmf = 0;       // this entry's probability
    float aliasPmf = 0;  // the alias's probability
    int label = 0, aliasLabel = 0;
  };
  std::vector<Bin> bins_;
};

}  // namespace tex::render
