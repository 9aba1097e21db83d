#pragma once

#include <cmath>
#include <span>
#include <string_view>

#include "cleanslam/slam_core/slam_config.hpp"

// Every setting of the estimator once: its configuration key, the member of SlamConfig it sets,
// its default, range, unit and meaning. Readers and writers of configurations walk the table.
namespace cleanslam::slam_core {

enum class ParameterType { kDouble, kFloat, kInt, kBool };

// The storage of one setting in a configuration struct.
struct ParameterField {
  ParameterType type = ParameterType::kDouble;
  void* value = nullptr;
};

constexpr ParameterField parameter_field(double& v) {
  return {ParameterType::kDouble, &v};
}
constexpr ParameterField parameter_field(float& v) {
  return {ParameterType::kFloat, &v};
}
constexpr ParameterField parameter_field(int& v) {
  return {ParameterType::kInt, &v};
}
constexpr ParameterField parameter_field(bool& v) {
  return {ParameterType::kBool, &v};
}

// One key of a configuration struct `Config`. Values travel as double (exact for every int and
// float); a flag is 0 or 1 and has no range.
template <typename Config>
struct Parameter {
  std::string_view key;                        // dotted configuration key, "section.name"
  ParameterField (*field)(Config&) = nullptr;  // the member it sets
  double default_value = 0.0;                  // the struct's default, as listed
  double lo = 0.0;                             // range [lo, hi], (lo, hi] when lo_open
  double hi = 0.0;
  bool lo_open = false;
  std::string_view unit;  // "" when dimensionless
  std::string_view doc;   // one line
};

template <typename Config>
ParameterType parameter_type(const Parameter<Config>& p) {
  Config probe{};
  return p.field(probe).type;
}

template <typename Config>
double get_parameter(const Parameter<Config>& p, const Config& config) {
  // The field accessor only takes the address of the member.
  const ParameterField f = p.field(const_cast<Config&>(config));  // NOLINT
  switch (f.type) {
    case ParameterType::kDouble:
      return *static_cast<const double*>(f.value);
    case ParameterType::kFloat:
      return static_cast<double>(*static_cast<const float*>(f.value));
    case ParameterType::kInt:
      return static_cast<double>(*static_cast<const int*>(f.value));
    case ParameterType::kBool:
      return *static_cast<const bool*>(f.value) ? 1.0 : 0.0;
  }
  return 0.0;
}

// `v` must be in range (parameter_in_range).
template <typename Config>
void set_parameter(const Parameter<Config>& p, Config& config, double v) {
  const ParameterField f = p.field(config);
  switch (f.type) {
    case ParameterType::kDouble:
      *static_cast<double*>(f.value) = v;
      break;
    case ParameterType::kFloat:
      *static_cast<float*>(f.value) = static_cast<float>(v);
      break;
    case ParameterType::kInt:
      *static_cast<int*>(f.value) = static_cast<int>(v);
      break;
    case ParameterType::kBool:
      *static_cast<bool*>(f.value) = v != 0.0;
      break;
  }
}

// Finite, within the range; an int integral, a flag 0 or 1.
template <typename Config>
bool parameter_in_range(const Parameter<Config>& p, double v) {
  const ParameterType t = parameter_type(p);
  if (t == ParameterType::kBool) {
    return v == 0.0 || v == 1.0;
  }
  if (!std::isfinite(v) || (t == ParameterType::kInt && v != std::trunc(v))) {
    return false;
  }
  return (p.lo_open ? v > p.lo : v >= p.lo) && v <= p.hi;
}

// The listed default as the member holds it (a float's default rounded to float).
template <typename Config>
double stored_default(const Parameter<Config>& p) {
  return parameter_type(p) == ParameterType::kFloat
             ? static_cast<double>(static_cast<float>(p.default_value))
             : p.default_value;
}

// Every key of SlamConfig a configuration sets, in the order of the sample configuration.
// Members set from elsewhere are not listed: the image size (the camera calibration), the gyro
// timeout (the firmware's loop.gyro_timeout_s).
std::span<const Parameter<SlamConfig>> slam_parameters();

// The key's entry, or nullptr.
const Parameter<SlamConfig>* find_slam_parameter(std::string_view key);

}  // namespace cleanslam::slam_core
