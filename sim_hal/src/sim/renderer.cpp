#include "cleanslam/sim_hal/sim/renderer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cleanslam/sim_hal/sim/camera_effects.hpp"

namespace cleanslam::sim_hal::sim {
namespace {

std::uint64_t hash3(std::uint64_t seed, std::int64_t i, std::int64_t j, std::int64_t k) {
  std::uint64_t s = seed ^ (static_cast<std::uint64_t>(i) * 0x9E3779B97F4A7C15ULL) ^
                    (static_cast<std::uint64_t>(j) * 0xC2B2AE3D27D4EB4FULL) ^
                    (static_cast<std::uint64_t>(k) * 0x165667B19E3779F9ULL);
  return splitmix64(s);
}

double unit(std::uint64_t h, int shift) {
  return static_cast<double>((h >> shift) & 0xFFFF) / 65535.0;
}

std::int64_t cell(double x, double size) {
  return static_cast<std::int64_t>(std::floor(x / size));
}

}  // namespace

Vec3 pixel_ray(const Scenario::Camera& c, double u, double v) {
  const double xd = (u - c.cx) / c.fx, yd = (v - c.cy) / c.fy;
  double x = xd, y = yd;
  const auto& d = c.distortion;
  for (int it = 0; it < 20; ++it) {
    const double r2 = x * x + y * y;
    const double radial = 1.0 + d[0] * r2 + d[1] * r2 * r2;
    const double dx = 2.0 * d[2] * x * y + d[3] * (r2 + 2.0 * x * x);
    const double dy = d[2] * (r2 + 2.0 * y * y) + 2.0 * d[3] * x * y;
    x = (xd - dx) / radial;
    y = (yd - dy) / radial;
  }
  const Vec3 r{x, y, 1.0};
  return (1.0 / norm(r)) * r;
}

Renderer::Renderer(const Scenario& sc)
    : camera_(sc.camera),
      room_(sc.world.size),
      boxes_(solid_boxes(sc.world)),
      first_wall_surface_(6 + static_cast<int>(sc.world.furniture.size())),
      seed_(sc.world_seed() * 0x2545F4914F6CDD1DULL + 7),
      noise_sigma_(sc.camera.image_noise),
      blur_(sc.camera.blur),
      shot_gain_(sc.camera.shot_noise_gain) {
  const int w = camera_.width, h = camera_.height;
  const std::size_t pixels = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  rays_.reserve(pixels);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      rays_.push_back(pixel_ray(camera_, x, y));
    }
  }
  // A pixel integrates the light over its area: kSamples rays on a rotated grid inside it (the
  // pixel centre at integer coordinates, as cx, cy), so that edges are not stair-stepped and a
  // corner's image moves smoothly with the camera.
  sample_rays_.reserve(pixels * kSamples);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      for (const auto& o : kSampleOffsets) {
        sample_rays_.push_back(pixel_ray(camera_, x + o[0], y + o[1]));
      }
    }
  }
  radiance_.resize(pixels);
  scratch_.resize(pixels);
  if (camera_.vignetting > 0.0) {
    vignette_.reserve(pixels);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        vignette_.push_back(static_cast<float>(vignetting_factor(camera_, x, y)));
      }
    }
  }
  textures_note_ = "procedural textures";
  if (camera_.textures == "photos") {
    std::vector<std::string> missing;
    photos_.load(camera_.photo_dir, missing);
    photos_in_use_ = photos_.complete();
    if (photos_in_use_) {
      textures_note_ = "textures from the photographs in " + camera_.photo_dir;
    } else {
      textures_note_ = "procedural textures: camera.textures is photos but " +
                       (missing.empty() ? camera_.photo_dir : missing.front()) +
                       " (the photographs come with the Debian package "
                       "python3-skimage, which tools/setup.sh installs)";
    }
  }
}

