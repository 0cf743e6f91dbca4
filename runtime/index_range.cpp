#include "runtime/index_range.h"

#include <algorithm>

namespace tex::runtime {

std::vector<IndexRange> mergeRanges(std::vector<IndexRange> ranges) {
  std::erase_if(ranges, [](const IndexRange& r) { return r.empty(); });
  std::sort(ranges.begin(), ranges.end(),
            [](const IndexRange& a, const IndexRange& b) { return a.begin < b.begin; });
  std::vector<IndexRange> merged;
  for (const IndexRange& r : ranges) {
    if (!merged.empty() && r.begin <= merged.back().end) {
      merged.back().end = std::max(merged.back().end, r.end);
    } else {
      merged.push_back(r);
    }
  }
  return merged;
}

bool rangesOverlap(std::vector<IndexRange> ranges) {
  std::erase_if(ranges, [](const IndexRange& r) { return r.empty(); });
  std::sort(ranges.begin(), ranges.end(),
            [](const IndexRange& a, const IndexRange& b) { return a.begin < b.begin; });
  for (size_t i = 1; i < ranges.size(); ++i) {
    if (ranges[i].begin < ranges[i - 1].end) return true;
  }
  return false;
}

uint64_t totalSize(const std::vector<IndexRange>& ranges) {
  uint64_t total = 0;
  for (const IndexRange& r : ranges) total += r.size();
  return total;
}

std::string formatRanges(const std::vector<IndexRange>& ranges) {
  if (ranges.empty()) return "(none)";
  std::string out;
  for (const IndexRange& r : ranges) {
    if (!out.empty()) out += ' ';
    out += '[' + std::to_string(r.begin) + ", " + std::to_string(r.end) + ')';
  }
  return out;
}

}  // namespace tex::runtime
