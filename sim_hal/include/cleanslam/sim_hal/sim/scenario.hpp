#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "cleanslam/readers/result.hpp"
#include "cleanslam/sim_hal/sim/sim_math.hpp"

// A simulation scenario: the world, the robot's path and every sensor's noise, read from YAML
// (sim_hal/scenarios/*.yaml, built in by name). A scenario may name a `base` scenario whose
// values it overrides, key by key. Lengths in metres, angles in degrees where the key says so.
namespace cleanslam::sim_hal::sim {

struct Box {
  Vec3 min;
  Vec3 max;
  // Furniture only (from world.moved): the box, with the landmarks on it, is moved by this after
  // the landmarks are placed (the same home on another day, with a few objects moved).
  Vec3 moved_by{};
};

struct StopSpec {
  double at_s = 0.0;  // path time at which the robot stops
  double duration_s = 0.0;
};

struct Scenario {
  std::string name;
  std::uint64_t seed = 1;
  double start_time_s = 1.0;  // clock value of the first sample
  double duration_s = 0.0;    // 0: until the path ends (wander paths need it)

  struct World {
    Vec3 size{6.0, 5.0, 2.5};    // room (or arena) from (0,0,0) to size
    std::vector<Box> furniture;  // world.moved: [{furniture: index, by: [dx, dy]}] sets moved_by
    // Interior walls (thin full-height boxes; doors are the gaps between them): they hide
    // landmarks like furniture, render with the walls' textures, carry
    // landmarks.on_interior_walls, and are not what hides an outer wall's point at placement.
    std::vector<Box> walls;
    // The stream that places the landmarks and textures; unset: `seed`. Two runs with one
    // world.seed and different seeds see the same world with other noise.
    std::optional<std::uint64_t> seed;
  } world;

  struct Landmarks {
    int on_walls = 90;
    int on_furniture = 30;
    int on_interior_walls = 0;  // spread over the vertical faces of world.walls by area
    int posts = 0;              // free-standing points, visible from every side
    double min_height = 0.05;
    double max_height = 2.0;
    double post_height = 0.10;
    double post_height_spread = 0.03;
    double post_margin = 1.0;  // from the arena's walls
  } landmarks;

  struct Person {
    bool enabled = false;
    int points = 12;
    double radius = 0.2;
    double height = 1.7;
    double speed = 0.8;
    Vec3 from{1.0, 1.0, 0.0};
    Vec3 to{5.0, 4.0, 0.0};
  } person;

  struct Path {
    // boustrophedon | wander | waypoints | calibration | standstill
    std::string type = "boustrophedon";
    double speed = 0.2;
    double turn_rate = 0.8;  // rad/s, turning in place
    double lane_spacing = 0.3;
    double margin = 0.55;  // from the walls
    bool wall_follow = true;
    int repeats = 1;
    std::vector<StopSpec> stops;
    // waypoints: straight runs between the points (x, y), turns in place at each; the robot starts
    // at the first (the dock) facing the second
    std::vector<std::array<double, 2>> waypoints;
    // calibration (the wheels' calibration drive, tools/calibrate): a standstill of settle_s, a
    // straight run of straight_m at speed, a standstill of settle_s, spin_turns full turns in place
    // counter-clockwise, settle_s still, as many clockwise, settle_s still. standstill: the robot
    // stands still for duration_s (the gyro's noise, tools/calibrate).
    double straight_m = 3.0;
    double spin_turns = 2.0;
    double settle_s = 10.0;
    // wander
    double min_speed = 0.1;
    double max_speed = 0.2;
    double min_run = 0.3;
    double max_run = 3.0;
    double min_turn_deg = 30.0;
    double max_turn_deg = 180.0;
    double pause_probability = 0.0;
    double max_pause_s = 0.0;
    double goal_bias = 0.5;  // probability that a turn heads (roughly) for a random goal
    // kidnapping: at path time kidnap_at_s, the robot is lifted and set down where the path is
    // kidnap_skip_s later, lift_duration_s later
    double kidnap_at_s = 0.0;
    double kidnap_skip_s = 0.0;
    double lift_duration_s = 3.0;
  } path;

  struct Robot {
    double wheel_base = 0.235;  // nominal (written to sensors.yaml)
    double ticks_per_meter = 4000.0;
    std::int64_t initial_ticks = 0;
    double radius = 0.2;  // footprint: a waypoint path keeps this far from walls and boxes
  } robot;

