#include "dataset_images.hpp"

#include <png.h>
#include <yaml.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

namespace cleanslam::tools::track {

namespace {

yaml_node_t* mapping_value(yaml_document_t* doc, yaml_node_t* map, const char* key) {
  if (map == nullptr || map->type != YAML_MAPPING_NODE) {
    return nullptr;
  }
  for (yaml_node_pair_t* p = map->data.mapping.pairs.start; p < map->data.mapping.pairs.top; ++p) {
    yaml_node_t* k = yaml_document_get_node(doc, p->key);
    if (k != nullptr && k->type == YAML_SCALAR_NODE &&
        std::strcmp(reinterpret_cast<const char*>(k->data.scalar.value), key) == 0) {
      return yaml_document_get_node(doc, p->value);
    }
  }
  return nullptr;
}

bool read_camera_size(const std::string& file, int& width, int& height, std::string& error) {
  FILE* f = std::fopen(file.c_str(), "rb");
  if (f == nullptr) {
    error = file + ": cannot open: " + std::strerror(errno);
    return false;
  }
  yaml_parser_t parser;
  yaml_document_t doc;
  yaml_parser_initialize(&parser);
  yaml_parser_set_input_file(&parser, f);
  const bool loaded = yaml_parser_load(&parser, &doc) != 0;
  bool ok = false;
  if (!loaded) {
    error = file + ":" + std::to_string(parser.problem_mark.line + 1) +
            ": YAML error: " + (parser.problem != nullptr ? parser.problem : "unknown");
  } else {
    yaml_node_t* camera = mapping_value(&doc, yaml_document_get_root_node(&doc), "camera");
    ok = true;
    for (const auto& [key, dst] : {std::pair<const char*, int*>{"width", &width},
                                   std::pair<const char*, int*>{"height", &height}}) {
      yaml_node_t* v = mapping_value(&doc, camera, key);
      if (v == nullptr || v->type != YAML_SCALAR_NODE) {
        error = file + ": missing required key camera." + key;
        ok = false;
        break;
      }
      const char* text = reinterpret_cast<const char*>(v->data.scalar.value);
      char* end = nullptr;
      const long n = std::strtol(text, &end, 10);
      if (end == text || *end != '\0' || n <= 0 || n > 100000) {
        error = file + ":" + std::to_string(v->start_mark.line + 1) + ": camera." + key +
                " is not a positive integer: '" + text + "'";
        ok = false;
        break;
      }
      *dst = static_cast<int>(n);
    }
    yaml_document_delete(&doc);
  }
  yaml_parser_delete(&parser);
  std::fclose(f);
  return ok;
}

bool ends_with(const std::string& s, const char* suffix) {
  const std::size_t n = std::strlen(suffix);
  return s.size() >= n && s.compare(s.size() - n, n, suffix) == 0;
}

bool load_pgm(const std::string& path, OwnedImage& out, std::string& error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    error = path + ": cannot open";
    return false;
  }
  std::string magic;
  int w = 0;
  int h = 0;
  int maxval = 0;
  in >> magic;
  // Skip comments between header fields.
  auto next_int = [&in](int& v) {
    while (in >> std::ws && in.peek() == '#') {
      std::string line;
      std::getline(in, line);
    }
    return static_cast<bool>(in >> v);
  };
  if (magic != "P5" || !next_int(w) || !next_int(h) || !next_int(maxval)) {
    error = path + ": not a binary PGM (P5) header";
    return false;
  }
  if (maxval != 255 || w <= 0 || h <= 0) {
    error = path + ": PGM " + std::to_string(w) + "x" + std::to_string(h) + " maxval " +
            std::to_string(maxval) + " (only 8-bit, maxval 255, is supported)";
    return false;
  }
  in.get();
  out.width = w;
  out.height = h;
  out.pixels.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  in.read(reinterpret_cast<char*>(out.pixels.data()),
          static_cast<std::streamsize>(out.pixels.size()));
  if (!in) {
    error = path + ": truncated PGM data";
    return false;
  }
  return true;
}

}  // namespace

bool load_gray_image(const std::string& path, OwnedImage& out, std::string& error) {
  if (ends_with(path, ".pgm") || ends_with(path, ".PGM")) {
    return load_pgm(path, out, error);
  }
  png_image img;
  std::memset(&img, 0, sizeof(img));
  img.version = PNG_IMAGE_VERSION;
  if (png_image_begin_read_from_file(&img, path.c_str()) == 0) {
    error = path + ": " + img.message;
    return false;
  }
  img.format = PNG_FORMAT_GRAY;
  out.width = static_cast<int>(img.width);
  out.height = static_cast<int>(img.height);
  out.pixels.resize(PNG_IMAGE_SIZE(img));
  if (png_image_finish_read(&img, nullptr, out.pixels.data(), 0, nullptr) == 0) {
    error = path + ": " + img.message;
    png_image_free(&img);
    return false;
  }
  return true;
}

bool load_dataset_images(const std::string& dataset, DatasetImages& out, std::string& error) {
  if (!read_camera_size(dataset + "/sensors.yaml", out.width, out.height, error)) {
    return false;
  }
  const std::string csv = dataset + "/cam0/data.csv";
  std::ifstream in(csv);
  if (!in) {
    error = csv + ": cannot open (the dataset has no camera images)";
    return false;
  }
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') {
      line.pop_back();
    }
    if (line.empty() || line[0] == '#') {
      continue;
    }
    const std::size_t comma = line.find(',');
    if (comma == std::string::npos) {
      error =
          csv + ":" + std::to_string(line_no) + ": expected 't_ns,filename', got '" + line + "'";
      return false;
    }
    const std::string t_text = line.substr(0, comma);
    char* end = nullptr;
    errno = 0;
    const long long t = std::strtoll(t_text.c_str(), &end, 10);
    if (end == t_text.c_str() || *end != '\0' || errno != 0) {
      error = csv + ":" + std::to_string(line_no) + ": t_ns '" + t_text + "' is not an integer";
      return false;
    }
    std::string name = line.substr(comma + 1);
    while (!name.empty() && name.front() == ' ') {
      name.erase(0, 1);
    }
    if (!out.frames.empty() && t < out.frames.back().t_ns) {
      error = csv + ":" + std::to_string(line_no) + ": t_ns " + t_text + " goes back in time";
      return false;
    }
    out.frames.push_back({static_cast<hal::TimeNs>(t), dataset + "/cam0/data/" + name});
  }
  return true;
}

}  // namespace cleanslam::tools::track
