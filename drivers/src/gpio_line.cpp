#include "cleanslam/drivers/gpio_line.hpp"

#include <cerrno>
#include <cstring>

namespace cleanslam::drivers {
namespace {

const char* mode_name(GpioLine::Mode mode) {
  switch (mode) {
    case GpioLine::Mode::kBothEdges:
      return "an input with edge events";
    case GpioLine::Mode::kRisingEdge:
      return "an input with rising-edge events";
    case GpioLine::Mode::kOutput:
      return "an output";
  }
  return "?";
}

}  // namespace

GpioLine::GpioLine(GpioApi& api, Diagnostics& diagnostics, std::string_view component,
                   const GpioLineConfig& config, const char* purpose, Mode mode, int initial_value)
    : api_(api) {
  if (config.line.empty()) {
    return;
  }
  chip_ = api_.open_chip(config.chip.c_str());
  if (chip_ == nullptr) {
    const int error = errno;
    const std::string chips = api_.describe_chips();
    reportf(diagnostics, Severity::kError, component,
            "GPIO chip '%s' for the %s not found (%s); chips present: %s. Running without it",
            config.chip.c_str(), purpose, std::strerror(error), chips.c_str());
    return;
  }
  GpioLineHandle* line = api_.find_line(chip_, config.line.c_str());
  if (line == nullptr) {
    const std::string lines = api_.describe_lines(chip_);
    reportf(diagnostics, Severity::kError, component,
            "GPIO line '%s' for the %s not found on chip '%s' (%s). Running without it",
            config.line.c_str(), purpose, config.chip.c_str(), lines.c_str());
    api_.close_chip(chip_);
    chip_ = nullptr;
    return;
  }
  const char* consumer = "cleanslam";
  int r = -1;
  switch (mode) {
    case Mode::kBothEdges:
      r = api_.request_edges(line, consumer, config.active_low);
      break;
    case Mode::kRisingEdge:
      r = api_.request_rising(line, consumer, config.active_low);
      break;
    case Mode::kOutput:
      r = api_.request_output(line, consumer, config.active_low, initial_value);
      break;
  }
  if (r < 0) {
    reportf(diagnostics, Severity::kError, component,
            "cannot request GPIO line '%s' of chip '%s' for the %s as %s (%s): is another driver "
            "or program holding it? Running without it",
            config.line.c_str(), config.chip.c_str(), purpose, mode_name(mode),
            std::strerror(errno));
    api_.close_chip(chip_);
    chip_ = nullptr;
    return;
  }
  line_ = line;
}

GpioLine::~GpioLine() {
  if (line_ != nullptr) {
    api_.release(line_);
  }
  if (chip_ != nullptr) {
    api_.close_chip(chip_);
  }
}

int GpioLine::event_fd() const {
  return line_ != nullptr ? api_.event_fd(line_) : -1;
}

}  // namespace cleanslam::drivers
