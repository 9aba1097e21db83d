#include <gtest/gtest.h>

#include "cleanslam/slam_core/version.hpp"

TEST(SlamCore, ReportsVersion) {
  EXPECT_STREQ(cleanslam::slam_core::version(), "0.1.0");
}
