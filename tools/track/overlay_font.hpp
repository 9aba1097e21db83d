#pragma once

#include <cstdint>

// A fixed 6 x 10 pixel font for the overlay's caption and legend.
namespace cleanslam::tools::track {

inline constexpr int kGlyphWidth = 6;
inline constexpr int kGlyphHeight = 10;

// The glyph's kGlyphHeight rows, top first; bit 7 - x of a row is column x. Characters outside
// ' '..'~' draw as '?'.
const std::uint8_t* glyph_rows(char c);

}  // namespace cleanslam::tools::track