  struct Camera {
    // features: features.csv from the point landmarks; images: rendered cam0/ images;
    // both: both (the point landmarks are not drawn in the images); checkerboard: images of a
    // planar checkerboard (the `checkerboard` section), not of the room.
    std::string mode = "features";
    int width = 320;
    int height = 240;
    double fx = 280.0;
    double fy = 280.0;
    double cx = 159.5;
    double cy = 119.5;
    std::array<double, 4> distortion{};
    double rate_hz = 2.0;
    double height_m = 0.10;
    double forward_m = 0.10;
    double tilt_deg = 10.0;
    double jitter_s = 0.005;
    double pixel_noise = 0.5;
    double outlier_probability = 0.0;
    double min_range = 0.3;
    double max_range = 6.0;
    double min_facing_cos = 0.2;  // wall points seen at grazing angles are dropped
    int max_features = 64;
    // images mode
    double image_noise = 2.0;                 // gray levels, std. dev. per pixel
    double blur = 0.5;                        // weight of the neighbours in a 3x3 blur (0: none)
    double exposure_walk = 0.03;              // relative gain change per frame (random walk)
    double exposure_jump_probability = 0.02;  // per frame: a sudden gain change of up to 30 %
    std::string image_format = "png";         // png | pgm
    // The camera's effects in images mode; each off at its default.
    std::string textures = "procedural";  // procedural | photos (photographs from photo_dir)
    std::string photo_dir = "/usr/lib/python3/dist-packages/skimage/data";
    double exposure_time_s = 0.0;  // motion blur: the image integrates the motion over this time
    int exposure_samples = 8;      // poses the exposure is integrated over (exposure_time_s > 0)
    double shot_noise_gain = 0.0;  // gray levels per photo-electron: variance = gain * signal
    double vignetting = 0.0;       // 1: the cos^4 law of the pinhole; 0: none
    bool auto_exposure = false;    // gain steps towards auto_exposure_target, one per frame
    double auto_exposure_target = 110.0;       // mean gray level
    double auto_exposure_step_ev = 1.0 / 3.0;  // gain quantum, in stops
  } camera;

  struct Gyro {
    double rate_hz = 100.0;
    double noise_density = 0.0005;  // rad/s/sqrt(Hz)
    double initial_bias = 0.002;    // rad/s
    double bias_walk = 0.0001;      // rad/s/sqrt(s)
    double scale_error = 0.005;
  } gyro;

  struct Encoders {
    double rate_hz = 20.0;
    double scale_error_left = 0.01;
    double scale_error_right = -0.008;
    double wheel_base_error = 0.02;  // true = nominal * (1 + error)
    double distance_noise = 0.01;    // relative, per sample and wheel
    double slip_rate_hz = 0.01;      // slip events per second
    double slip_duration_s = 0.5;
    double slip_fraction = 0.3;  // extra counts of the slipping wheel
  } encoders;

  struct GroundTruth {
    double rate_hz = 100.0;
  } groundtruth;

  // camera.mode checkerboard: each frame is a view of this planar board (tools/calibrate camera),
  // from a pose of its own, through the scenario's camera (intrinsics and distortion).
  struct Checkerboard {
    int cols = 9;  // inner corners along the board's x
    int rows = 6;
    double square_m = 0.03;
    // Set: the board lies on the floor, its first inner corner at (x, y) in the body frame, its
    // cols along yaw_deg from the body's x axis, seen through the camera's mount in every frame
    // (the mount's calibration); unset: a pose of its own in each frame.
    std::optional<std::array<double, 3>> on_floor;  // x, y, yaw_deg
  } checkerboard;

  [[nodiscard]] std::uint64_t world_seed() const { return world.seed.value_or(seed); }
};

// The solid boxes of the world as the robot meets them: the furniture at its place (moved_by
// applied), then the interior walls.
std::vector<Box> solid_boxes(const Scenario::World& world);

// Slab test of the segment a + s (b - a), s in [0, 1], against a box (touching counts).
[[nodiscard]] bool segment_hits_box(Vec3 a, Vec3 b, const Box& box);

// Names of the built-in scenarios.
std::vector<std::string> builtin_scenario_names();
// The YAML text of a built-in scenario, or an empty string.
std::string builtin_scenario_text(const std::string& name);

// Loads a scenario by built-in name or file path; `overrides` are "key.path=value" (value in YAML
// syntax, e.g. "camera.rate_hz=1" or "world.size=[8, 6, 2.5]"). Unknown keys are errors.
readers::Result<Scenario> load_scenario(const std::string& name_or_path,
                                        const std::vector<std::string>& overrides = {});

}  // namespace cleanslam::sim_hal::sim
