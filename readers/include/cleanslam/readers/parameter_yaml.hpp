#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cleanslam/hal/parameter.hpp"
#include "cleanslam/readers/yaml_document.hpp"

// Configuration sections read and written through tables of hal::Parameter: a section's keys
// are the table's keys below the section's dotted path, each read with its type and range.
namespace cleanslam::readers {

// The key's name below `prefix` ("frontend.harris." and "frontend.harris.k" -> "k") when it is
// directly below it, else empty.
std::string_view parameter_leaf_name(std::string_view key, std::string_view prefix);

// Reads `name` of `section` into the member `field` points at, which keeps its value when the
// key is absent; a value of the wrong type or out of [lo, hi] ((lo, hi] when lo_open) is an error
// naming the file, line and key, followed by `doc` (what the key means) when given.
void read_parameter_field(yaml::MappingReader& section, std::string_view name,
                          const hal::ParameterField& field, double lo, double hi, bool lo_open,
                          std::string_view doc, yaml::Diagnostics& diagnostics);

// The member's value as a configuration writes it: a float with the digits that read back to
// it, a text quoted, a choice by its name.
std::string parameter_field_text(const hal::ParameterField& field);

// A YAML double-quoted scalar that reads back as `s`.
std::string yaml_quoted(const std::string& s);

// "doc (unit, [lo, hi])": the comment of a key in a sample configuration.
std::string parameter_comment(const hal::ParameterField& field, double lo, double hi, bool lo_open,
                              std::string_view unit, std::string_view doc);

// The keys of `table` directly below `prefix`, read from `section` into `config`.
template <typename Config>
void read_parameters(yaml::MappingReader& section, std::span<const hal::Parameter<Config>> table,
                     std::string_view prefix, Config& config, yaml::Diagnostics& diagnostics) {
  for (const auto& p : table) {
    const std::string_view name = parameter_leaf_name(p.key, prefix);
    if (!name.empty()) {
      read_parameter_field(section, name, p.field(config), p.lo, p.hi, p.lo_open, p.doc,
                           diagnostics);
    }
  }
}

// The mappings directly below `prefix` ("" gives the top-level sections), in the table's order,
// appended to `out` unless there already.
template <typename Config>
void parameter_children(std::span<const hal::Parameter<Config>> table, std::string_view prefix,
                        std::vector<std::string>& out) {
  for (const auto& p : table) {
    if (!p.key.starts_with(prefix)) {
      continue;
    }
    const std::string_view rest = p.key.substr(prefix.size());
    const auto dot = rest.find('.');
    if (dot == std::string_view::npos) {
      continue;
    }
    std::string child(rest.substr(0, dot));
    bool seen = false;
    for (const std::string& o : out) {
      seen = seen || o == child;
    }
    if (!seen) {
      out.push_back(std::move(child));
    }
  }
}

// "name: value" of each key of `table` directly below `prefix`, at `indent`; with `comments`,
// each followed by its parameter_comment.
template <typename Config>
void write_parameters(std::string& out, std::span<const hal::Parameter<Config>> table,
                      std::string_view prefix, std::string_view indent, const Config& config,
                      bool comments) {
  for (const auto& p : table) {
    const std::string_view name = parameter_leaf_name(p.key, prefix);
    if (name.empty()) {
      continue;
    }
    // The field accessor only takes the address of the member.
    const hal::ParameterField f = p.field(const_cast<Config&>(config));  // NOLINT
    out.append(indent).append(name).append(": ").append(parameter_field_text(f));
    if (comments) {
      out.append("  # ").append(parameter_comment(f, p.lo, p.hi, p.lo_open, p.unit, p.doc));
    }
    out.append("\n");
  }
}

}  // namespace cleanslam::readers
