#pragma once

#include <cerrno>
#include <cstdlib>
#include <deque>
#include <map>
#include <string>
#include <vector>

#include "cleanslam/drivers/gpio_api.hpp"
#include "fake_os.hpp"

namespace cleanslam::drivers::testing {

// Fake GPIO chips behind the libgpiod seam; edge events are queued by the test.
class FakeGpio : public GpioApi {
 public:
  struct Line {
    std::string name;
    int value = 0;  // physical level
    bool requested = false;
    bool output = false;
    bool active_low = false;
    bool busy = false;
    std::deque<GpioEdge> events;
    std::vector<int> writes;
  };
  struct Chip {
    std::string label;
    std::vector<Line> lines;
  };
  std::map<std::string, Chip> chips;
  int open_chips = 0;

  explicit FakeGpio(FakeOs& os) : os_(os) {
    chips["gpiochip0"] = Chip{"pl061", std::vector<Line>(8)};
    chips["gpiochip0"].lines[5].name = "LIFT";
    os_.readable_hook = [this](int fd) {
      Line* l = by_fd(fd);
      return l != nullptr && !l->events.empty();
    };
  }

  Line& line(const std::string& chip, int offset) {
    return chips.at(chip).lines.at(static_cast<std::size_t>(offset));
  }
  void edge(const std::string& chip, int offset, bool rising, hal::TimeNs t_ns) {
    Line& l = line(chip, offset);
    l.value = rising ? 1 : 0;
    l.events.push_back(GpioEdge{rising != l.active_low, t_ns});
  }

  GpioChipHandle* open_chip(const char* chip) override {
    const auto it = chips.find(chip);
    if (it == chips.end()) {
      errno = ENOENT;
      return nullptr;
    }
    ++open_chips;
    return reinterpret_cast<GpioChipHandle*>(&it->second);
  }
  void close_chip(GpioChipHandle*) override { --open_chips; }
  GpioLineHandle* find_line(GpioChipHandle* chip, const char* name) override {
    Chip& c = *reinterpret_cast<Chip*>(chip);
    const std::string n(name);
    if (!n.empty() && n.find_first_not_of("0123456789") == std::string::npos) {
      const auto offset = std::strtoul(name, nullptr, 10);
      if (offset >= c.lines.size()) {
        errno = EINVAL;
        return nullptr;
      }
      return reinterpret_cast<GpioLineHandle*>(&c.lines[offset]);
    }
    for (Line& l : c.lines) {
      if (l.name == n) {
        return reinterpret_cast<GpioLineHandle*>(&l);
      }
    }
    errno = ENOENT;
    return nullptr;
  }
  int request(GpioLineHandle* handle, bool active_low, bool output) {
    Line& l = *reinterpret_cast<Line*>(handle);
    if (l.busy || l.requested) {
      errno = EBUSY;
      return -1;
    }
    l.requested = true;
    l.output = output;
    l.active_low = active_low;
    return 0;
  }
  int request_edges(GpioLineHandle* line, const char*, bool active_low) override {
    return request(line, active_low, false);
  }
  int request_rising(GpioLineHandle* line, const char*, bool active_low) override {
    return request(line, active_low, false);
  }
  int request_output(GpioLineHandle* line, const char*, bool active_low, int value) override {
    const int r = request(line, active_low, true);
    if (r == 0) {
      set_value(line, value);
    }
    return r;
  }
  int event_fd(GpioLineHandle* handle) override {
    for (auto& [name, chip] : chips) {
      for (std::size_t i = 0; i < chip.lines.size(); ++i) {
        if (reinterpret_cast<Line*>(handle) == &chip.lines[i]) {
          return 500 + static_cast<int>(i);
        }
      }
    }
    return -1;
  }
  int read_edge(GpioLineHandle* handle, GpioEdge& edge) override {
    Line& l = *reinterpret_cast<Line*>(handle);
    if (l.events.empty()) {
      errno = EAGAIN;
      return -1;
    }
    edge = l.events.front();
    l.events.pop_front();
    return 0;
  }
  int get_value(GpioLineHandle* handle) override {
    const Line& l = *reinterpret_cast<Line*>(handle);
    return l.value != (l.active_low ? 1 : 0) ? 1 : 0;
  }
  int set_value(GpioLineHandle* handle, int value) override {
    Line& l = *reinterpret_cast<Line*>(handle);
    l.value = (value != 0) != l.active_low ? 1 : 0;
    l.writes.push_back(value);
    return 0;
  }
  void release(GpioLineHandle* handle) override {
    reinterpret_cast<Line*>(handle)->requested = false;
  }
  std::string describe_chips() override {
    std::string s;
    for (auto& [name, chip] : chips) {
      s += name + " [" + chip.label + ", " + std::to_string(chip.lines.size()) + " lines]";
    }
    return s;
  }
  std::string describe_lines(GpioChipHandle* chip) override {
    return std::to_string(reinterpret_cast<Chip*>(chip)->lines.size()) + " lines";
  }

 private:
  Line* by_fd(int fd) {
    const int offset = fd - 500;
    auto& lines = chips.begin()->second.lines;
    if (offset < 0 || offset >= static_cast<int>(lines.size())) {
      return nullptr;
    }
    return &lines[static_cast<std::size_t>(offset)];
  }
  FakeOs& os_;
};

}  // namespace cleanslam::drivers::testing
