#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>

#include "cleanslam/slam_core/frontend/harris.hpp"
#include "cleanslam/slam_core/frontend/image_check.hpp"
#include "frontend_synthetic.hpp"

namespace fe = cleanslam::slam_core::frontend;
using cleanslam::test::GrayImage;
using cleanslam::test::render;
using cleanslam::test::Warp;

namespace {

std::string describe(fe::ImageCheck check, const cleanslam::hal::GrayImageView& v, int w, int h) {
  char buf[160];
  return fe::describe_image_check(check, v, w, h, buf, sizeof(buf));
}

}  // namespace

TEST(FrontendImage, AcceptsConfiguredSize) {
  const GrayImage img(320, 240, 10);
  EXPECT_EQ(fe::check_image(img.view(), 320, 240), fe::ImageCheck::kOk);
}

TEST(FrontendImage, RejectsWrongSizeWithClearMessage) {
  const GrayImage img(640, 480, 10);
  const fe::ImageCheck c = fe::check_image(img.view(), 320, 240);
  EXPECT_EQ(c, fe::ImageCheck::kWrongSize);
  EXPECT_EQ(describe(c, img.view(), 320, 240),
            "image 640x480 does not match the configured 320x240");
}

TEST(FrontendImage, RejectsEmptyBadStrideAndOversizedConfiguration) {
  const cleanslam::hal::GrayImageView empty{};
  EXPECT_EQ(fe::check_image(empty, 320, 240), fe::ImageCheck::kEmpty);
  const GrayImage img(320, 240, 10);
  cleanslam::hal::GrayImageView bad = img.view();
  bad.stride = 100;
  const fe::ImageCheck c = fe::check_image(bad, 320, 240);
  EXPECT_EQ(c, fe::ImageCheck::kBadStride);
  EXPECT_NE(describe(c, bad, 320, 240).find("stride 100"), std::string::npos);
  const fe::ImageCheck big = fe::check_image(img.view(), 640, 480);
  EXPECT_EQ(big, fe::ImageCheck::kTooLarge);
  EXPECT_NE(describe(big, img.view(), 640, 480).find("640x480"), std::string::npos);
}

TEST(FrontendImage, DescribeTruncatesSafely) {
  const GrayImage img(640, 480, 10);
  char buf[8];
  std::memset(buf, 'x', sizeof(buf));
  fe::describe_image_check(fe::ImageCheck::kWrongSize, img.view(), 320, 240, buf, sizeof(buf));
  EXPECT_EQ(std::strlen(buf), 7U);
}

TEST(FrontendHarris, FindsTheFourCornersOfASquare) {
  GrayImage img(320, 240, 30);
  for (int y = 80; y < 160; ++y) {
    for (int x = 100; x < 200; ++x) {
      img.at(x, y) = 220;
    }
  }
  fe::HarrisDetector det;
  ASSERT_EQ(det.detect(img.view(), 320, 240), fe::ImageCheck::kOk);
  ASSERT_EQ(det.corner_count(), 4);
  const double expected[4][2] = {{99.5, 79.5}, {199.5, 79.5}, {99.5, 159.5}, {199.5, 159.5}};
  for (const auto& e : expected) {
    double best = 1e9;
    for (int i = 0; i < det.corner_count(); ++i) {
      best = std::min(best, std::hypot(det.corners()[i].x - e[0], det.corners()[i].y - e[1]));
    }
    EXPECT_LT(best, 1.5) << "corner near " << e[0] << "," << e[1];
  }
}

TEST(FrontendHarris, EdgesAreNotCorners) {
  GrayImage img(320, 240, 30);
  for (int y = 0; y < 240; ++y) {
    for (int x = 160; x < 320; ++x) {
      img.at(x, y) = 220;
    }
  }
  fe::HarrisDetector det;
  ASSERT_EQ(det.detect(img.view(), 320, 240), fe::ImageCheck::kOk);
  EXPECT_EQ(det.corner_count(), 0);
}

TEST(FrontendHarris, TexturedImageGivesManySeparatedCornersStrongestFirst) {
  const GrayImage img = render(Warp{});
  fe::HarrisConfig cfg;
  cfg.min_distance_px = 6.0F;
  fe::HarrisDetector det(cfg);
  ASSERT_EQ(det.detect(img.view(), 320, 240), fe::ImageCheck::kOk);
  ASSERT_GT(det.corner_count(), 60);
  for (int i = 0; i < det.corner_count(); ++i) {
    const fe::Corner& a = det.corners()[i];
    EXPECT_GE(a.x, cfg.border_px);
    EXPECT_LT(a.x, 320 - cfg.border_px);
    if (i > 0) {
      EXPECT_LE(a.response, det.corners()[i - 1].response);
    }
    for (int j = 0; j < i; ++j) {
      const fe::Corner& b = det.corners()[j];
      EXPECT_GE(std::hypot(a.x - b.x, a.y - b.y), 6.0);
    }
  }
}

TEST(FrontendHarris, RespectsMaxCorners) {
  const GrayImage img = render(Warp{});
  fe::HarrisConfig cfg;
  cfg.max_corners = 10;
  fe::HarrisDetector det(cfg);
  det.detect(img.view(), 320, 240);
  EXPECT_EQ(det.corner_count(), 10);
}

