#include "key_history.hpp"

#include <algorithm>
#include <cmath>
#include <string_view>
#include <utility>

#include "cleanslam/firmware/config.hpp"
#include "cleanslam/hal/time.hpp"
#include "cleanslam/readers/dataset.hpp"
#include "yaml_paths.hpp"

namespace cleanslam::firmware::key_history {

namespace {

namespace yaml = readers::yaml;

struct RenamedKey {
  std::string_view former;
  std::string_view key;
};

// The estimator's keys moved to the section named after the struct they set (issue 46).
constexpr RenamedKey kRenamedKeys[] = {
    {"filter.encoder_yaw_noise_rad_per_sqrt_m", "odometry.encoder_yaw_noise_rad_per_sqrt_m"},
    {"filter.gyro_bias_correlation_time_s", "odometry.gyro_bias_correlation_time_s"},
    {"filter.gyro_scale_error", "odometry.gyro_scale_error"},
    {"filter.wheel_yaw_window_intervals", "odometry.wheel_yaw_window_intervals"},
    {"filter.wheel_yaw_gate_chi2", "odometry.wheel_yaw_gate_chi2"},
    {"filter.wheel_yaw_scale_std", "odometry.wheel_yaw_scale_std"},
    {"filter.wheel_yaw_drift_std_rad_per_m", "odometry.wheel_yaw_drift_std_rad_per_m"},
    {"filter.wheel_yaw_correlation_time_s", "odometry.wheel_yaw_correlation_time_s"},
    {"filter.z_noise_m_per_sqrt_m", "odometry.z_noise_m_per_sqrt_m"},
    {"filter.roll_pitch_noise_rad_per_sqrt_m", "odometry.roll_pitch_noise_rad_per_sqrt_m"},
    {"filter.outage_speed_time_constant_s", "odometry.outage_speed_time_constant_s"},
    {"filter.outage_speed_std_m_s", "odometry.outage_speed_std_m_s"},
    {"frontend.standstill_rate_rad_s", "odometry.standstill_rate_rad_s"},
    {"filter.remap_pixel_std_px", "map_management.remap_pixel_std_px"},
    {"filter.remap_min_yaw_std_deg", "map_management.remap_min_yaw_std_deg"},
    {"filter.remap_max_mapped_in_view", "map_management.remap_max_mapped_in_view"},
    {"filter.pose_lost_position_std_m", "map_management.pose_lost_position_std_m"},
    {"frontend.features_min_inliers", "map_management.features_min_inliers"},
    {"robot.on_set_down", "map_management.on_set_down"},
    {"robot.relocalize_std_m", "map_management.relocalize_std_m"},
    {"robot.relocalize_std_yaw_deg", "map_management.relocalize_std_yaw_deg"},
    {"frontend.relocalizer.min_ncc", "relocalizer.min_ncc"},
    {"frontend.relocalizer.min_inliers", "relocalizer.min_inliers"},
};

struct RemovedKey {
  std::string_view key;
  // The value the firmware now always has, in the key's former unit (a flag: 1 or 0).
  double (*value)(const FirmwareConfig&);
};

using C = FirmwareConfig;

double flag(bool b) {
  return b ? 1.0 : 0.0;
}

// Switches measured on and kept on, settings tried and not kept (at their off value, 0), and
// internals no measurement moved from their default (issue 46; docs/experiments.md).
constexpr RemovedKey kRemovedKeys[] = {
    {"filter.consider_young_landmarks",
     [](const C& c) { return flag(c.slam.filter.consider_young_landmarks); }},
    {"filter.depth_bounds", [](const C& c) { return flag(c.slam.filter.depth_bounds); }},
    {"filter.wheel_yaw_fusion", [](const C& c) { return flag(c.slam.odometry.wheel_yaw.enabled); }},
    {"filter.remap_merge_consider_earlier",
     [](const C& c) { return flag(c.slam.filter.merge_considers_kept); }},
    {"filter.invariant_reset", [](const C& c) { return flag(c.slam.filter.invariant_reset); }},
    {"filter.solve_pose_beyond_linear_range",
     [](const C& c) { return flag(c.slam.filter.solve_pose_beyond_linear_range); }},
    {"filter.remap_merge_gate_chi2", [](const C&) { return 0.0; }},
    {"filter.distance_scale_correlation_m", [](const C&) { return 0.0; }},
    {"filter.max_abs_pitch_rad", [](const C& c) { return c.slam.filter.max_abs_pitch_rad; }},
    {"filter.min_motion_for_direction_m",
     [](const C& c) { return c.slam.filter.min_motion_for_direction_m; }},
    {"filter.min_variance", [](const C& c) { return c.slam.filter.min_variance; }},
    {"filter.max_wheel_speed_m_s", [](const C& c) { return c.slam.odometry.max_wheel_speed_m_s; }},
    {"filter.max_gyro_rate_rad_s", [](const C& c) { return c.slam.odometry.max_gyro_rate_rad_s; }},
    {"filter.bias_max_samples",
     [](const C& c) { return static_cast<double>(c.slam.odometry.bias_max_samples); }},
    {"filter.max_extrapolation_s", [](const C& c) { return c.slam.odometry.max_extrapolation_s; }},
    {"filter.outage_yaw_rate_std_rad_s",
     [](const C& c) { return c.slam.odometry.outage_yaw_rate_std_rad_s; }},
    {"frontend.standstill_window_s",
     [](const C& c) { return c.slam.odometry.standstill_window_s; }},
    {"frontend.standstill_max_ticks",
     [](const C& c) { return static_cast<double>(c.slam.odometry.standstill_max_ticks); }},
    {"frontend.duplicate_px", [](const C& c) { return c.slam.frontend.duplicate_px; }},
    {"frontend.max_view_scale", [](const C& c) { return c.slam.frontend.max_view_scale; }},
    {"frontend.min_view_cos", [](const C& c) { return c.slam.frontend.min_view_cos; }},
    {"frontend.reacquire_after_frames",
     [](const C& c) { return static_cast<double>(c.slam.frontend.reacquire_after_frames); }},
    {"frontend.detect_rows_per_step",
     [](const C& c) { return static_cast<double>(c.slam.frontend.detect_rows_per_step); }},
    {"frontend.predictions_per_step",
     [](const C& c) { return static_cast<double>(c.slam.frontend.predictions_per_step); }},
    {"frontend.tracks_per_step",
     [](const C& c) { return static_cast<double>(c.slam.frontend.tracks_per_step); }},
    {"frontend.initializations_per_step",
     [](const C& c) { return static_cast<double>(c.slam.frontend.initializations_per_step); }},
    {"frontend.harris.quality_level",
     [](const C& c) { return static_cast<double>(c.slam.frontend.harris.quality_level); }},
    {"frontend.harris.min_response",
     [](const C& c) { return static_cast<double>(c.slam.frontend.harris.min_response); }},
    {"frontend.harris.border_px",
     [](const C& c) { return static_cast<double>(c.slam.frontend.harris.border_px); }},
    {"frontend.tracker.max_iterations",
     [](const C& c) { return static_cast<double>(c.slam.frontend.tracker.max_iterations); }},
    {"frontend.tracker.convergence_px",
     [](const C& c) { return static_cast<double>(c.slam.frontend.tracker.convergence_px); }},
    {"frontend.tracker.max_corner_starts",
     [](const C& c) { return static_cast<double>(c.slam.frontend.tracker.max_corner_starts); }},
    {"frontend.tracker.min_start_ncc",
     [](const C& c) { return static_cast<double>(c.slam.frontend.tracker.min_start_ncc); }},
    {"frontend.tracker.max_travel_px",
     [](const C& c) { return static_cast<double>(c.slam.frontend.tracker.max_travel_px); }},
    {"frontend.tracker.min_template_std",
     [](const C& c) { return static_cast<double>(c.slam.frontend.tracker.min_template_std); }},
    {"frontend.tracker.min_template_isotropy",
     [](const C& c) { return static_cast<double>(c.slam.frontend.tracker.min_template_isotropy); }},
    {"frontend.tracker.min_window_std",
     [](const C& c) { return static_cast<double>(c.slam.frontend.tracker.min_window_std); }},
    {"frontend.tracker.ncc_tie",
     [](const C& c) { return static_cast<double>(c.slam.frontend.tracker.ncc_tie); }},
    {"frontend.tracker.distinct_px",
     [](const C& c) { return static_cast<double>(c.slam.frontend.tracker.distinct_px); }},
    {"frontend.tracker.ambiguity_ncc",
     [](const C& c) { return static_cast<double>(c.slam.frontend.tracker.ambiguity_ncc); }},
    {"frontend.tracker.reacquire_min_ncc",
     [](const C& c) { return static_cast<double>(c.slam.frontend.tracker.reacquire_min_ncc); }},
    {"frontend.tracker.reacquire_box_px",
     [](const C& c) { return static_cast<double>(c.slam.frontend.tracker.reacquire_box_px); }},
    {"frontend.relocalizer.candidates_per_landmark",
     [](const C& c) { return static_cast<double>(c.slam.relocalizer.candidates_per_landmark); }},
    {"frontend.relocalizer.min_elevation_tan",
     [](const C& c) { return c.slam.relocalizer.min_elevation_tan; }},
    {"frontend.relocalizer.pair_tolerance_m",
     [](const C& c) { return c.slam.relocalizer.pair_tolerance_m; }},
    {"frontend.relocalizer.pair_tolerance_fraction",
     [](const C& c) { return c.slam.relocalizer.pair_tolerance_fraction; }},
    {"frontend.relocalizer.inlier_px", [](const C& c) { return c.slam.relocalizer.inlier_px; }},
    {"frontend.relocalizer.min_margin",
     [](const C& c) { return static_cast<double>(c.slam.relocalizer.min_margin); }},
    {"frontend.relocalizer.chance_match",
     [](const C& c) { return c.slam.relocalizer.chance_match; }},
    {"frontend.relocalizer.max_chance_probability",
     [](const C& c) { return c.slam.relocalizer.max_chance_probability; }},
    {"frontend.relocalizer.min_inliers_unchecked",
     [](const C& c) { return static_cast<double>(c.slam.relocalizer.min_inliers_unchecked); }},
    {"frontend.relocalizer.landmarks_per_step",
     [](const C& c) { return static_cast<double>(c.slam.relocalizer.landmarks_per_step); }},
    {"frontend.relocalizer.rows_per_step",
     [](const C& c) { return static_cast<double>(c.slam.relocalizer.rows_per_step); }},
    {"loop.max_time_skew_s", [](const C& c) { return hal::to_seconds(c.loop.max_time_skew_ns); }},
    {"loop.max_lead_s", [](const C& c) { return hal::to_seconds(c.loop.max_lead_ns); }},
    {"recorder.buffer_kb",
     [](const C& c) { return static_cast<double>(c.recorder.buffer_bytes) / 1024.0; }},
    {"recorder.write_chunk_kb",
     [](const C& c) { return static_cast<double>(c.recorder.write_chunk_bytes) / 1024.0; }},
    {"robot.gyro_ready_max_latency_s", [](const C& c) { return c.robot.gyro_ready_max_latency_s; }},
};

// The entry of the dotted `key` below `root` and the mappings on its way (root first), or an
// empty path.
std::vector<std::pair<yaml::Node*, std::size_t>> find_entry(yaml::Node& root,
                                                            std::string_view key) {
  std::vector<std::pair<yaml::Node*, std::size_t>> path;
  yaml::Node* node = &root;
  while (true) {
    if (!node->is_mapping()) {
      return {};
    }
    const auto dot = key.find('.');
    const std::string_view part = key.substr(0, dot);
    std::size_t i = 0;
    while (i < node->entries.size() && node->entries[i].key != part) {
      ++i;
    }
    if (i == node->entries.size()) {
      return {};
    }
    path.emplace_back(node, i);
    if (dot == std::string_view::npos) {
      return path;
    }
    node = &node->entries[i].value;
    key = key.substr(dot + 1);
  }
}

// Removes the entry at the end of `path`, then each mapping on the way that it left empty.
void erase_entry(std::vector<std::pair<yaml::Node*, std::size_t>> path) {
  while (!path.empty()) {
    auto [node, i] = path.back();
    path.pop_back();
    node->entries.erase(node->entries.begin() + static_cast<std::ptrdiff_t>(i));
    if (!node->entries.empty() || path.empty()) {
      return;
    }
  }
}

// The number or flag a former key's scalar holds, as the firmware of then read it.
bool former_value(const yaml::Node& node, double& out) {
  if (!node.is_scalar() || node.quoted) {
    return false;
  }
  if (node.scalar == "true" || node.scalar == "false") {
    out = node.scalar == "true" ? 1.0 : 0.0;
    return true;
  }
  const auto v = yaml::as_double(node, "");
  if (!v.ok()) {
    return false;
  }
  out = *v;
  return true;
}

// A float member's value was written as the float it is; a duration, as its nanoseconds in
// seconds.
bool same_value(double written, double fixed) {
  const auto single = static_cast<float>(fixed);
  if (static_cast<double>(single) == fixed) {
    return static_cast<float>(written) == single;
  }
  return std::abs(written - fixed) <= 1e-12 * std::max(1.0, std::abs(fixed));
}

// A former key found in a document: its entry's place and "file:line: key" for messages.
struct Found {
  std::vector<std::pair<yaml::Node*, std::size_t>> path;
  const yaml::Node::Entry* entry = nullptr;
  std::string where;
};

Found find_former(yaml::Node& root, std::string_view key) {
  Found f;
  f.path = find_entry(root, key);
  if (!f.path.empty()) {
    f.entry = &f.path.back().first->entries[f.path.back().second];
    f.where = (f.entry->key_location.line > 0 ? f.entry->key_location.str() + ": " : "") +
              std::string(key);
  }
  return f;
}

}  // namespace

void apply(yaml::Node& root, std::vector<std::string>& errors, std::vector<std::string>& warnings) {
  const FirmwareConfig today{};
  std::string first_renamed;
  int renamed = 0;
  for (const RenamedKey& r : kRenamedKeys) {
    const Found f = find_former(root, r.former);
    if (f.entry == nullptr) {
      continue;
    }
    const std::string& where = f.where;
    if (yaml_paths::find(root, r.key) != nullptr) {
      errors.push_back(where + ": the former name of " + std::string(r.key) +
                       ", which is set too; keep one");
      continue;
    }
    yaml::Node value = f.entry->value;
    const yaml::Location at = f.entry->key_location;
    erase_entry(f.path);
    std::string error;
    yaml::Node* slot = yaml_paths::make(root, r.key, at, error);
    if (slot == nullptr) {
      errors.push_back(where);
      errors.back().append(": the former name of ").append(r.key).append(", where ").append(error);
      continue;
    }
    *slot = std::move(value);
    if (renamed++ == 0) {
      first_renamed = where + " is now " + std::string(r.key);
    }
  }
  if (renamed > 0) {
    warnings.push_back(std::to_string(renamed) + " key(s) under a former name, read as today's (" +
                       first_renamed + "); `cleanslam --print-sample-config` prints today's names");
  }
  std::string first_removed;
  int removed = 0;
  for (const RemovedKey& r : kRemovedKeys) {
    const Found f = find_former(root, r.key);
    if (f.entry == nullptr) {
      continue;
    }
    const double fixed = r.value(today);
    double v = 0.0;
    if (!former_value(f.entry->value, v) || !same_value(v, fixed)) {
      errors.push_back(f.where + ": no longer a key: the firmware always uses " +
                       readers::format_double(fixed) + " (docs/experiments.md), not " +
                       f.entry->value.describe());
      continue;
    }
    const std::string where = f.where;
    erase_entry(f.path);
    if (removed++ == 0) {
      first_removed = where;
    }
  }
  if (removed > 0) {
    warnings.push_back(std::to_string(removed) +
                       " former key(s) at the value the firmware now always uses, ignored (" +
                       first_removed + ")");
  }
}

}  // namespace cleanslam::firmware::key_history
