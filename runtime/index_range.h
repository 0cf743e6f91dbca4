// Half-open ranges of sample indices [begin, end) and sets of them.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace tex::runtime {

struct IndexRange {
  uint64_t begin = 0;
  uint64_t end = 0;

  uint64_t size() const { return end > begin ? end - begin : 0; }
  bool empty() const { return end <= begin; }
  bool contains(uint64_t index) const { return index >= begin && index < end; }
  friend bool operator==(const IndexRange&, const IndexRange&) = default;
};

// Sorts and coalesces adjacent or overlapping ranges; drops empty ones.
std::vector<IndexRange> mergeRanges(std::vector<IndexRange> ranges);

// True if any two of the ranges share an index.
bool rangesOverlap(std::vector<IndexRange> ranges);

// Total number of indices in a set of disjoint ranges.
uint64_t totalSize(const std::vector<IndexRange>& ranges);

// "[a, b)" or "[a, b) [c, d)" for messages.
std::string formatRanges(const std::vector<IndexRange>& ranges);

}  // namespace tex::runtime
