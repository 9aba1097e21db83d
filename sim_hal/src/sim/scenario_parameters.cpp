#include "cleanslam/sim_hal/sim/scenario_parameters.hpp"

#include <array>
#include <string_view>
#include <vector>

#include "cleanslam/readers/parameter_yaml.hpp"

namespace cleanslam::sim_hal::sim {

namespace {

using hal::numbers_field;
using hal::parameter_field;
using hal::text_field;
using P = hal::Parameter<Scenario>;
using S = Scenario;

void vec3_get(const void* p, double* out) {
  const Vec3& v = *static_cast<const Vec3*>(p);
  out[0] = v.x;
  out[1] = v.y;
  out[2] = v.z;
}

void vec3_set(void* p, const double* in) {
  *static_cast<Vec3*>(p) = Vec3{in[0], in[1], in[2]};
}

hal::ParameterField vec3_field(Vec3& v) {
  return {
      hal::ParameterType::kNumbers, &v, 1.0, false, 3, {}, nullptr, nullptr, &vec3_get, &vec3_set};
}

constexpr std::array<std::string_view, 5> kPathTypes{"boustrophedon", "wander", "waypoints",
                                                     "calibration", "standstill"};
constexpr std::array<std::string_view, 4> kCameraModes{"features", "images", "both",
                                                       "checkerboard"};
constexpr std::array<std::string_view, 2> kImageFormats{"png", "pgm"};
constexpr std::array<std::string_view, 2> kTextures{"procedural", "photos"};

constexpr double kDay = 86400.0;

// Key, member, default, range (lo, hi, lo open), unit, meaning. A text's default is the struct's.
const std::array kScenarioParameters{
    P{"name", [](S& s) { return parameter_field(s.name); }, 0.0, 0.0, 0.0, false, "",
      "the dataset's name; unset: the file's"},
    P{"seed", [](S& s) { return parameter_field(s.seed); }, 1.0, 0.0, 9007199254740992.0, false, "",
      "the sensors' noise"},
    P{"start_time_s", [](S& s) { return parameter_field(s.start_time_s); }, 1.0, 0.0, 1e12, false,
      "s", "clock value of the first sample"},
    P{"duration_s", [](S& s) { return parameter_field(s.duration_s); }, 0.0, 0.0, kDay, false, "s",
      "0: until the path ends (a wander path and a standstill need it)"},

    P{"world.size", [](S& s) { return vec3_field(s.world.size); }, 0.0, 0.0, 1000.0, true, "m",
      "room (or arena) from (0, 0, 0) to size, at most 100 m high"},

    P{"landmarks.on_walls", [](S& s) { return parameter_field(s.landmarks.on_walls); }, 90.0, 0.0,
      100000.0, false, "", "points on the room's walls"},
    P{"landmarks.on_furniture", [](S& s) { return parameter_field(s.landmarks.on_furniture); },
      30.0, 0.0, 100000.0, false, "", "points on the furniture"},
    P{"landmarks.on_interior_walls",
      [](S& s) { return parameter_field(s.landmarks.on_interior_walls); }, 0.0, 0.0, 100000.0,
      false, "", "points on world.walls' vertical faces, spread by area"},
    P{"landmarks.posts", [](S& s) { return parameter_field(s.landmarks.posts); }, 0.0, 0.0,
      100000.0, false, "", "free-standing points, visible from every side"},
    P{"landmarks.min_height", [](S& s) { return parameter_field(s.landmarks.min_height); }, 0.05,
      0.0, 100.0, false, "m", "lowest point on a wall or furniture, at most max_height"},
    P{"landmarks.max_height", [](S& s) { return parameter_field(s.landmarks.max_height); }, 2.0,
      0.0, 100.0, false, "m", "highest point on a wall or furniture"},
    P{"landmarks.post_height", [](S& s) { return parameter_field(s.landmarks.post_height); }, 0.10,
      0.0, 100.0, false, "m", "a post's mean height"},
    P{"landmarks.post_height_spread",
      [](S& s) { return parameter_field(s.landmarks.post_height_spread); }, 0.03, 0.0, 100.0, false,
      "m", "a post's height spread"},
    P{"landmarks.post_margin", [](S& s) { return parameter_field(s.landmarks.post_margin); }, 1.0,
      0.0, 1000.0, false, "m", "posts keep this far from the arena's walls"},

    P{"person.enabled", [](S& s) { return parameter_field(s.person.enabled); }, 0.0, 0.0, 1.0,
      false, "", "a person walks through the room (moving points)"},
    P{"person.points", [](S& s) { return parameter_field(s.person.points); }, 12.0, 0.0, 100000.0,
      false, "", "points on the person"},
    P{"person.radius", [](S& s) { return parameter_field(s.person.radius); }, 0.2, 0.0, 100.0,
      false, "m", "the person's radius"},
    P{"person.height", [](S& s) { return parameter_field(s.person.height); }, 1.7, 0.0, 100.0,
      false, "m", "the person's height"},
    P{"person.speed", [](S& s) { return parameter_field(s.person.speed); }, 0.8, 0.0, 100.0, false,
      "m/s", "walking speed, back and forth between from and to"},
    P{"person.from", [](S& s) { return vec3_field(s.person.from); }, 0.0, -1000.0, 1000.0, false,
      "m", "one end of the walk"},
    P{"person.to", [](S& s) { return vec3_field(s.person.to); }, 0.0, -1000.0, 1000.0, false, "m",
      "the other end"},

    P{"path.type", [](S& s) { return text_field(s.path.type, kPathTypes); }, 0.0, 0.0, 0.0, false,
      "", "how the robot drives"},
    P{"path.speed", [](S& s) { return parameter_field(s.path.speed); }, 0.2, 0.0, 5.0, false, "m/s",
      "straight-line speed (positive for boustrophedon, waypoints and calibration)"},
    P{"path.turn_rate", [](S& s) { return parameter_field(s.path.turn_rate); }, 0.8, 0.0, 100.0,
      true, "rad/s", "turning in place"},
    P{"path.lane_spacing", [](S& s) { return parameter_field(s.path.lane_spacing); }, 0.3, 0.0,
      100.0, true, "m", "boustrophedon: between lanes"},
    P{"path.margin", [](S& s) { return parameter_field(s.path.margin); }, 0.55, 0.0, 1000.0, false,
      "m", "from the walls; leaves room to drive in world.size"},
    P{"path.wall_follow", [](S& s) { return parameter_field(s.path.wall_follow); }, 1.0, 0.0, 1.0,
      false, "", "boustrophedon: a lap along the walls first"},
    P{"path.repeats", [](S& s) { return parameter_field(s.path.repeats); }, 1.0, 1.0, 1000.0, false,
      "", "the path driven this many times"},
    P{"path.straight_m", [](S& s) { return parameter_field(s.path.straight_m); }, 3.0, 0.0, 1000.0,
      false, "m", "calibration: the straight run (positive)"},
    P{"path.spin_turns", [](S& s) { return parameter_field(s.path.spin_turns); }, 2.0, 0.0, 1000.0,
      false, "", "calibration: full turns in place each way (positive)"},
    P{"path.settle_s", [](S& s) { return parameter_field(s.path.settle_s); }, 10.0, 0.0, kDay,
      false, "s", "calibration: each standstill (positive)"},
    P{"path.min_speed", [](S& s) { return parameter_field(s.path.min_speed); }, 0.1, 0.0, 5.0,
      false, "m/s", "wander: slowest run (positive)"},
    P{"path.max_speed", [](S& s) { return parameter_field(s.path.max_speed); }, 0.2, 0.0, 5.0,
      false, "m/s", "wander: fastest run, at least min_speed"},
    P{"path.min_run", [](S& s) { return parameter_field(s.path.min_run); }, 0.3, 0.0, 1000.0, false,
      "m", "wander: shortest run"},
    P{"path.max_run", [](S& s) { return parameter_field(s.path.max_run); }, 3.0, 0.0, 1000.0, false,
      "m", "wander: longest run"},
    P{"path.min_turn_deg", [](S& s) { return parameter_field(s.path.min_turn_deg); }, 30.0, 0.0,
      360.0, false, "deg", "wander: smallest turn"},
    P{"path.max_turn_deg", [](S& s) { return parameter_field(s.path.max_turn_deg); }, 180.0, 0.0,
      360.0, false, "deg", "wander: largest turn"},
    P{"path.pause_probability", [](S& s) { return parameter_field(s.path.pause_probability); }, 0.0,
      0.0, 1.0, false, "", "wander: a run ends in a pause"},
    P{"path.max_pause_s", [](S& s) { return parameter_field(s.path.max_pause_s); }, 0.0, 0.0, kDay,
      false, "s", "wander: longest pause"},
    P{"path.goal_bias", [](S& s) { return parameter_field(s.path.goal_bias); }, 0.5, 0.0, 1.0,
      false, "", "wander: probability that a turn heads (roughly) for a random goal"},
    P{"path.kidnap_at_s", [](S& s) { return parameter_field(s.path.kidnap_at_s); }, 0.0, 0.0, kDay,
      false, "s", "path time the robot is lifted, 0: never"},
    P{"path.kidnap_skip_s", [](S& s) { return parameter_field(s.path.kidnap_skip_s); }, 0.0, 0.0,
      kDay, false, "s", "it is set down where the path is this much later"},
    P{"path.lift_duration_s", [](S& s) { return parameter_field(s.path.lift_duration_s); }, 3.0,
      0.0, kDay, false, "s", "how long it is in the air"},

    P{"robot.wheel_base", [](S& s) { return parameter_field(s.robot.wheel_base); }, 0.235, 0.0,
      10.0, true, "m", "nominal (written to sensors.yaml)"},
    P{"robot.ticks_per_meter", [](S& s) { return parameter_field(s.robot.ticks_per_meter); },
      4000.0, 0.0, 1e7, true, "1/m", "nominal encoder ticks per metre"},
    P{"robot.initial_ticks", [](S& s) { return parameter_field(s.robot.initial_ticks); }, 0.0,
      -1e15, 1e15, false, "", "the encoders' count at the start"},
    P{"robot.radius", [](S& s) { return parameter_field(s.robot.radius); }, 0.2, 0.0, 2.0, false,
      "m", "footprint: a waypoint path keeps this far from walls and boxes"},

    P{"camera.mode", [](S& s) { return text_field(s.camera.mode, kCameraModes); }, 0.0, 0.0, 0.0,
      false, "",
      "features.csv from the point landmarks, rendered images, both, or a checkerboard's images"},
    P{"camera.width", [](S& s) { return parameter_field(s.camera.width); }, 320.0, 1.0, 4096.0,
      false, "px", "image width"},
    P{"camera.height", [](S& s) { return parameter_field(s.camera.height); }, 240.0, 1.0, 4096.0,
      false, "px", "image height"},
    P{"camera.fx", [](S& s) { return parameter_field(s.camera.fx); }, 280.0, 0.0, 1e6, true, "px",
      "focal length"},
    P{"camera.fy", [](S& s) { return parameter_field(s.camera.fy); }, 280.0, 0.0, 1e6, true, "px",
      "focal length"},
    P{"camera.cx", [](S& s) { return parameter_field(s.camera.cx); }, 159.5, -1e6, 1e6, false, "px",
      "principal point"},
    P{"camera.cy", [](S& s) { return parameter_field(s.camera.cy); }, 119.5, -1e6, 1e6, false, "px",
      "principal point"},
    P{"camera.distortion", [](S& s) { return numbers_field(s.camera.distortion); }, 0.0, -100.0,
      100.0, false, "", "radial-tangential k1 k2 p1 p2"},
    P{"camera.rate_hz", [](S& s) { return parameter_field(s.camera.rate_hz); }, 2.0, 0.0, 100.0,
      true, "Hz", "frames per second"},
    P{"camera.height_m", [](S& s) { return parameter_field(s.camera.height_m); }, 0.10, -100.0,
      100.0, false, "m", "above the floor"},
    P{"camera.forward_m", [](S& s) { return parameter_field(s.camera.forward_m); }, 0.10, -100.0,
      100.0, false, "m", "ahead of the wheel axle"},
    P{"camera.tilt_deg", [](S& s) { return parameter_field(s.camera.tilt_deg); }, 10.0, -90.0, 90.0,
      false, "deg", "upwards from the horizontal"},
    P{"camera.jitter_s", [](S& s) { return parameter_field(s.camera.jitter_s); }, 0.005, 0.0, 1.0,
      false, "s", "std. dev. of a frame's stamp"},
    P{"camera.pixel_noise", [](S& s) { return parameter_field(s.camera.pixel_noise); }, 0.5, 0.0,
      100.0, false, "px", "std. dev. of a feature's position"},
    P{"camera.outlier_probability",
      [](S& s) { return parameter_field(s.camera.outlier_probability); }, 0.0, 0.0, 1.0, false, "",
      "a feature placed at random"},
    P{"camera.min_range", [](S& s) { return parameter_field(s.camera.min_range); }, 0.3, 0.0,
      10000.0, false, "m", "nearest point seen, at most max_range"},
    P{"camera.max_range", [](S& s) { return parameter_field(s.camera.max_range); }, 6.0, 0.0,
      10000.0, false, "m", "farthest point seen"},
    P{"camera.min_facing_cos", [](S& s) { return parameter_field(s.camera.min_facing_cos); }, 0.2,
      -1.0, 1.0, false, "", "wall points seen at grazing angles are dropped"},
    P{"camera.max_features", [](S& s) { return parameter_field(s.camera.max_features); }, 64.0, 0.0,
      100000.0, false, "", "features a frame lists at most"},
    P{"camera.image_noise", [](S& s) { return parameter_field(s.camera.image_noise); }, 2.0, 0.0,
      255.0, false, "", "gray levels, std. dev. per pixel"},
    P{"camera.blur", [](S& s) { return parameter_field(s.camera.blur); }, 0.5, 0.0, 100.0, false,
      "", "weight of the neighbours in a 3x3 blur (0: none)"},
    P{"camera.exposure_walk", [](S& s) { return parameter_field(s.camera.exposure_walk); }, 0.03,
      0.0, 1.0, false, "", "relative gain change per frame (random walk)"},
    P{"camera.exposure_jump_probability",
      [](S& s) { return parameter_field(s.camera.exposure_jump_probability); }, 0.02, 0.0, 1.0,
      false, "", "per frame: a sudden gain change of up to 30 %"},
    P{"camera.image_format", [](S& s) { return text_field(s.camera.image_format, kImageFormats); },
      0.0, 0.0, 0.0, false, "", "the images' files"},
    P{"camera.textures", [](S& s) { return text_field(s.camera.textures, kTextures); }, 0.0, 0.0,
      0.0, false, "", "procedural, or photographs from photo_dir"},
    P{"camera.photo_dir", [](S& s) { return parameter_field(s.camera.photo_dir); }, 0.0, 0.0, 0.0,
      false, "", "textures: photos"},
    P{"camera.exposure_time_s", [](S& s) { return parameter_field(s.camera.exposure_time_s); }, 0.0,
      0.0, 1.0, false, "s",
      "motion blur: the image integrates the motion over this time, at most a frame period"},
    P{"camera.exposure_samples", [](S& s) { return parameter_field(s.camera.exposure_samples); },
      8.0, 1.0, 64.0, false, "", "poses the exposure is integrated over (exposure_time_s > 0)"},
    P{"camera.shot_noise_gain", [](S& s) { return parameter_field(s.camera.shot_noise_gain); }, 0.0,
      0.0, 10.0, false, "", "gray levels per photo-electron: variance = gain * signal"},
    P{"camera.vignetting", [](S& s) { return parameter_field(s.camera.vignetting); }, 0.0, 0.0,
      10.0, false, "", "1: the cos^4 law of the pinhole; 0: none"},
    P{"camera.auto_exposure", [](S& s) { return parameter_field(s.camera.auto_exposure); }, 0.0,
      0.0, 1.0, false, "", "gain steps towards auto_exposure_target, one per frame"},
    P{"camera.auto_exposure_target",
      [](S& s) { return parameter_field(s.camera.auto_exposure_target); }, 110.0, 1.0, 254.0, false,
      "", "mean gray level"},
    P{"camera.auto_exposure_step_ev",
      [](S& s) { return parameter_field(s.camera.auto_exposure_step_ev); }, 1.0 / 3.0, 0.01, 2.0,
      false, "EV", "gain quantum, in stops"},

    P{"gyro.rate_hz", [](S& s) { return parameter_field(s.gyro.rate_hz); }, 100.0, 0.0, 10000.0,
      true, "Hz", "samples per second"},
    P{"gyro.noise_density", [](S& s) { return parameter_field(s.gyro.noise_density); }, 0.0005, 0.0,
      1.0, false, "rad/s/sqrt(Hz)", "white noise"},
    P{"gyro.initial_bias", [](S& s) { return parameter_field(s.gyro.initial_bias); }, 0.002, -1.0,
      1.0, false, "rad/s", "bias at the start"},
    P{"gyro.bias_walk", [](S& s) { return parameter_field(s.gyro.bias_walk); }, 0.0001, 0.0, 1.0,
      false, "rad/s/sqrt(s)", "bias random walk"},
    P{"gyro.scale_error", [](S& s) { return parameter_field(s.gyro.scale_error); }, 0.005, -0.5,
      0.5, false, "", "relative rate scale error"},

    P{"encoders.rate_hz", [](S& s) { return parameter_field(s.encoders.rate_hz); }, 20.0, 0.0,
      1000.0, true, "Hz", "samples per second"},
    P{"encoders.scale_error_left",
      [](S& s) { return parameter_field(s.encoders.scale_error_left); }, 0.01, -0.5, 0.5, false, "",
      "left wheel's distance scale error"},
    P{"encoders.scale_error_right",
      [](S& s) { return parameter_field(s.encoders.scale_error_right); }, -0.008, -0.5, 0.5, false,
      "", "right wheel's distance scale error"},
    P{"encoders.wheel_base_error",
      [](S& s) { return parameter_field(s.encoders.wheel_base_error); }, 0.02, -0.5, 0.5, false, "",
      "true = nominal * (1 + error)"},
    P{"encoders.distance_noise", [](S& s) { return parameter_field(s.encoders.distance_noise); },
      0.01, 0.0, 1.0, false, "", "relative, per sample and wheel"},
    P{"encoders.slip_rate_hz", [](S& s) { return parameter_field(s.encoders.slip_rate_hz); }, 0.01,
      0.0, 10.0, false, "Hz", "slip events per second"},
    P{"encoders.slip_duration_s", [](S& s) { return parameter_field(s.encoders.slip_duration_s); },
      0.5, 0.0, 100.0, false, "s", "a slip's duration"},
    P{"encoders.slip_fraction", [](S& s) { return parameter_field(s.encoders.slip_fraction); }, 0.3,
      0.0, 1.0, false, "", "extra counts of the slipping wheel"},

    P{"groundtruth.rate_hz", [](S& s) { return parameter_field(s.groundtruth.rate_hz); }, 100.0,
      0.0, 1000.0, true, "Hz", "poses per second"},

    P{"checkerboard.cols", [](S& s) { return parameter_field(s.checkerboard.cols); }, 9.0, 2.0,
      1000.0, false, "", "inner corners along the board's x"},
    P{"checkerboard.rows", [](S& s) { return parameter_field(s.checkerboard.rows); }, 6.0, 2.0,
      1000.0, false, "", "inner corners along the board's y"},
    P{"checkerboard.square_m", [](S& s) { return parameter_field(s.checkerboard.square_m); }, 0.03,
      0.0, 10.0, true, "m", "a square's side"},
};

}  // namespace

std::span<const hal::Parameter<Scenario>> scenario_parameters() {
  return kScenarioParameters;
}

std::string scenario_keys_text() {
  const Scenario defaults{};
  std::string out =
      "# Every scenario key with its default (a built-in scenario sets some otherwise), unit\n"
      "# and range. Besides these: base (a scenario this one overrides), world.seed (the\n"
      "# landmarks' placement; unset: seed), world.furniture and world.walls ([{min: [x, y, z],\n"
      "# max: [x, y, z]}]), world.moved ([{furniture: index, by: [dx, dy]}]), path.stops\n"
      "# ([{at_s: t, duration_s: d}]), path.waypoints ([[x, y], ...]) and checkerboard.on_floor\n"
      "# ([x, y, yaw_deg]; unset: a pose of its own in each frame).\n";
  readers::write_parameters(out, scenario_parameters(), "", "", defaults, true);
  std::vector<std::string> sections;
  readers::parameter_children(scenario_parameters(), "", sections);
  for (const std::string& section : sections) {
    out.append(section).append(":\n");
    readers::write_parameters(out, scenario_parameters(), section + ".", "  ", defaults, true);
  }
  return out;
}

}  // namespace cleanslam::sim_hal::sim