double Renderer::photo_albedo(int surface, double a, double b, double footprint) const {
  enum Photo : std::size_t { kBrick = 0, kGravel = 1, kGrass = 2, kFirstPicture = 3 };
  const std::size_t pictures = photos_.size() - kFirstPicture;
  if (surface == 0) {
    constexpr double kTile = 1.0;
    return 0.2 + 0.45 * photos_.sample(kGravel, a / kTile, b / kTile, footprint / kTile);
  }
  if (surface == 1) {
    return 0.85;
  }
  if (surface >= 6 && surface < first_wall_surface_) {
    constexpr double kTile = 0.8;
    const std::uint64_t h = hash3(seed_, surface, 0, 3);
    const std::size_t photo = kFirstPicture + h % pictures;
    return 0.1 + 0.8 * photos_.sample(photo, a / kTile, -b / kTile, footprint / kTile);
  }
  // Walls: bricks or paint, with framed pictures hung in 1 m cells.
  constexpr double kCell = 1.0;
  const std::int64_t ci = cell(a, kCell);
  const std::uint64_t h = hash3(seed_ ^ static_cast<std::uint64_t>(surface), ci, 0, 4);
  if (h % 4 != 0) {
    const std::size_t photo = kFirstPicture + (h >> 8) % pictures;
    const double width = 0.45 + 0.35 * unit(h, 16);
    const double height = width * photos_.aspect(photo);
    const double left = static_cast<double>(ci) * kCell + (kCell - width) * unit(h, 32);
    const double bottom = 0.3 + 0.4 * unit(h, 48);
    constexpr double kFrame = 0.03;
    const double s = (a - left) / width, t = (bottom + height - b) / height;
    if (s >= 0.0 && s < 1.0 && t >= 0.0 && t < 1.0) {
      return 0.05 + 0.9 * photos_.sample(photo, s, t, footprint / width);
    }
    if (a > left - kFrame && a < left + width + kFrame && b > bottom - kFrame &&
        b < bottom + height + kFrame) {
      return 0.12;
    }
  }
  if (surface % 2 == 0) {
    constexpr double kTile = 1.2;
    // The photograph's courses run down the picture: turned a quarter to run along the wall.
    return 0.25 + 0.6 * photos_.sample(kBrick, -b / kTile, a / kTile, footprint / kTile);
  }
  constexpr double kTile = 2.0;
  return 0.62 + 0.2 * photos_.sample(kGrass, a / kTile, -b / kTile, footprint / kTile);
}

double Renderer::albedo(int surface, double a, double b) const {
  const std::uint64_t sid = static_cast<std::uint64_t>(surface) + 1;
  if (surface == 0) {
    // Floor: planks 0.15 m wide, staggered, each its own shade, with fine grain.
    const std::int64_t row = cell(b, 0.15);
    const double offset = unit(hash3(seed_, row, 0, 99), 0) * 1.2;
    const std::int64_t plank = cell(a + offset, 1.2);
    const double shade = 0.30 + 0.25 * unit(hash3(seed_, row, plank, 98), 8);
    const double grain = 0.04 * std::sin(b * 140.0 + 3.0 * unit(hash3(seed_, row, plank, 97), 16));
    return shade + grain;
  }
  if (surface == 1) {
    return 0.85;
  }
  // Walls and furniture: coarse 0.5 m cells, each plain, a checker, random blocks or a poster.
  const bool furniture = surface >= 6 && surface < first_wall_surface_;
  const double coarse = furniture ? 0.3 : 0.5;
  const std::int64_t ci = cell(a, coarse), cj = cell(b, coarse);
  const std::uint64_t h = hash3(seed_ ^ sid, ci, cj, 1);
  const double base = furniture ? 0.25 + 0.4 * unit(h, 0) : 0.55 + 0.25 * unit(h, 0);
  switch (h % 8) {
    case 0:
    case 1:
    case 2:
      return base;
    case 3: {  // checker of two random levels
      const double s = coarse / 4.0;
      const bool odd = ((cell(a, s) + cell(b, s)) & 1) != 0;
      return odd ? base : 0.1 + 0.3 * unit(h, 16);
    }
    case 4: {  // blocks of random levels
      const double s = coarse / 3.0;
      return 0.1 + 0.8 * unit(hash3(seed_ ^ sid, cell(a, s), cell(b, s), 2), 0);
    }
    case 5:
    case 6: {  // a dark poster with a light mark inside the cell
      const double fa = a / coarse - static_cast<double>(ci),
                   fb = b / coarse - static_cast<double>(cj);
      const double m = 0.15 + 0.1 * unit(h, 32);
      if (fa < m || fa > 1.0 - m || fb < m || fb > 1.0 - m) {
        return base;
      }
      const bool inner = fa > 0.4 && fa < 0.6 && fb > 0.3;
      return inner ? 0.9 : 0.08 + 0.2 * unit(h, 48);
    }
    default: {  // horizontal stripes
      const double s = coarse / 5.0;
      return (cell(b, s) & 1) != 0 ? base : base * 0.4;
    }
  }
}