TEST(FrontendHarris, RepeatableUnderShift) {
  const GrayImage a = render(Warp{});
  Warp w;
  w.shift_x = 4.0;
  w.shift_y = -3.0;
  const GrayImage b = render(w);
  fe::HarrisConfig cfg;
  cfg.max_corners = 100;
  fe::HarrisDetector da(cfg);
  fe::HarrisDetector db(cfg);
  da.detect(a.view(), 320, 240);
  db.detect(b.view(), 320, 240);
  int inside = 0;
  int repeated = 0;
  for (int i = 0; i < da.corner_count(); ++i) {
    const double u = da.corners()[i].x + 4.0;
    const double v = da.corners()[i].y - 3.0;
    if (u < 12 || v < 12 || u > 308 || v > 228) {
      continue;
    }
    ++inside;
    for (int j = 0; j < db.corner_count(); ++j) {
      if (std::hypot(db.corners()[j].x - u, db.corners()[j].y - v) < 1.5) {
        ++repeated;
        break;
      }
    }
  }
  ASSERT_GT(inside, 50);
  EXPECT_GT(static_cast<double>(repeated) / inside, 0.8);
}

TEST(FrontendHarris, FlatBlackWhiteAndSaturatedFramesGiveNoCorners) {
  fe::HarrisDetector det;
  for (const int level : {0, 128, 255}) {
    const GrayImage img(320, 240, static_cast<std::uint8_t>(level));
    EXPECT_EQ(det.detect(img.view(), 320, 240), fe::ImageCheck::kOk);
    EXPECT_EQ(det.corner_count(), 0) << "level " << level;
  }
  // Overexposed: the texture clipped to white almost everywhere, weak noise left.
  const GrayImage sat = render(Warp{}, 320, 240, 1.0, 400.0);
  EXPECT_EQ(det.detect(sat.view(), 320, 240), fe::ImageCheck::kOk);
  EXPECT_EQ(det.corner_count(), 0);
  // One gray level of noise is not texture.
  GrayImage noise(320, 240, 100);
  for (int y = 0; y < 240; ++y) {
    for (int x = 0; x < 320; ++x) {
      noise.at(x, y) = static_cast<std::uint8_t>(100 + ((x * 7 + y * 13) % 3 == 0 ? 1 : 0));
    }
  }
  det.detect(noise.view(), 320, 240);
  EXPECT_EQ(det.corner_count(), 0);
}

TEST(FrontendHarris, WrongSizeIsRejectedAndLeavesNoCorners) {
  const GrayImage good = render(Warp{});
  fe::HarrisDetector det;
  det.detect(good.view(), 320, 240);
  ASSERT_GT(det.corner_count(), 0);
  const GrayImage small(160, 120, 50);
  EXPECT_EQ(det.detect(small.view(), 320, 240), fe::ImageCheck::kWrongSize);
  EXPECT_EQ(det.corner_count(), 0);
}

TEST(FrontendHarris, HonoursStride) {
  const GrayImage img = render(Warp{});
  GrayImage wide(400, 240, 0);
  for (int y = 0; y < 240; ++y) {
    for (int x = 0; x < 320; ++x) {
      wide.at(x, y) = img.pixels[static_cast<std::size_t>(y * 320 + x)];
    }
  }
  const cleanslam::hal::GrayImageView strided{wide.pixels.data(), 320, 240, 400};
  fe::HarrisDetector a;
  fe::HarrisDetector b;
  a.detect(img.view(), 320, 240);
  b.detect(strided, 320, 240);
  ASSERT_EQ(a.corner_count(), b.corner_count());
  for (int i = 0; i < a.corner_count(); ++i) {
    EXPECT_EQ(a.corners()[i].x, b.corners()[i].x);
    EXPECT_EQ(a.corners()[i].y, b.corners()[i].y);
  }
}

TEST(FrontendHarris, DetectionInBoundedStepsEqualsOneCall) {
  const GrayImage img = render(Warp{});
  fe::HarrisDetector whole;
  fe::HarrisDetector pieces;
  whole.detect(img.view(), 320, 240);
  ASSERT_EQ(pieces.begin(img.view(), 320, 240), fe::ImageCheck::kOk);
  int steps = 0;
  while (!pieces.step(7)) {
    ++steps;
    EXPECT_EQ(pieces.corner_count(), 0);
  }
  EXPECT_EQ(steps + 1, (238 + 6) / 7);
  ASSERT_EQ(whole.corner_count(), pieces.corner_count());
  for (int i = 0; i < whole.corner_count(); ++i) {
    EXPECT_EQ(whole.corners()[i].x, pieces.corners()[i].x);
    EXPECT_EQ(whole.corners()[i].y, pieces.corners()[i].y);
    EXPECT_EQ(whole.corners()[i].response, pieces.corners()[i].response);
  }
  // A rejected image finishes at once with no corners.
  const GrayImage small(10, 10, 0);
  EXPECT_EQ(pieces.begin(small.view(), 320, 240), fe::ImageCheck::kWrongSize);
  EXPECT_TRUE(pieces.step(7));
  EXPECT_EQ(pieces.corner_count(), 0);
}
