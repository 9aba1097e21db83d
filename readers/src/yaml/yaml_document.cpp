#include "cleanslam/readers/yaml_document.hpp"

#include "cleanslam/readers/bounded_file.hpp"
#include "cleanslam/readers/nearest_key.hpp"

#include <yaml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace cleanslam::readers::yaml {
namespace {

const Node& null_node() {
  static const Node kNull;
  return kNull;
}

std::string key_prefix(std::string_view key) {
  return key.empty() ? std::string() : std::string(key) + ": ";
}

std::string fail_at(const Location& where, std::string_view key, const std::string& what) {
  return where.str() + ": " + key_prefix(key) + what;
}

// The event stream of libyaml, one event at a time, freed automatically.
class EventReader {
 public:
  EventReader(std::string_view text, std::shared_ptr<const std::string> file)
      : file_(std::move(file)) {
    yaml_parser_initialize(&parser_);
    yaml_parser_set_input_string(&parser_, reinterpret_cast<const unsigned char*>(text.data()),
                                 text.size());
  }
  ~EventReader() {
    if (has_event_) {
      yaml_event_delete(&event_);
    }
    yaml_parser_delete(&parser_);
  }
  EventReader(const EventReader&) = delete;
  EventReader& operator=(const EventReader&) = delete;

  // Reads the next event into event(); false with error() set on a syntax error.
  bool next() {
    if (has_event_) {
      yaml_event_delete(&event_);
    }
    has_event_ = false;
    if (yaml_parser_parse(&parser_, &event_) == 0) {
      Location where{file_, static_cast<int>(parser_.problem_mark.line) + 1,
                     static_cast<int>(parser_.problem_mark.column) + 1};
      error_ = where.str() + ": YAML syntax error: " +
               (parser_.problem != nullptr ? parser_.problem : "unknown problem");
      if (parser_.context != nullptr) {
        error_ += std::string(" ") + parser_.context;
      }
      return false;
    }
    has_event_ = true;
    return true;
  }
  [[nodiscard]] const yaml_event_t& event() const { return event_; }
  [[nodiscard]] Location location() const {
    return Location{file_, static_cast<int>(event_.start_mark.line) + 1,
                    static_cast<int>(event_.start_mark.column) + 1};
  }
  [[nodiscard]] const std::string& error() const { return error_; }
  void fail(const std::string& message) { error_ = location().str() + ": " + message; }
  void fail_at_location(const Location& where, const std::string& message) {
    error_ = where.str() + ": " + message;
  }

 private:
  yaml_parser_t parser_{};
  yaml_event_t event_{};
  bool has_event_ = false;
  std::shared_ptr<const std::string> file_;
  std::string error_;
};

constexpr int kMaxDepth = 64;

// Builds the node that starts at the current event; false with reader.error() set on failure.
bool build(EventReader& reader, Node& out, int depth) {
  if (depth > kMaxDepth) {
    reader.fail("nesting deeper than 64 levels");
    return false;
  }
  const yaml_event_t& ev = reader.event();
  out.location = reader.location();
  switch (ev.type) {
    case YAML_ALIAS_EVENT:
      reader.fail("anchors and aliases are not supported");
      return false;
    case YAML_SCALAR_EVENT: {
      if (ev.data.scalar.anchor != nullptr) {
        reader.fail("anchors and aliases are not supported");
        return false;
      }
      out.scalar.assign(reinterpret_cast<const char*>(ev.data.scalar.value), ev.data.scalar.length);
      out.quoted = ev.data.scalar.style != YAML_PLAIN_SCALAR_STYLE;
      const bool is_null =
          !out.quoted && (out.scalar.empty() || out.scalar == "~" || out.scalar == "null" ||
                          out.scalar == "Null" || out.scalar == "NULL");
      out.kind = is_null ? Node::Kind::kNull : Node::Kind::kScalar;
      return true;
    }
    case YAML_SEQUENCE_START_EVENT: {
      if (ev.data.sequence_start.anchor != nullptr) {
        reader.fail("anchors and aliases are not supported");
        return false;
      }
      out.kind = Node::Kind::kSequence;
      while (true) {
        if (!reader.next()) {
          return false;
        }
        if (reader.event().type == YAML_SEQUENCE_END_EVENT) {
          return true;
        }
        Node item;
        if (!build(reader, item, depth + 1)) {
          return false;
        }
        out.items.push_back(std::move(item));
      }
    }
    case YAML_MAPPING_START_EVENT: {
      if (ev.data.mapping_start.anchor != nullptr) {
        reader.fail("anchors and aliases are not supported");
        return false;
      }
      out.kind = Node::Kind::kMapping;
      while (true) {
        if (!reader.next()) {
          return false;
        }
        if (reader.event().type == YAML_MAPPING_END_EVENT) {
          return true;
        }
        Node key;
        if (!build(reader, key, depth + 1)) {
          return false;
        }
        if (!key.is_scalar()) {
          reader.fail_at_location(key.location, "mapping keys must be scalars");
          return false;
        }
        if (out.find(key.scalar) != nullptr) {
          reader.fail_at_location(key.location, key.scalar + ": duplicate key");
          return false;
        }
        if (!reader.next()) {
          return false;
        }
        Node::Entry entry{key.scalar, key.location, Node{}};
        if (!build(reader, entry.value, depth + 1)) {
          return false;
        }
        out.entries.push_back(std::move(entry));
      }
    }
    default:
      reader.fail("unexpected YAML event");
      return false;
  }
}

// Drops a leading '+' (from_chars takes none); false when no digits can follow.
bool drop_plus_sign(std::string_view& s) {
  if (!s.empty() && s.front() == '+') {
    s.remove_prefix(1);
  }
  return !s.empty();
}

bool parse_plain_double(std::string_view s, double& out) {
  if (!drop_plus_sign(s)) {
    return false;
  }
  const char* end = s.data() + s.size();
  auto [ptr, ec] = std::from_chars(s.data(), end, out);
  return ec == std::errc() && ptr == end && std::isfinite(out);
}

bool parse_plain_int(std::string_view s, std::int64_t& out) {
  if (!drop_plus_sign(s)) {
    return false;
  }
  const char* end = s.data() + s.size();
  auto [ptr, ec] = std::from_chars(s.data(), end, out);
  return ec == std::errc() && ptr == end;
}

}  // namespace

