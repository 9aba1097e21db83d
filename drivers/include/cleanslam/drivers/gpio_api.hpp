#pragma once

#include <string>

#include "cleanslam/hal/time.hpp"

namespace cleanslam::drivers {

struct GpioChipHandle;
struct GpioLineHandle;

struct GpioEdge {
  bool rising = false;
  hal::TimeNs t_ns = 0;  // kernel time stamp (CLOCK_MONOTONIC since Linux 5.7)
};

// The seam over libgpiod's v1 API (Debian 12), so unit tests can put fake lines behind it.
// Calls return what libgpiod returns and leave errno set on failure.
class GpioApi {
 public:
  virtual ~GpioApi() = default;
  // By name ("gpiochip0"), path, label or number.
  virtual GpioChipHandle* open_chip(const char* chip) = 0;
  virtual void close_chip(GpioChipHandle* chip) = 0;
  // By line name, or by offset when `line` is a number.
  virtual GpioLineHandle* find_line(GpioChipHandle* chip, const char* line) = 0;
  virtual int request_edges(GpioLineHandle* line, const char* consumer, bool active_low) = 0;
  virtual int request_rising(GpioLineHandle* line, const char* consumer, bool active_low) = 0;
  virtual int request_output(GpioLineHandle* line, const char* consumer, bool active_low,
                             int value) = 0;
  virtual int event_fd(GpioLineHandle* line) = 0;
  // Blocks when no event is pending: call after event_fd() polled readable.
  virtual int read_edge(GpioLineHandle* line, GpioEdge& edge) = 0;
  virtual int get_value(GpioLineHandle* line) = 0;
  virtual int set_value(GpioLineHandle* line, int value) = 0;
  virtual void release(GpioLineHandle* line) = 0;
  // For error messages: the chips there are, and one chip's lines.
  virtual std::string describe_chips() = 0;
  virtual std::string describe_lines(GpioChipHandle* chip) = 0;
};

GpioApi& libgpiod_api();

}  // namespace cleanslam::drivers
