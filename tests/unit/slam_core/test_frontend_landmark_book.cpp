#include <gtest/gtest.h>

#include "cleanslam/slam_core/frontend/landmark_book.hpp"

namespace fe = cleanslam::slam_core::frontend;

TEST(FrontendLandmarkBook, YoungUntilMatchedEnoughTimes) {
  fe::LandmarkBook book;
  book.activate(7);
  EXPECT_TRUE(book.young(7));
  EXPECT_EQ(book.matches(7), 0);
  for (int k = 1; k < book.config().min_matches_to_keep; ++k) {
    book.next_frame();
    EXPECT_FALSE(book.record(7, true));
    EXPECT_TRUE(book.young(7)) << k;
  }
  book.next_frame();
  book.record(7, true);
  EXPECT_FALSE(book.young(7));
  EXPECT_EQ(book.matches(7), book.config().min_matches_to_keep);
  // A reused slot starts afresh.
  book.activate(7);
  EXPECT_TRUE(book.young(7));
}

TEST(FrontendLandmarkBook, FramesSinceTheLastMatch) {
  fe::LandmarkBook book;
  book.activate(3);
  EXPECT_EQ(book.frames_since_match(3), 0);
  book.next_frame();
  book.next_frame();
  EXPECT_EQ(book.frames_since_match(3), 2);
  book.record(3, true);
  EXPECT_EQ(book.frames_since_match(3), 0);
  book.next_frame();
  book.record(3, false);
  EXPECT_EQ(book.frames_since_match(3), 1);
  EXPECT_EQ(book.frames_since_match(-1), 0);
  EXPECT_EQ(book.frames_since_match(cleanslam::hal::kMaxLandmarks), 0);
}

TEST(FrontendLandmarkBook, ConsecutiveFailuresStillDeleteAMatureLandmark) {
  fe::LandmarkBook book;
  book.activate(0);
  for (int k = 0; k < 5; ++k) {
    book.record(0, true);
  }
  EXPECT_FALSE(book.young(0));
  EXPECT_FALSE(book.record(0, false));
  EXPECT_FALSE(book.record(0, false));
  EXPECT_TRUE(book.record(0, false));
}