std::string Location::str() const {
  return file_name() + ":" + std::to_string(line);
}

const Node* Node::find(std::string_view key) const {
  for (const Entry& e : entries) {
    if (e.key == key) {
      return &e.value;
    }
  }
  return nullptr;
}

std::string Node::describe() const {
  switch (kind) {
    case Kind::kNull:
      return "nothing";
    case Kind::kScalar:
      return "\"" + scalar + "\"";
    case Kind::kSequence:
      return "a sequence";
    case Kind::kMapping:
      return "a mapping";
  }
  return "?";
}

Result<Node> parse_string(std::string_view text, std::string file_name) {
  auto file = std::make_shared<const std::string>(std::move(file_name));
  EventReader reader(text, file);
  Node root;
  root.location = Location{file, 1, 1};
  bool in_document = false;
  while (true) {
    if (!reader.next()) {
      return Result<Node>::failure(reader.error());
    }
    const yaml_event_type_t type = reader.event().type;
    if (type == YAML_STREAM_END_EVENT) {
      break;
    }
    if (type == YAML_STREAM_START_EVENT) {
      continue;
    }
    if (type == YAML_DOCUMENT_START_EVENT) {
      if (in_document) {
        reader.fail(
            "a second YAML document (after \"---\"): a file holds one document, and a reader "
            "would take only the first; merge them into one");
        return Result<Node>::failure(reader.error());
      }
      in_document = true;
      continue;
    }
    if (type == YAML_DOCUMENT_END_EVENT) {
      continue;
    }
    if (!build(reader, root, 0)) {
      return Result<Node>::failure(reader.error());
    }
  }
  return root;
}

Result<Node> parse_file(const std::string& path) {
  auto text = read_bounded_file(path, kYamlFileLimit);
  if (!text.ok()) {
    return Result<Node>::failure(text.error());
  }
  return parse_string(*text, path);
}

Result<double> as_double(const Node& node, std::string_view key) {
  double v = 0.0;
  if (!node.is_scalar() || node.quoted || !parse_plain_double(node.scalar, v)) {
    return Result<double>::failure(
        fail_at(node.location, key, "expected a number, got " + node.describe()));
  }
  return v;
}

Result<std::int64_t> as_int(const Node& node, std::string_view key) {
  std::int64_t v = 0;
  if (!node.is_scalar() || node.quoted || !parse_plain_int(node.scalar, v)) {
    return Result<std::int64_t>::failure(
        fail_at(node.location, key, "expected an integer, got " + node.describe()));
  }
  return v;
}

Result<bool> as_bool(const Node& node, std::string_view key) {
  if (node.is_scalar() && !node.quoted) {
    const std::string& s = node.scalar;
    if (s == "true" || s == "True" || s == "TRUE") {
      return true;
    }
    if (s == "false" || s == "False" || s == "FALSE") {
      return false;
    }
  }
  return Result<bool>::failure(
      fail_at(node.location, key, "expected true or false, got " + node.describe()));
}

Result<std::string> as_string(const Node& node, std::string_view key) {
  if (!node.is_scalar()) {
    return Result<std::string>::failure(
        fail_at(node.location, key, "expected a string, got " + node.describe()));
  }
  return node.scalar;
}

std::string Diagnostics::error_text() const {
  std::string out;
  for (const std::string& e : errors) {
    if (!out.empty()) {
      out += '\n';
    }
    out += e;
  }
  return out;
}

MappingReader::MappingReader(const Node& node, std::string prefix, Diagnostics& diagnostics)
    : node_(&node), prefix_(std::move(prefix)), diagnostics_(&diagnostics) {
  if (!node.is_mapping() && !node.is_null()) {
    error(node.location.str() + ": " + key_prefix(prefix_) + "expected a mapping, got " +
          node.describe());
    node_ = &null_node();
  }
}

