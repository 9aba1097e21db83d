#include "cleanslam/drivers/lift_switch.hpp"

namespace cleanslam::drivers {

LiftSwitch::LiftSwitch(const LiftSwitchConfig& config, GpioApi& api, Os& os,
                       Diagnostics& diagnostics)
    : config_(config),
      api_(api),
      os_(os),
      line_(api, diagnostics, "lift", config.gpio, "lift switch", GpioLine::Mode::kBothEdges),
      readiness_(os) {
  if (!line_.available()) {
    return;
  }
  event_fd_ = line_.event_fd();
  readiness_.watch(event_fd_);
  if (api_.get_value(line_.handle()) == 1) {
    pending_initial_ = true;
    readiness_.arm_timer(1);
  }
}

bool LiftSwitch::change_to(bool lifted, hal::SensorEvent& out) {
  if (lifted == lifted_) {
    return false;
  }
  lifted_ = lifted;
  ++(lifted ? stats_.lifts : stats_.set_downs);
  out = hal::SensorEvent{};
  out.kind = hal::SensorEvent::Kind::kLift;
  out.lifted = lifted;
  return true;
}

bool LiftSwitch::read(hal::SensorEvent& out) {
  if (!line_.available()) {
    return false;
  }
  if (pending_initial_) {
    pending_initial_ = false;
    readiness_.disarm_timer();
    return change_to(true, out);
  }
  const hal::TimeNs now = os_.monotonic_now();
  // Drain the pending edges; the first change outside a bounce window is reported at once.
  while (os_.poll_readable(event_fd_, 0)) {
    GpioEdge edge;
    if (api_.read_edge(line_.handle(), edge) < 0) {
      break;
    }
    ++stats_.edges;
    if (now < settle_until_ns_) {
      ++stats_.bounces;
      continue;
    }
    if (edge.rising != lifted_) {
      settle_until_ns_ = now + config_.debounce_ns;
      readiness_.arm_timer(config_.debounce_ns);
      return change_to(edge.rising, out);
    }
  }
  if (readiness_.timer_fired()) {
    // The bounce window is over: the level decides.
    const int level = api_.get_value(line_.handle());
    if (level >= 0) {
      return change_to(level == 1, out);
    }
  }
  return false;
}

}  // namespace cleanslam::drivers