int Renderer::surface_at(const Pose3& world_camera, int x, int y) const {
  if (x < 0 || y < 0 || x >= camera_.width || y >= camera_.height) {
    return -1;
  }
  const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(camera_.width) +
                        static_cast<std::size_t>(x);
  return cast(world_camera.position, world_camera.rotation * rays_[i]).surface;
}

Renderer::SurfacePoint Renderer::point_at(const Pose3& world_camera, double u, double v) const {
  const Vec3 dir = world_camera.rotation * pixel_ray(camera_, u, v);
  const Hit hit = cast(world_camera.position, dir);
  if (hit.surface < 0) {
    return {};
  }
  return {hit.surface, world_camera.position + hit.distance * dir, hit.distance};
}

Renderer::Hit Renderer::cast(Vec3 o, Vec3 d) const {
  Hit best{std::numeric_limits<double>::infinity(), -1, 0.0, 0.0, 1.0};
  auto consider = [&](double t, int surface, double a, double b, double cosi) {
    if (t > 1e-6 && t < best.distance) {
      best = Hit{t, surface, a, b, cosi};
    }
  };
  // Room planes (the camera is inside the room).
  if (d.z < 0.0) {
    const double t = -o.z / d.z;
    consider(t, 0, o.x + t * d.x, o.y + t * d.y, -d.z);
  } else if (d.z > 0.0) {
    const double t = (room_.z - o.z) / d.z;
    consider(t, 1, o.x + t * d.x, o.y + t * d.y, d.z);
  }
  if (d.y < 0.0) {
    const double t = -o.y / d.y;
    consider(t, 2, o.x + t * d.x, o.z + t * d.z, -d.y);
  } else if (d.y > 0.0) {
    const double t = (room_.y - o.y) / d.y;
    consider(t, 3, room_.x - (o.x + t * d.x), o.z + t * d.z, d.y);
  }
  if (d.x < 0.0) {
    const double t = -o.x / d.x;
    consider(t, 4, room_.y - (o.y + t * d.y), o.z + t * d.z, -d.x);
  } else if (d.x > 0.0) {
    const double t = (room_.x - o.x) / d.x;
    consider(t, 5, o.y + t * d.y, o.z + t * d.z, d.x);
  }
  // Furniture boxes: entry face of the slab test.
  for (std::size_t k = 0; k < boxes_.size(); ++k) {
    const Box& b = boxes_[k];
    double t0 = 0.0, t1 = best.distance;
    int axis = -1;
    const double od[3] = {o.x, o.y, o.z}, dd[3] = {d.x, d.y, d.z};
    const double lo[3] = {b.min.x, b.min.y, b.min.z}, hi[3] = {b.max.x, b.max.y, b.max.z};
    bool miss = false;
    for (int i = 0; i < 3 && !miss; ++i) {
      if (std::abs(dd[i]) < 1e-12) {
        miss = od[i] < lo[i] || od[i] > hi[i];
        continue;
      }
      double ta = (lo[i] - od[i]) / dd[i], tb = (hi[i] - od[i]) / dd[i];
      if (ta > tb) {
        std::swap(ta, tb);
      }
      if (ta > t0) {
        t0 = ta;
        axis = i;
      }
      t1 = std::min(t1, tb);
      miss = t0 > t1;
    }
    if (miss || axis < 0) {
      continue;
    }
    const Vec3 p = o + t0 * d;
    // An interior wall's two faces (and its jambs) are two surfaces, each with its own pattern.
    const int surface =
        6 + static_cast<int>(k) < first_wall_surface_
            ? 6 + static_cast<int>(k)
            : 2 * (6 + static_cast<int>(k)) - first_wall_surface_ + (dd[axis] < 0.0 ? 1 : 0);
    const double cosi = std::abs(dd[axis]);
    if (axis == 0) {
      consider(t0, surface, p.y, p.z, cosi);
    }
    if (axis == 1) {
      consider(t0, surface, p.x, p.z, cosi);
    }
    if (axis == 2) {
      consider(t0, surface, p.x, p.y, cosi);
    }
  }
  return best;
}

