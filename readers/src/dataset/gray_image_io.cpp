#include <png.h>

#include <cctype>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>

#include "cleanslam/readers/bounded_file.hpp"
#include "cleanslam/readers/gray_image.hpp"

namespace cleanslam::readers {
namespace {

constexpr int kMaxSide = 16384;

enum class Kind { kPgm, kPng, kUnknown };

Kind sniff(const std::string& path, std::string& error) {
  const Status bounded = check_bounded_file(path, kImageFileLimit);
  if (!bounded) {
    error = bounded.error();
    return Kind::kUnknown;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    error = path + ": cannot open image";
    return Kind::kUnknown;
  }
  unsigned char magic[8] = {};
  in.read(reinterpret_cast<char*>(magic), 8);
  const auto got = in.gcount();
  if (got >= 2 && magic[0] == 'P' && magic[1] == '5') {
    return Kind::kPgm;
  }
  if (got == 8 && png_sig_cmp(magic, 0, 8) == 0) {
    return Kind::kPng;
  }
  error = path + ": not a binary PGM (P5) or PNG image";
  return Kind::kUnknown;
}

// Reads one whitespace-separated header integer of a PNM file, skipping '#' comments.
bool pnm_int(std::istream& in, int& out) {
  int c = in.get();
  while (true) {
    if (c == '#') {
      while (c != '\n' && c != EOF) {
        c = in.get();
      }
    } else if (c != EOF && std::isspace(c) != 0) {
      c = in.get();
    } else {
      break;
    }
  }
  if (c == EOF || std::isdigit(c) == 0) {
    return false;
  }
  long v = 0;
  while (c != EOF && std::isdigit(c) != 0) {
    v = v * 10 + (c - '0');
    if (v > 1'000'000) {
      return false;
    }
    c = in.get();
  }
  if (c == EOF || std::isspace(c) == 0) {
    return false;  // exactly one whitespace ends the field
  }
  out = static_cast<int>(v);
  return true;
}

Status pgm_header(std::istream& in, const std::string& path, ImageSize& size) {
  char p = 0;
  char five = 0;
  in.get(p);
  in.get(five);
  int maxval = 0;
  if (p != 'P' || five != '5' || !pnm_int(in, size.width) || !pnm_int(in, size.height) ||
      !pnm_int(in, maxval)) {
    return Status::failure(path + ": malformed PGM header");
  }
  if (size.width <= 0 || size.height <= 0 || size.width > kMaxSide || size.height > kMaxSide) {
    return Status::failure(path + ": PGM size " + std::to_string(size.width) + "x" +
                           std::to_string(size.height) + " out of range");
  }
  if (maxval <= 0 || maxval > 255) {
    return Status::failure(path + ": PGM maxval " + std::to_string(maxval) +
                           " is not 8-bit (1..255)");
  }
  return Status();
}

struct PngImage {
  png_image image{};
  PngImage() {
    image.version = PNG_IMAGE_VERSION;
    image.opaque = nullptr;
  }
  ~PngImage() { png_image_free(&image); }
  PngImage(const PngImage&) = delete;
  PngImage& operator=(const PngImage&) = delete;
};

Status png_begin(PngImage& png, const std::string& path) {
  if (png_image_begin_read_from_file(&png.image, path.c_str()) == 0) {
    return Status::failure(path + ": PNG error: " + png.image.message);
  }
  if ((png.image.format & (PNG_FORMAT_FLAG_COLOR | PNG_FORMAT_FLAG_LINEAR)) != 0) {
    return Status::failure(path + ": PNG is not 8-bit grayscale");
  }
  if ((png.image.format & PNG_FORMAT_FLAG_ALPHA) != 0) {
    return Status::failure(path +
                           ": PNG has an alpha channel (grey+alpha or transparency); the dataset "
                           "format takes 8-bit grayscale without one");
  }
  if (png.image.width == 0 || png.image.height == 0 || png.image.width > kMaxSide ||
      png.image.height > kMaxSide) {
    return Status::failure(path + ": PNG size out of range");
  }
  return Status();
}

}  // namespace

Result<ImageSize> read_gray_image_size(const std::string& path) {
  std::string error;
  const Kind kind = sniff(path, error);
  ImageSize size;
  if (kind == Kind::kPgm) {
    std::ifstream in(path, std::ios::binary);
    Status s = pgm_header(in, path, size);
    if (!s) {
      return Result<ImageSize>::failure(s.error());
    }
    return size;
  }
  if (kind == Kind::kPng) {
    PngImage png;
    Status s = png_begin(png, path);
    if (!s) {
      return Result<ImageSize>::failure(s.error());
    }
    return ImageSize{static_cast<int>(png.image.width), static_cast<int>(png.image.height)};
  }
  return Result<ImageSize>::failure(error);
}

Status read_gray_image(const std::string& path, GrayImage& out) {
  std::string error;
  const Kind kind = sniff(path, error);
  if (kind == Kind::kPgm) {
    std::ifstream in(path, std::ios::binary);
    ImageSize size;
    Status s = pgm_header(in, path, size);
    if (!s) {
      return s;
    }
    out.width = size.width;
    out.height = size.height;
    out.pixels.resize(static_cast<std::size_t>(size.width) * static_cast<std::size_t>(size.height));
    in.read(reinterpret_cast<char*>(out.pixels.data()),
            static_cast<std::streamsize>(out.pixels.size()));
    if (static_cast<std::size_t>(in.gcount()) != out.pixels.size()) {
      return Status::failure(path + ": PGM data truncated");
    }
    return Status();
  }
  if (kind == Kind::kPng) {
    PngImage png;
    Status s = png_begin(png, path);
    if (!s) {
      return s;
    }
    png.image.format = PNG_FORMAT_GRAY;
    out.width = static_cast<int>(png.image.width);
    out.height = static_cast<int>(png.image.height);
    out.pixels.resize(PNG_IMAGE_SIZE(png.image));
    if (png_image_finish_read(&png.image, nullptr, out.pixels.data(), 0, nullptr) == 0) {
      return Status::failure(path + ": PNG error: " + png.image.message);
    }
    return Status();
  }
  return Status::failure(error);
}

}  // namespace cleanslam::readers
