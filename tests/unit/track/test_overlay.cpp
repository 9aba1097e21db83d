#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "cleanslam/hal/image.hpp"
#include "overlay.hpp"

namespace fe = cleanslam::slam_core::frontend;
using cleanslam::tools::track::FrameCaption;
using cleanslam::tools::track::Overlay;

namespace {

struct Gray {
  std::vector<std::uint8_t> pixels;
  cleanslam::hal::GrayImageView view;
  Gray(int w, int h) : pixels(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 128U) {
    view.data = pixels.data();
    view.width = w;
    view.height = h;
    view.stride = w;
  }
};

bool same(Overlay::Rgb a, Overlay::Rgb b) {
  return a.r == b.r && a.g == b.g && a.b == b.b;
}

// Pixels of the strip below the image that differ between two overlays.
int strip_differences(const Overlay& a, const Overlay& b) {
  int n = 0;
  for (int y = a.image_height(); y < a.height(); ++y) {
    for (int x = 0; x < a.width(); ++x) {
      n += same(a.at(x, y), b.at(x, y)) ? 0 : 1;
    }
  }
  return n;
}

int strip_pixels_of(const Overlay& o, Overlay::Rgb c) {
  int n = 0;
  for (int y = o.image_height(); y < o.height(); ++y) {
    for (int x = 0; x < o.width(); ++x) {
      n += same(o.at(x, y), c) ? 1 : 0;
    }
  }
  return n;
}

}  // namespace

TEST(TrackOverlay, ASmallImageIsDrawnTwiceItsSizeWithACaptionStripBelow) {
  const Gray small(320, 240);
  const Overlay o(small.view);
  EXPECT_EQ(o.width(), 640);
  EXPECT_EQ(o.image_height(), 480);
  EXPECT_GT(o.height(), 480 + 3 * 10);
  const Gray large(640, 480);
  const Overlay l(large.view);
  EXPECT_EQ(l.width(), 640);
  EXPECT_EQ(l.image_height(), 480);
}

TEST(TrackOverlay, TheCaptionSaysTheFrameAndItsTime) {
  const Gray g(320, 240);
  const fe::FramePipeline pipeline;
  Overlay first(g.view);
  first.draw(pipeline, FrameCaption{7, 12.5});
  Overlay same_again(g.view);
  same_again.draw(pipeline, FrameCaption{7, 12.5});
  Overlay next_frame(g.view);
  next_frame.draw(pipeline, FrameCaption{8, 12.5});
  Overlay later(g.view);
  later.draw(pipeline, FrameCaption{7, 13.5});
  EXPECT_EQ(strip_differences(first, same_again), 0);
  EXPECT_GT(strip_differences(first, next_frame), 0);
  EXPECT_GT(strip_differences(first, later), 0);
}

TEST(TrackOverlay, TheLegendShowsEveryMarkInItsColour) {
  const Gray g(320, 240);
  const fe::FramePipeline pipeline;
  Overlay o(g.view);
  const Overlay blank(g.view);
  EXPECT_EQ(strip_pixels_of(blank, {235, 235, 235}), 0);
  o.draw(pipeline, FrameCaption{0, 0.0});
  EXPECT_GT(strip_pixels_of(o, {235, 235, 235}), 500);  // text
  for (const Overlay::Rgb mark :
       {Overlay::Rgb{230, 200, 0}, Overlay::Rgb{0, 220, 0}, Overlay::Rgb{240, 0, 0},
        Overlay::Rgb{220, 0, 220}, Overlay::Rgb{0, 200, 230}}) {
    EXPECT_GT(strip_pixels_of(o, mark), 8)
        << int{mark.r} << "," << int{mark.g} << "," << int{mark.b};
  }
  for (int y = 0; y < o.image_height(); ++y) {
    for (int x = 0; x < o.width(); ++x) {
      ASSERT_TRUE(same(o.at(x, y), {128, 128, 128})) << x << "," << y;
    }
  }
}
