// The volumes a path is inside: entered and left in any order (overlapping objects), the
// innermost one found, and the one around a volume being left.
#include <gtest/gtest.h>

#include "renderer/integrators/medium_stack.h"

namespace tex::render {
namespace {

TEST(MediumStack, NestedOverlappingAndTooDeepVolumes) {
  MediumStack media;
  EXPECT_TRUE(media.empty());
  media.leave(3);  // leaving what was never entered (a camera inside glass) changes nothing
  EXPECT_TRUE(media.empty());
  media.enter(1);  // a glass of water: glass, then the water inside it
  media.enter(2);
  EXPECT_EQ(media.innermost(), 2);
  EXPECT_TRUE(media.contains(1) && media.contains(2) && !media.contains(3));
  EXPECT_EQ(media.innermostOutside(2), 1);  // leaving the water returns to the glass
  EXPECT_EQ(media.innermostOutside(1), 2);  // leaving the glass (overlap) keeps the water
  media.leave(1);                           // overlapping objects: left out of order
  EXPECT_EQ(media.innermost(), 2);
  EXPECT_EQ(media.innermostOutside(2), -1);
  media.leave(2);
  EXPECT_TRUE(media.empty());
  for (int i = 0; i < 10; ++i) media.enter(i);  // deeper than the stack: the outermost go
  EXPECT_EQ(media.innermost(), 9);
  for (int i = 9; i >= 2; --i) {
    EXPECT_EQ(media.innermost(), i);
    media.leave(i);
  }
  EXPECT_TRUE(media.empty());
}

}  // namespace
}  // namespace tex::render