std::string MappingReader::path(std::string_view key) const {
  return prefix_.empty() ? std::string(key) : prefix_ + "." + std::string(key);
}

void MappingReader::error(std::string message) {
  diagnostics_->errors.push_back(std::move(message));
}

bool MappingReader::has(std::string_view key) const {
  const Node* n = node_->find(key);
  return n != nullptr && !n->is_null();
}

const Node* MappingReader::lookup(std::string_view key, bool required) {
  used_.emplace_back(key);
  const Node* n = node_->find(key);
  if (n != nullptr && n->is_null()) {
    n = nullptr;
  }
  if (n == nullptr && required) {
    error(node_->location.str() + ": " + path(key) + ": missing required key");
  }
  return n;
}

const Node* MappingReader::node(std::string_view key) {
  return lookup(key, false);
}

const Node* MappingReader::required_node(std::string_view key) {
  return lookup(key, true);
}

template <typename T, typename Convert>
T MappingReader::get(std::string_view key, bool required, T fallback, Convert convert) {
  const Node* n = lookup(key, required);
  if (n == nullptr) {
    return fallback;
  }
  auto r = convert(*n, path(key));
  if (!r.ok()) {
    error(r.error());
    return fallback;
  }
  return std::move(r).value();
}

double MappingReader::required_double(std::string_view key) {
  return get<double>(key, true, 0.0, as_double);
}
double MappingReader::optional_double(std::string_view key, double fallback) {
  return get<double>(key, false, fallback, as_double);
}
std::int64_t MappingReader::required_int(std::string_view key) {
  return get<std::int64_t>(key, true, 0, as_int);
}
std::int64_t MappingReader::optional_int(std::string_view key, std::int64_t fallback) {
  return get<std::int64_t>(key, false, fallback, as_int);
}
std::string MappingReader::required_string(std::string_view key) {
  return get<std::string>(key, true, std::string(), as_string);
}
std::string MappingReader::optional_string(std::string_view key, std::string fallback) {
  return get<std::string>(key, false, std::move(fallback), as_string);
}
bool MappingReader::optional_bool(std::string_view key, bool fallback) {
  return get<bool>(key, false, fallback, as_bool);
}

Result<std::vector<double>> as_doubles(const Node& node, std::string_view key,
                                       std::size_t expected_count) {
  using R = Result<std::vector<double>>;
  if (!node.is_sequence()) {
    return R::failure(
        fail_at(node.location, key, "expected a sequence of numbers, got " + node.describe()));
  }
  if (expected_count != 0 && node.items.size() != expected_count) {
    return R::failure(fail_at(node.location, key,
                              "expected " + std::to_string(expected_count) + " numbers, got " +
                                  std::to_string(node.items.size())));
  }
  std::vector<double> out;
  out.reserve(node.items.size());
  for (std::size_t i = 0; i < node.items.size(); ++i) {
    auto v = as_double(node.items[i], std::string(key) + "[" + std::to_string(i) + "]");
    if (!v.ok()) {
      return R::failure(v.error());
    }
    out.push_back(*v);
  }
  return out;
}

std::vector<double> MappingReader::required_doubles(std::string_view key,
                                                    std::size_t expected_count) {
  return get<std::vector<double>>(key, true, {}, [expected_count](const Node& n, const auto& k) {
    return as_doubles(n, k, expected_count);
  });
}

std::vector<double> MappingReader::optional_doubles(std::string_view key,
                                                    std::vector<double> fallback,
                                                    std::size_t expected_count) {
  return get<std::vector<double>>(
      key, false, std::move(fallback),
      [expected_count](const Node& n, const auto& k) { return as_doubles(n, k, expected_count); });
}

MappingReader MappingReader::required_mapping(std::string_view key) {
  const Node* n = lookup(key, true);
  return MappingReader(n != nullptr ? *n : null_node(), path(key), *diagnostics_);
}

MappingReader MappingReader::optional_mapping(std::string_view key) {
  const Node* n = lookup(key, false);
  return MappingReader(n != nullptr ? *n : null_node(), path(key), *diagnostics_);
}

void MappingReader::report_unknown_keys() {
  static constexpr std::string_view kSet = "--set ";
  for (const Node::Entry& e : node_->entries) {
    if (std::find(used_.begin(), used_.end(), e.key) == used_.end()) {
      // An unknown key is an error, in a file as on the command line: the value it was meant to
      // set would silently not apply.
      const std::string origin = e.key_location.file_name();
      const bool from_set = origin.rfind(kSet, 0) == 0;
      const std::string full = from_set ? origin.substr(kSet.size()) : path(e.key);
      const std::string here = path(e.key) + ".";
      const std::string rest =
          full.rfind(here, 0) == 0 ? full.substr(here.size() - 1) : std::string();
      const std::string hint = unknown_key_hint(e.key, used_, prefix_, rest);
      if (from_set) {
        diagnostics_->errors.push_back(origin + ": unknown key " + path(e.key) + "; " + hint);
      } else {
        diagnostics_->errors.push_back(e.key_location.str() + ": " + path(e.key) +
                                       ": unknown key; " + hint);
      }
    }
  }
}

}  // namespace cleanslam::readers::yaml
