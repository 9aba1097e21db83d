#include "cleanslam/readers/parameter_yaml.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iomanip>
#include <limits>
#include <sstream>

#include "cleanslam/readers/dataset.hpp"

namespace cleanslam::readers {

namespace {

using hal::ParameterType;

// "file:line: dotted.key", or the dotted key alone when the key is absent.
std::string where(yaml::MappingReader& section, std::string_view name) {
  const yaml::Node* n = section.node(name);
  return (n != nullptr ? n->location.str() + ": " : std::string()) + section.path(name);
}

std::string out_of_range(const std::string& where, double v, double lo, double hi, bool lo_open,
                         std::string_view doc) {
  std::ostringstream s;
  s << where << ": " << v << " is out of range " << (lo_open ? "(" : "[") << lo << ", " << hi << "]"
    << (doc.empty() ? "" : ": ") << doc;
  return s.str();
}

std::string choice_list(std::span<const std::string_view> names) {
  std::string s;
  for (std::size_t i = 0; i < names.size(); ++i) {
    s.append(i == 0 ? "" : ", ").append(names[i]);
  }
  return s;
}

}  // namespace

std::string_view parameter_leaf_name(std::string_view key, std::string_view prefix) {
  if (!key.starts_with(prefix)) {
    return {};
  }
  const std::string_view rest = key.substr(prefix.size());
  return rest.find('.') == std::string_view::npos ? rest : std::string_view{};
}

void read_parameter_field(yaml::MappingReader& section, std::string_view name,
                          const hal::ParameterField& f, double lo, double hi, bool lo_open,
                          std::string_view doc, yaml::Diagnostics& d) {
  if (!section.has(name)) {
    section.node(name);  // a known key: an unknown one's nearest match may be it
    return;
  }
  switch (f.type) {
    case ParameterType::kBool: {
      auto& v = *static_cast<bool*>(f.value);
      v = section.optional_bool(name, v);
      return;
    }
    case ParameterType::kText: {
      auto& v = *static_cast<std::string*>(f.value);
      std::string text = section.optional_string(name, v);
      if (!f.choices.empty() &&
          std::find(f.choices.begin(), f.choices.end(), text) == f.choices.end()) {
        d.errors.push_back(where(section, name) + ": \"" + text + "\" is not one of " +
                           choice_list(f.choices));
        return;
      }
      v = std::move(text);
      return;
    }
    case ParameterType::kChoice: {
      const int current = f.get_choice(f.value);
      const std::string text =
          section.optional_string(name, std::string(f.choices[static_cast<std::size_t>(current)]));
      for (std::size_t i = 0; i < f.choices.size(); ++i) {
        if (f.choices[i] == text) {
          f.set_choice(f.value, static_cast<int>(i));
          return;
        }
      }
      d.errors.push_back(where(section, name) + ": \"" + text + "\" is not one of " +
                         choice_list(f.choices));
      return;
    }
    case ParameterType::kNumbers: {
      std::vector<double> current(f.count);
      f.get_numbers(f.value, current.data());
      const std::size_t errors_before = d.errors.size();
      const std::vector<double> x = section.optional_doubles(name, current, f.count);
      if (d.errors.size() != errors_before || x.size() != f.count) {
        return;
      }
      for (const double e : x) {
        if (e < lo || e > hi || (lo_open && e <= lo) || !std::isfinite(e)) {
          d.errors.push_back(out_of_range(where(section, name), e, lo, hi, lo_open, doc));
          return;
        }
      }
      f.set_numbers(f.value, x.data());
      return;
    }
    case ParameterType::kInt: {
      auto& v = *static_cast<int*>(f.value);
      const std::int64_t x = section.optional_int(name, v);
      const auto ilo = static_cast<std::int64_t>(lo);
      const auto ihi = static_cast<std::int64_t>(hi);
      if (x < ilo || x > ihi) {
        d.errors.push_back(where(section, name) + ": " + std::to_string(x) + " is out of range [" +
                           std::to_string(ilo) + ", " + std::to_string(ihi) + "]" +
                           (doc.empty() ? "" : ": ") + std::string(doc));
        return;
      }
      v = static_cast<int>(x);
      return;
    }
    case ParameterType::kDouble:
    case ParameterType::kFloat:
    case ParameterType::kScaledInt64:
    case ParameterType::kUnsigned64:
    case ParameterType::kScaledSize:
      break;
  }
  const std::size_t errors_before = d.errors.size();
  const double x = f.integral ? static_cast<double>(section.optional_int(name, 0))
                              : section.optional_double(name, 0.0);
  if (d.errors.size() != errors_before) {
    return;
  }
  if (x < lo || x > hi || (lo_open && x <= lo) || !std::isfinite(x)) {
    d.errors.push_back(out_of_range(where(section, name), x, lo, hi, lo_open, doc));
    return;
  }
  hal::set_field_number(f, x);
}

std::string parameter_field_text(const hal::ParameterField& f) {
  switch (f.type) {
    case ParameterType::kBool:
      return *static_cast<const bool*>(f.value) ? "true" : "false";
    case ParameterType::kInt:
      return std::to_string(*static_cast<const int*>(f.value));
    case ParameterType::kFloat: {
      std::array<char, 64> buf{};
      const auto [end, ec] =
          std::to_chars(buf.data(), buf.data() + buf.size(), *static_cast<const float*>(f.value),
                        std::chars_format::fixed);
      std::string s(buf.data(), ec == std::errc() ? end : buf.data());
      if (s.find_first_of(".ni") == std::string::npos) {
        s += ".0";
      }
      return s;
    }
    case ParameterType::kDouble:
      return format_double(*static_cast<const double*>(f.value));
    case ParameterType::kScaledInt64: {
      const std::int64_t v = *static_cast<const std::int64_t*>(f.value);
      return f.integral ? std::to_string(v) : format_double(static_cast<double>(v) / f.scale);
    }
    case ParameterType::kUnsigned64:
      return std::to_string(*static_cast<const std::uint64_t*>(f.value));
    case ParameterType::kScaledSize: {
      const double v = static_cast<double>(*static_cast<const std::size_t*>(f.value)) / f.scale;
      return f.integral ? std::to_string(std::llround(v)) : format_double(v);
    }
    case ParameterType::kChoice:
      return std::string(f.choices[static_cast<std::size_t>(f.get_choice(f.value))]);
    case ParameterType::kText:
      return yaml_quoted(*static_cast<const std::string*>(f.value));
    case ParameterType::kNumbers: {
      std::vector<double> v(f.count);
      f.get_numbers(f.value, v.data());
      std::string s = "[";
      for (std::size_t i = 0; i < f.count; ++i) {
        s.append(i == 0 ? "" : ", ").append(format_double(v[i]));
      }
      return s + "]";
    }
  }
  return {};
}

std::string parameter_comment(const hal::ParameterField& f, double lo, double hi, bool lo_open,
                              std::string_view unit, std::string_view doc) {
  std::ostringstream s;
  s << doc;
  if (f.type == ParameterType::kBool || (f.type == ParameterType::kText && f.choices.empty())) {
    return s.str();
  }
  if (f.type == ParameterType::kChoice || f.type == ParameterType::kText) {
    std::string names;
    for (std::size_t i = 0; i < f.choices.size(); ++i) {
      names.append(i == 0 ? "" : " | ").append(f.choices[i]);
    }
    s << " (" << names << ")";
    return s.str();
  }
  const bool unbounded =
      lo <= -std::numeric_limits<double>::max() && hi >= std::numeric_limits<double>::max();
  if (unbounded) {
    return unit.empty() ? s.str() : s.str() + " (" + std::string(unit) + ")";
  }
  s << " (";
  if (!unit.empty()) {
    s << unit << ", ";
  }
  s << std::setprecision(10) << (lo_open ? "(" : "[") << lo << ", " << hi << "])";
  return s.str();
}

// Quotes, backslashes and every character YAML does not print (controls, C1 controls, line and
// paragraph separators, the byte order mark) are escaped; a raw line break would be folded into a
// space when read back.
std::string yaml_quoted(const std::string& s) {
  std::string out = "\"";
  char buf[16];
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    std::size_t n = 1;
    std::uint32_t cp = c;
    if (c >= 0xC0 && c < 0xE0 && i + 1 < s.size()) {
      n = 2;
      cp = ((c & 0x1FU) << 6) | (static_cast<unsigned char>(s[i + 1]) & 0x3FU);
    } else if (c >= 0xE0 && c < 0xF0 && i + 2 < s.size()) {
      n = 3;
      cp = ((c & 0x0FU) << 12) | ((static_cast<unsigned char>(s[i + 1]) & 0x3FU) << 6) |
           (static_cast<unsigned char>(s[i + 2]) & 0x3FU);
    } else if (c >= 0xF0 && i + 3 < s.size()) {
      n = 4;  // beyond the characters escaped below
      cp = 0x10000;
    }
    if (c == '"' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (cp < 0x20 || cp == 0x7F || (cp >= 0x80 && cp < 0xA0)) {
      std::snprintf(buf, sizeof buf, "\\x%02X", static_cast<unsigned>(cp));
      out += buf;
    } else if (cp == 0x2028 || cp == 0x2029 || cp == 0xFEFF || cp == 0xFFFE || cp == 0xFFFF) {
      std::snprintf(buf, sizeof buf, "\\u%04X", static_cast<unsigned>(cp));
      out += buf;
    } else {
      out.append(s, i, n);
    }
    i += n;
  }
  return out + "\"";
}

}  // namespace cleanslam::readers
