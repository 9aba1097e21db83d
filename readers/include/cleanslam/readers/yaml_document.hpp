#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "cleanslam/readers/result.hpp"

// A small YAML document tree on top of libyaml: mappings, sequences (block and flow) and scalars,
// each node with the file name, line and column it came from. Anchors, aliases and tags other
// than the core ones are refused. Nothing throws: parsing returns a Result, typed reading goes
// through a MappingReader that collects errors and warnings.
namespace cleanslam::readers::yaml {

struct Location {
  std::shared_ptr<const std::string> file;  // shared by every node of a document
  int line = 0;                             // 1-based
  int column = 0;                           // 1-based

  [[nodiscard]] std::string file_name() const { return file ? *file : std::string("<yaml>"); }
  // "file:line"
  [[nodiscard]] std::string str() const;
};

class Node {
 public:
  enum class Kind : std::uint8_t { kNull, kScalar, kSequence, kMapping };
  struct Entry;

  Kind kind = Kind::kNull;
  Location location;
  std::string scalar;   // kScalar: the text as written (after YAML unquoting)
  bool quoted = false;  // kScalar: written in quotes (so never a number)
  std::vector<Node> items;
  std::vector<Entry> entries;  // kMapping, in file order, keys unique

  [[nodiscard]] bool is_null() const { return kind == Kind::kNull; }
  [[nodiscard]] bool is_scalar() const { return kind == Kind::kScalar; }
  [[nodiscard]] bool is_sequence() const { return kind == Kind::kSequence; }
  [[nodiscard]] bool is_mapping() const { return kind == Kind::kMapping; }
  // The value of `key` in a mapping, or nullptr.
  [[nodiscard]] const Node* find(std::string_view key) const;
  // A short description for messages: the scalar in quotes, "a mapping", "a sequence", "nothing".
  [[nodiscard]] std::string describe() const;
};

struct Node::Entry {
  std::string key;
  Location key_location;
  Node value;
};

// Parses the one document of a YAML text; a second document is an error. `file_name` is used in
// messages.
Result<Node> parse_string(std::string_view text, std::string file_name = "<string>");
// Parses a file; messages name `path` as given.
Result<Node> parse_file(const std::string& path);

// Scalar conversions; the error names the location and `key` ("f.yaml:7: camera.fx: expected a
// number, got "abc""). Numbers must be finite; integers must fit.
Result<double> as_double(const Node& node, std::string_view key);
Result<std::int64_t> as_int(const Node& node, std::string_view key);
Result<bool> as_bool(const Node& node, std::string_view key);
Result<std::string> as_string(const Node& node, std::string_view key);
// A sequence of numbers; `expected_count` 0 accepts any length.
Result<std::vector<double>> as_doubles(const Node& node, std::string_view key,
                                       std::size_t expected_count);

struct Diagnostics {
  std::vector<std::string> errors;
  std::vector<std::string> warnings;
  [[nodiscard]] bool ok() const { return errors.empty(); }
  // All errors, one per line.
  [[nodiscard]] std::string error_text() const;
};

// Typed access to the keys of one mapping. Every getter records the key as known; a missing
// required key or a value of the wrong type adds an error to the Diagnostics and returns the
// default. report_unknown_keys() adds a warning for each key no getter asked for.
class MappingReader {
 public:
  // `node` must outlive the reader. `prefix` is the dotted path of the mapping ("" at the root).
  // A node that is not a mapping adds an error (unless it is null and `required` is false).
  MappingReader(const Node& node, std::string prefix, Diagnostics& diagnostics);

  [[nodiscard]] bool has(std::string_view key) const;
  double required_double(std::string_view key);
  double optional_double(std::string_view key, double fallback);
  std::int64_t required_int(std::string_view key);
  std::int64_t optional_int(std::string_view key, std::int64_t fallback);
  std::string required_string(std::string_view key);
  std::string optional_string(std::string_view key, std::string fallback);
  bool optional_bool(std::string_view key, bool fallback);
  // A sequence of numbers; `expected_count` 0 accepts any length.
  std::vector<double> required_doubles(std::string_view key, std::size_t expected_count);
  std::vector<double> optional_doubles(std::string_view key, std::vector<double> fallback,
                                       std::size_t expected_count);
  // A nested mapping; a missing optional one reads as empty (every getter then yields defaults).
  MappingReader required_mapping(std::string_view key);
  MappingReader optional_mapping(std::string_view key);
  // The raw node of a key (marked as known), or nullptr.
  const Node* node(std::string_view key);
  // The same; an absent (or null) key is a "missing required key" error.
  const Node* required_node(std::string_view key);

  // An error "file:line: prefix.key: unknown key; did you mean ..." for each key not asked for.
  void report_unknown_keys();
  // Full dotted name of a key of this mapping.
  [[nodiscard]] std::string path(std::string_view key) const;

 private:
  const Node* lookup(std::string_view key, bool required);
  template <typename T, typename Convert>
  T get(std::string_view key, bool required, T fallback, Convert convert);
  void error(std::string message);

  const Node* node_;
  std::string prefix_;
  Diagnostics* diagnostics_;
  std::vector<std::string> used_;
};

}  // namespace cleanslam::readers::yaml
