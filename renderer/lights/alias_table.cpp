// AliasTable (alias_table.h): Vose's linear construction, in double so that the bins' keep
// probabilities carry no accumulated rounding.
#include "renderer/lights/alias_table.h"

#include <algorithm>
#include <cmath>

namespace tex::render {

AliasTable::AliasTable(std::span<const float> weights, std::span<const int> labels) {
  double total = 0;
  for (const float w : weights)
    if (w > 0.0f && std::isfinite(w)) total += w;
  if (!(total > 0)) return;
  const size_t n = weights.size();
  bins_.resize(n);
  std::vector<double> scaled(n);  // probability x n: 1 is a full bin
  std::vector<int> small, large;
  int anyPositive = -1;
  for (size_t i = 0; i < n; ++i) {
    const double p = weights[i] > 0.0f && std::isfinite(weights[i]) ? double(weights[i]) / total : 0.0;
    bins_[i].pmf = float(p);
    if (p > 0) anyPositive = int(i);
    scaled[i] = p * double(n);
    (scaled[i] < 1.0 ? small : large).push_back(int(i));
  }
  while (!small.empty() && !large.empty()) {
    const int s = small.back(), l = large.back();
    small.pop_back();
    large.pop_back();
    bins_[size_t(s)].keep = float(scaled[size_t(s)]);
    bins_[size_t(s)].alias = l;
    scaled[size_t(l)] += scaled[size_t(s)] - 1.0;
    (scaled[size_t(l)] < 1.0 ? small : large).push_back(l);
  }
  // What is left is full up to rounding: kept whole, except that a zero entry is never kept.
  for (const std::vector<int>* rest : {&small, &large})
    for (const int i : *rest) {
      Bin& bin = bins_[size_t(i)];
      bin.keep = bin.pmf > 0.0f ? 1.0f : 0.0f;
      bin.alias = bin.pmf > 0.0f ? i : anyPositive;
    }
  for (size_t i = 0; i < n; ++i) bins_[i].label = labels.size() == n ? labels[i] : int(i);
  for (Bin& bin : bins_) {
    bin.aliasPmf = bins_[size_t(bin.alias)].pmf;
    bin.aliasLabel = bins_[size_t(bin.alias)].label;
  }
}

}  // namespace tex::render