void Renderer::render(const Pose3& wc, double exposure, Random& rng, readers::GrayImage& out) {
  render(std::vector<Pose3>{wc}, exposure, rng, out);
}

void Renderer::render(const std::vector<Pose3>& poses, double exposure, Random& rng,
                      readers::GrayImage& out, double gain) {
  const int w = camera_.width, h = camera_.height;
  const std::size_t n = rays_.size();
  if (poses.empty()) {
    return;
  }
  const std::size_t pose_count = poses.size();
  const std::size_t per_pixel = std::max(pose_count, kSamples);
  const double focal = 0.5 * (camera_.fx + camera_.fy);
  for (std::size_t i = 0; i < n; ++i) {
    double sum = 0.0;
    for (std::size_t k = 0; k < per_pixel; ++k) {
      const Pose3& wc = poses[k % pose_count];
      const Vec3 dir = wc.rotation * sample_rays_[i * kSamples + k % kSamples];
      const Hit hit = cast(wc.position, dir);
      double v = 0.5;
      if (hit.surface >= 0) {
        const double shade = 0.45 + 0.55 * hit.cos_incidence;
        const double falloff = 1.0 / (1.0 + 0.04 * hit.distance * hit.distance);
        const double footprint =
            hit.distance / (focal * std::sqrt(std::max(hit.cos_incidence, 0.05)));
        const double rho = photos_in_use_ ? photo_albedo(hit.surface, hit.a, hit.b, footprint)
                                          : albedo(hit.surface, hit.a, hit.b);
        v = rho * shade * (0.6 + 0.4 * falloff);
      }
      sum += v;
    }
    radiance_[i] = static_cast<float>(sum / static_cast<double>(per_pixel) * exposure * 255.0);
    if (!vignette_.empty()) {
      radiance_[i] *= vignette_[i];
    }
  }
  // A little blur: separable [1 b 1] / (2 + b) kernels, b from the scenario (0: none).
  if (blur_ > 0.0) {
    const float c = static_cast<float>(1.0 / (1.0 + 2.0 * blur_));
    const float s = static_cast<float>(blur_ / (1.0 + 2.0 * blur_));
    for (int y = 0; y < h; ++y) {
      const std::size_t r = static_cast<std::size_t>(y) * static_cast<std::size_t>(w);
      for (int x = 0; x < w; ++x) {
        const std::size_t xl = static_cast<std::size_t>(std::max(0, x - 1));
        const std::size_t xr = static_cast<std::size_t>(std::min(w - 1, x + 1));
        scratch_[r + static_cast<std::size_t>(x)] = c * radiance_[r + static_cast<std::size_t>(x)] +
                                                    s * (radiance_[r + xl] + radiance_[r + xr]);
      }
    }
    for (int y = 0; y < h; ++y) {
      const std::size_t up =
          static_cast<std::size_t>(std::max(0, y - 1)) * static_cast<std::size_t>(w);
      const std::size_t dn =
          static_cast<std::size_t>(std::min(h - 1, y + 1)) * static_cast<std::size_t>(w);
      const std::size_t r = static_cast<std::size_t>(y) * static_cast<std::size_t>(w);
      for (int x = 0; x < w; ++x) {
        const std::size_t xi = static_cast<std::size_t>(x);
        radiance_[r + xi] = c * scratch_[r + xi] + s * (scratch_[up + xi] + scratch_[dn + xi]);
      }
    }
  }
  out.width = w;
  out.height = h;
  out.pixels.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double signal = static_cast<double>(radiance_[i]);
    const double sigma = shot_gain_ > 0.0
                             ? sensor_noise_sigma(noise_sigma_, shot_gain_, signal, gain)
                             : noise_sigma_;
    const double v = signal + rng.gaussian(sigma);
    out.pixels[i] = static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
  }
}

}  // namespace cleanslam::sim_hal::sim
