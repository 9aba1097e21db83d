#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>

// A configuration key declared once: its dotted name, the member of a configuration struct it
// sets, its default, range, unit and meaning. The estimator, the firmware and the simulator each
// list their keys in a table of these; the readers and writers of configurations walk the tables.
namespace cleanslam::hal {

enum class ParameterType {
  kDouble,
  kFloat,
  kInt,
  kBool,
  kScaledInt64,  // std::int64_t holding the configured number times `scale` (seconds as ns)
  kUnsigned64,   // std::uint64_t (a seed)
  kScaledSize,   // std::size_t holding the configured number times `scale` (MiB as bytes)
  kChoice,       // an enum, configured by the name of its value
  kText,         // std::string, one of `choices` when there are any
  kNumbers,      // `count` doubles, each within the range, through get_numbers and set_numbers
};

// The storage of one key in a configuration struct.
struct ParameterField {
  ParameterType type = ParameterType::kDouble;
  void* value = nullptr;
  double scale = 1.0;
  bool integral = false;                        // kScaledSize: a whole number of units
  std::size_t count = 0;                        // kNumbers
  std::span<const std::string_view> choices{};  // kChoice: the names of the values 0, 1, ...
  int (*get_choice)(const void*) = nullptr;
  void (*set_choice)(void*, int) = nullptr;
  void (*get_numbers)(const void*, double*) = nullptr;
  void (*set_numbers)(void*, const double*) = nullptr;
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
inline ParameterField parameter_field(std::string& v) {
  return {ParameterType::kText, &v};
}
// A text that must be one of `allowed`.
inline ParameterField text_field(std::string& v, std::span<const std::string_view> allowed) {
  return {ParameterType::kText, &v, 1.0, false, 0, allowed};
}
constexpr ParameterField parameter_field(std::int64_t& v) {
  return {ParameterType::kScaledInt64, &v, 1.0, true};
}
constexpr ParameterField parameter_field(std::uint64_t& v) {
  return {ParameterType::kUnsigned64, &v, 1.0, true};
}
// A duration held in nanoseconds, configured in seconds.
constexpr ParameterField seconds_field(std::int64_t& ns) {
  return {ParameterType::kScaledInt64, &ns, 1e9};
}
// A size held in bytes, configured in mebibytes.
constexpr ParameterField mebibytes_field(std::size_t& bytes) {
  return {ParameterType::kScaledSize, &bytes, 1048576.0};
}
// A size held in bytes, configured as a whole number of kibibytes.
constexpr ParameterField kibibytes_field(std::size_t& bytes) {
  return {ParameterType::kScaledSize, &bytes, 1024.0, true};
}

namespace detail {
template <typename Enum>
int enum_get(const void* p) {
  return static_cast<int>(*static_cast<const Enum*>(p));
}
template <typename Enum>
void enum_set(void* p, int v) {
  *static_cast<Enum*>(p) = static_cast<Enum>(v);
}
template <std::size_t N>
void array_get(const void* p, double* out) {
  const auto& a = *static_cast<const std::array<double, N>*>(p);
  std::copy(a.begin(), a.end(), out);
}
template <std::size_t N>
void array_set(void* p, const double* in) {
  auto& a = *static_cast<std::array<double, N>*>(p);
  std::copy(in, in + N, a.begin());
}
}  // namespace detail

// An enum whose values 0, 1, ... are named by `names`.
template <typename Enum>
constexpr ParameterField choice_field(Enum& v, std::span<const std::string_view> names) {
  return {ParameterType::kChoice, &v, 1.0, false, 0, names, &detail::enum_get<Enum>,
          &detail::enum_set<Enum>};
}

// A fixed number of doubles, configured as a sequence.
template <std::size_t N>
constexpr ParameterField numbers_field(std::array<double, N>& v) {
  return {ParameterType::kNumbers, &v, 1.0, false, N, {}, nullptr, nullptr, &detail::array_get<N>,
          &detail::array_set<N>};
}

// One key of a configuration struct `Config`. Numbers travel as double (exact for every int and
// float; a choice as the index of its name); a flag is 0 or 1 and a choice or a text has no
// range.
template <typename Config>
struct Parameter {
  std::string_view key;                        // dotted configuration key, "section.name"
  ParameterField (*field)(Config&) = nullptr;  // the member it sets
  double default_value = 0.0;  // the struct's default, as listed (a choice: its index; a text's
                               // default is the struct's alone)
  double lo = 0.0;             // range [lo, hi], (lo, hi] when lo_open
  double hi = 0.0;
  bool lo_open = false;
  std::string_view unit;  // "" when dimensionless
  std::string_view doc;   // one line; a value out of range is refused with it
};

template <typename Config>
ParameterType parameter_type(const Parameter<Config>& p) {
  Config probe{};
  return p.field(probe).type;
}

// The member's number, flag or choice index, in the configured unit (0 for a text or a list).
inline double field_number(const ParameterField& f) {
  switch (f.type) {
    case ParameterType::kDouble:
      return *static_cast<const double*>(f.value);
    case ParameterType::kFloat:
      return static_cast<double>(*static_cast<const float*>(f.value));
    case ParameterType::kInt:
      return static_cast<double>(*static_cast<const int*>(f.value));
    case ParameterType::kBool:
      return *static_cast<const bool*>(f.value) ? 1.0 : 0.0;
    case ParameterType::kScaledInt64:
      return static_cast<double>(*static_cast<const std::int64_t*>(f.value)) / f.scale;
    case ParameterType::kUnsigned64:
      return static_cast<double>(*static_cast<const std::uint64_t*>(f.value));
    case ParameterType::kScaledSize:
      return static_cast<double>(*static_cast<const std::size_t*>(f.value)) / f.scale;
    case ParameterType::kChoice:
      return static_cast<double>(f.get_choice(f.value));
    case ParameterType::kText:
    case ParameterType::kNumbers:
      break;
  }
  return 0.0;
}

// Sets the member from a number in the configured unit; a text or a list is left as it is.
inline void set_field_number(const ParameterField& f, double v) {
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
    case ParameterType::kScaledInt64:
      *static_cast<std::int64_t*>(f.value) = std::llround(v * f.scale);
      break;
    case ParameterType::kUnsigned64:
      *static_cast<std::uint64_t*>(f.value) = static_cast<std::uint64_t>(v);
      break;
    case ParameterType::kScaledSize:
      *static_cast<std::size_t*>(f.value) = static_cast<std::size_t>(std::llround(v * f.scale));
      break;
    case ParameterType::kChoice:
      f.set_choice(f.value, static_cast<int>(v));
      break;
    case ParameterType::kText:
    case ParameterType::kNumbers:
      break;
  }
}

// A number, a flag or a choice's index.
template <typename Config>
double get_parameter(const Parameter<Config>& p, const Config& config) {
  // The field accessor only takes the address of the member.
  return field_number(p.field(const_cast<Config&>(config)));  // NOLINT
}

// `v` must be in range (parameter_in_range).
template <typename Config>
void set_parameter(const Parameter<Config>& p, Config& config, double v) {
  set_field_number(p.field(config), v);
}

template <typename Config>
const std::string& get_text_parameter(const Parameter<Config>& p, const Config& config) {
  const ParameterField f = p.field(const_cast<Config&>(config));  // NOLINT
  return *static_cast<const std::string*>(f.value);
}

template <typename Config>
void set_text_parameter(const Parameter<Config>& p, Config& config, std::string v) {
  *static_cast<std::string*>(p.field(config).value) = std::move(v);
}

// Finite, within the range; an int integral, a flag 0 or 1, a choice one of its names.
template <typename Config>
bool parameter_in_range(const Parameter<Config>& p, double v) {
  Config probe{};
  const ParameterField f = p.field(probe);
  if (f.type == ParameterType::kBool) {
    return v == 0.0 || v == 1.0;
  }
  if (f.type == ParameterType::kChoice) {
    return v >= 0.0 && v < static_cast<double>(f.choices.size()) && v == std::trunc(v);
  }
  const bool integral = f.type == ParameterType::kInt || f.integral;
  if (!std::isfinite(v) || (integral && v != std::trunc(v))) {
    return false;
  }
  return (p.lo_open ? v > p.lo : v >= p.lo) && v <= p.hi;
}

// The listed default as the member holds it (a float's default rounded to float, a scaled
// integer's to its unit).
template <typename Config>
double stored_default(const Parameter<Config>& p) {
  Config probe{};
  const ParameterField f = p.field(probe);
  switch (f.type) {
    case ParameterType::kFloat:
      return static_cast<double>(static_cast<float>(p.default_value));
    case ParameterType::kScaledInt64:
    case ParameterType::kScaledSize:
      return static_cast<double>(std::llround(p.default_value * f.scale)) / f.scale;
    default:
      return p.default_value;
  }
}

}  // namespace cleanslam::hal
