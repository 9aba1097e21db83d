#include "yaml_paths.hpp"

namespace cleanslam::firmware::yaml_paths {

namespace yaml = readers::yaml;

const yaml::Node* find(const yaml::Node& root, std::string_view key) {
  const yaml::Node* node = &root;
  while (node != nullptr && !key.empty()) {
    const auto dot = key.find('.');
    node = node->find(key.substr(0, dot));
    key = dot == std::string_view::npos ? std::string_view() : key.substr(dot + 1);
  }
  return node;
}

yaml::Node* make(yaml::Node& root, std::string_view key, const yaml::Location& where,
                 std::string& error) {
  yaml::Node* node = &root;
  std::size_t start = 0;
  while (true) {
    const auto dot = key.find('.', start);
    const std::string part(key.substr(start, dot == std::string_view::npos ? dot : dot - start));
    if (part.empty()) {
      error = "empty key component";
      return nullptr;
    }
    if (node->is_null()) {
      node->kind = yaml::Node::Kind::kMapping;
      node->location = where;
    }
    if (!node->is_mapping()) {
      error = std::string(key.substr(0, start - 1)) + " is not a mapping";
      return nullptr;
    }
    yaml::Node::Entry* entry = nullptr;
    for (auto& e : node->entries) {
      if (e.key == part) {
        entry = &e;
      }
    }
    if (entry == nullptr) {
      node->entries.push_back(yaml::Node::Entry{part, where, yaml::Node{}});
      entry = &node->entries.back();
    }
    if (dot == std::string_view::npos) {
      return &entry->value;
    }
    node = &entry->value;
    start = dot + 1;
  }
}

}  // namespace cleanslam::firmware::yaml_paths
