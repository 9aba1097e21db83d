#pragma once

#include <string>
#include <vector>

#include "cleanslam/readers/dataset.hpp"
#include "cleanslam/readers/result.hpp"

// The wheels' odometry constants from a calibration drive (UMBmark-like, with the gyro as the
// turn reference): the robot stands still (the gyro's bias), drives straight a measured length,
// and turns in place. Ticks per metre of each wheel come from the straight drive, the wheel base
// from the turns: each wheel's travel in a turn in place is +-wheel_base/2 times the gyro's angle.
namespace cleanslam::calibrate {

struct WheelCalibrationOptions {
  double straight_length_m = 0.0;  // the straight drive's measured length (all straight runs)
  double min_standstill_s = 3.0;   // before the first motion: the gyro's bias
  double min_turn_rad = 6.283185307179586;  // total |angle| of the turns in place
};

struct WheelCalibration {
  double ticks_per_meter_left = 0.0;
  double ticks_per_meter_right = 0.0;
  double wheel_base_m = 0.0;
  // What the figures rest on, for the report and the YAML comments.
  double gyro_bias_rad_s = 0.0;
  double standstill_s = 0.0;
  double straight_ticks_left = 0.0;
  double straight_ticks_right = 0.0;
  double straight_yaw_rad = 0.0;     // the gyro's heading change over the straight drive
  int turns = 0;                     // runs of turning in place
  double turn_angle_rad = 0.0;       // their total |angle| by the gyro
  double wheel_base_spread_m = 0.0;  // std. dev. of the per-turn wheel bases (0 with one turn)
  int mixed_intervals = 0;           // encoder intervals with one wheel still (neither kind)
};

// `dataset` must hold the drive's gyro and encoder samples (a folder's gyro.csv and encoders.csv,
// or a log's records: read_log_samples); its sensors.yaml's wheel base (when set) only starts the
// calculation.
// Refused, with the file and what is missing, when the standstill is too short, there is no
// straight drive or too little turning.
readers::Result<WheelCalibration> calibrate_wheels(const readers::Dataset& dataset,
                                                   const WheelCalibrationOptions& options);

}  // namespace cleanslam::calibrate
