#pragma once

#include <cstdint>

#include "cleanslam/drivers/diagnostics.hpp"
#include "cleanslam/drivers/gpio_api.hpp"
#include "cleanslam/drivers/gpio_line.hpp"
#include "cleanslam/drivers/os.hpp"
#include "cleanslam/drivers/readiness.hpp"
#include "cleanslam/hal/interfaces.hpp"

namespace cleanslam::drivers {

// The driver only reports lifted / set down; what set-down means is the firmware's
// map_management.on_set_down (relocalize or a new map).
struct LiftSwitchConfig {
  GpioLineConfig gpio;  // active level = lifted
  // Edges within this time of an accepted change are bounce; the level is re-read after it.
  hal::TimeNs debounce_ns = 20 * hal::kNsPerMillisecond;
};

struct LiftSwitchStats {
  std::uint64_t edges = 0;
  std::uint64_t bounces = 0;
  std::uint64_t lifts = 0;
  std::uint64_t set_downs = 0;
};

// The lift / wheel-drop switch: SensorEvent::kLift with `lifted` on every debounced change, and
// one at start when the robot starts lifted.
class LiftSwitch final : public hal::SensorSource {
 public:
  LiftSwitch(const LiftSwitchConfig& config, GpioApi& api = libgpiod_api(), Os& os = linux_os(),
             Diagnostics& diagnostics = stderr_diagnostics());

  [[nodiscard]] int fd() const override { return readiness_.fd(); }
  bool read(hal::SensorEvent& out) override;

  [[nodiscard]] bool available() const { return line_.available(); }
  [[nodiscard]] bool lifted() const { return lifted_; }
  [[nodiscard]] const LiftSwitchStats& stats() const { return stats_; }

 private:
  bool change_to(bool lifted, hal::SensorEvent& out);

  LiftSwitchConfig config_;
  GpioApi& api_;
  Os& os_;
  GpioLine line_;
  Readiness readiness_;
  int event_fd_ = -1;
  bool lifted_ = false;
  bool pending_initial_ = false;
  hal::TimeNs settle_until_ns_ = 0;
  LiftSwitchStats stats_;
};

}  // namespace cleanslam::drivers
