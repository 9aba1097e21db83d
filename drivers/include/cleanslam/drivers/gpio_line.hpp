#pragma once

#include <string>
#include <string_view>

#include "cleanslam/drivers/diagnostics.hpp"
#include "cleanslam/drivers/gpio_api.hpp"

namespace cleanslam::drivers {

struct GpioLineConfig {
  std::string chip = "gpiochip0";  // name, path, label or number
  std::string line;                // line name or offset; empty: not used
  bool active_low = false;
};

// One requested GPIO line; every failure is explained (what was asked, what the system has)
// and leaves the line unavailable rather than stopping the program.
class GpioLine {
 public:
  enum class Mode : std::uint8_t { kBothEdges, kRisingEdge, kOutput };

  GpioLine(GpioApi& api, Diagnostics& diagnostics, std::string_view component,
           const GpioLineConfig& config, const char* purpose, Mode mode, int initial_value = 0);
  ~GpioLine();
  GpioLine(const GpioLine&) = delete;
  GpioLine& operator=(const GpioLine&) = delete;

  [[nodiscard]] bool available() const { return line_ != nullptr; }
  [[nodiscard]] GpioLineHandle* handle() const { return line_; }
  [[nodiscard]] int event_fd() const;

 private:
  GpioApi& api_;
  GpioChipHandle* chip_ = nullptr;
  GpioLineHandle* line_ = nullptr;
};

}  // namespace cleanslam::drivers
