#include <gpiod.h>

#include <cerrno>
#include <cstdlib>
#include <string>

#include "cleanslam/drivers/gpio_api.hpp"

// libgpiod's handles are passed through the seam as opaque pointers.
namespace cleanslam::drivers {
namespace {

gpiod_chip* chip_of(GpioChipHandle* c) {
  return reinterpret_cast<gpiod_chip*>(c);
}
gpiod_line* line_of(GpioLineHandle* l) {
  return reinterpret_cast<gpiod_line*>(l);
}

int flags(bool active_low) {
  return active_low ? GPIOD_LINE_REQUEST_FLAG_ACTIVE_LOW : 0;
}

bool is_number(const char* s) {
  if (*s == '\0') {
    return false;
  }
  for (; *s != '\0'; ++s) {
    if (*s < '0' || *s > '9') {
      return false;
    }
  }
  return true;
}

class Libgpiod final : public GpioApi {
 public:
  GpioChipHandle* open_chip(const char* chip) override {
    return reinterpret_cast<GpioChipHandle*>(gpiod_chip_open_lookup(chip));
  }
  void close_chip(GpioChipHandle* chip) override {
    if (chip != nullptr) {
      gpiod_chip_close(chip_of(chip));
    }
  }
  GpioLineHandle* find_line(GpioChipHandle* chip, const char* line) override {
    if (is_number(line)) {
      const unsigned long offset = std::strtoul(line, nullptr, 10);
      if (offset >= gpiod_chip_num_lines(chip_of(chip))) {
        errno = EINVAL;
        return nullptr;
      }
      return reinterpret_cast<GpioLineHandle*>(
          gpiod_chip_get_line(chip_of(chip), static_cast<unsigned int>(offset)));
    }
    return reinterpret_cast<GpioLineHandle*>(gpiod_chip_find_line(chip_of(chip), line));
  }
  int request_edges(GpioLineHandle* line, const char* consumer, bool active_low) override {
    return gpiod_line_request_both_edges_events_flags(line_of(line), consumer, flags(active_low));
  }
  int request_rising(GpioLineHandle* line, const char* consumer, bool active_low) override {
    return gpiod_line_request_rising_edge_events_flags(line_of(line), consumer, flags(active_low));
  }
  int request_output(GpioLineHandle* line, const char* consumer, bool active_low,
                     int value) override {
    return gpiod_line_request_output_flags(line_of(line), consumer, flags(active_low), value);
  }
  int event_fd(GpioLineHandle* line) override { return gpiod_line_event_get_fd(line_of(line)); }
  int read_edge(GpioLineHandle* line, GpioEdge& edge) override {
    gpiod_line_event event{};
    const int r = gpiod_line_event_read(line_of(line), &event);
    if (r == 0) {
      edge.rising = event.event_type == GPIOD_LINE_EVENT_RISING_EDGE;
      edge.t_ns = static_cast<hal::TimeNs>(event.ts.tv_sec) * hal::kNsPerSecond + event.ts.tv_nsec;
    }
    return r;
  }
  int get_value(GpioLineHandle* line) override { return gpiod_line_get_value(line_of(line)); }
  int set_value(GpioLineHandle* line, int value) override {
    return gpiod_line_set_value(line_of(line), value);
  }
  void release(GpioLineHandle* line) override { gpiod_line_release(line_of(line)); }

  std::string describe_chips() override {
    std::string out;
    gpiod_chip_iter* iter = gpiod_chip_iter_new();
    if (iter == nullptr) {
      return "none";
    }
    gpiod_chip* chip = nullptr;
    gpiod_foreach_chip(iter, chip) {
      if (!out.empty()) {
        out += ", ";
      }
      out += std::string(gpiod_chip_name(chip)) + " [" + gpiod_chip_label(chip) + ", " +
             std::to_string(gpiod_chip_num_lines(chip)) + " lines]";
    }
    gpiod_chip_iter_free(iter);
    return out.empty() ? "none" : out;
  }

  std::string describe_lines(GpioChipHandle* chip) override {
    std::string out;
    const unsigned int n = gpiod_chip_num_lines(chip_of(chip));
    for (unsigned int i = 0; i < n; ++i) {
      gpiod_line* line = gpiod_chip_get_line(chip_of(chip), i);
      const char* name = line != nullptr ? gpiod_line_name(line) : nullptr;
      out += (i == 0 ? "" : ", ") + std::to_string(i) + "=" + (name != nullptr ? name : "unnamed");
    }
    return std::to_string(n) + " lines: " + out;
  }
};

}  // namespace

GpioApi& libgpiod_api() {
  static Libgpiod api;
  return api;
}

}  // namespace cleanslam::drivers
