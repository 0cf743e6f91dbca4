// The volumes a path is inside (KHR_materials_volume interiors, and the clear solids that
// hide an outer volume from their own interior): a volume is entered by a transmission into
// the back side of its surface and left by one out of it. Absorption along a segment is the
// innermost volume's, whichever surface ends the segment: a lamp, a diffuse object or another
// volume inside or touching the first (until round 16 only a segment ending on the back of a
// volume was absorbed, by that volume: a lamp inside absorbing glass shone 40x too bright).
// Volumes need not be entered in order or left in reverse order (overlapping objects): leaving
// one removes its innermost entry wherever it is.
#pragma once

namespace tex::render {

class MediumStack {
 public:
  bool empty() const { return depth_ == 0; }
  // The innermost volume (a material index); only when not empty.
  int innermost() const { return materials_[depth_ - 1]; }

  void enter(int material) {
    if (depth_ == kMaxDepth) {  // deeper than any real nesting: forget the outermost
      for (int i = 1; i < kMaxDepth; ++i) materials_[i - 1] = materials_[i];
      --depth_;
    }
    materials_[depth_++] = material;
  }

  void leave(int material) {
    for (int i = depth_ - 1; i >= 0; --i) {
      if (materials_[i] != material) continue;
      for (int j = i + 1; j < depth_; ++j) materials_[j - 1] = materials_[j];
      --depth_;
      return;
    }
  }

  bool contains(int material) const {
    for (int i = 0; i < depth_; ++i)
      if (materials_[i] == material) return true;
    return false;
  }

  // The innermost volume once `material` is left (-1: none), without leaving it.
  int innermostOutside(int material) const {
    bool skipped = false;
    for (int i = depth_ - 1; i >= 0; --i) {
      if (!skipped && materials_[i] == material) {
        skipped = true;
        continue;
      }
      return materials_[i];
    }
    return -1;
  }

 private:
  static constexpr int kMaxDepth = 8;
  int materials_[kMaxDepth];
  int depth_ = 0;
};

}  // namespace tex::render
