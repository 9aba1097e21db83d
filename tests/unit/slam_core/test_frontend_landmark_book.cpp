#include <gtest/gtest.h>

#include <cmath>

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

TEST(FrontendLandmarkBook, AMatchStrayingFromItsPredictionMatchAfterMatchIsDeleted) {
  fe::LandmarkBookConfig cfg;
  cfg.min_matches_to_keep = 3;
  cfg.residual_weight = 0.5;
  cfg.max_mean_nis = 4.0;
  fe::LandmarkBook book(cfg);
  book.activate(0);
  // Consistent matches (NIS about 2) never delete it.
  for (int k = 0; k < 20; ++k) {
    book.record(0, true);
    EXPECT_FALSE(book.record_residual(0, k % 2 == 0 ? 1.0 : 3.0)) << k;
  }
  EXPECT_NEAR(book.mean_nis(0), 2.0, 0.7);
  // One wild match is averaged out; a run of them is not.
  book.record(0, true);
  EXPECT_FALSE(book.record_residual(0, 5.0));
  book.record(0, true);
  EXPECT_FALSE(book.record_residual(0, 1.0));
  int deleted_at = -1;
  for (int k = 0; k < 10 && deleted_at < 0; ++k) {
    book.record(0, true);
    deleted_at = book.record_residual(0, 5.5) ? k : -1;
  }
  EXPECT_EQ(deleted_at, 1);
  // Not before min_matches_to_keep matches; a non-finite value counts as max_mean_nis.
  book.activate(1);
  book.record(1, true);
  EXPECT_FALSE(book.record_residual(1, 100.0));
  book.record(1, true);
  EXPECT_FALSE(book.record_residual(1, 100.0));
  book.record(1, true);
  EXPECT_TRUE(book.record_residual(1, 100.0));
  book.activate(2);
  for (int k = 0; k < 3; ++k) {
    book.record(2, true);
    book.record_residual(2, std::nan(""));
  }
  EXPECT_DOUBLE_EQ(book.mean_nis(2), 4.0);
  // An inactive slot records nothing.
  EXPECT_FALSE(book.record_residual(5, 100.0));
}
