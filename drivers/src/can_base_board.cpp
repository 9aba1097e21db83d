#include "cleanslam/drivers/can_base_board.hpp"

#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <sys/socket.h>

#include <cerrno>
#include <cstring>
#include <utility>

namespace cleanslam::drivers {
namespace {

constexpr std::string_view kCanComponent = "can";

hal::TimeNs timespec_ns(const timespec& ts) {
  return static_cast<hal::TimeNs>(ts.tv_sec) * hal::kNsPerSecond + ts.tv_nsec;
}

}  // namespace

CanBaseBoard::CanBaseBoard(CanBaseBoardConfig config, Os& os, Diagnostics& diagnostics)
    : config_(std::move(config)),
      os_(os),
      diagnostics_(diagnostics),
      readiness_(os),
      backoff_(config_.reopen_min_ns, config_.reopen_max_ns) {
  if (config_.max_frames_per_read < 1) {
    config_.max_frames_per_read = 1;
  }
  if (!open_socket()) {
    schedule_reopen();
  }
}

CanBaseBoard::~CanBaseBoard() {
  close_socket();
}

bool CanBaseBoard::open_socket() {
  const char* name = config_.interface.c_str();
  const unsigned int index = os_.if_nametoindex(name);
  if (index == 0) {
    ++stats_.open_failures;
    reportf(diagnostics_, Severity::kError, kCanComponent,
            "interface '%s' not found (%s): is the CAN driver loaded and the link configured "
            "('ip link set %s up type can bitrate 500000')? Running without odometry",
            name, std::strerror(errno), name);
    return false;
  }
  const int s = os_.socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK, CAN_RAW);
  if (s < 0) {
    ++stats_.open_failures;
    reportf(diagnostics_, Severity::kError, kCanComponent,
            "cannot open a raw CAN socket (%s): is the can-raw module available?",
            std::strerror(errno));
    return false;
  }
  const can_filter filters[] = {
      {can_map::kEncoderId, CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG},
      {can_map::kGyroId, CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG},
  };
  const can_err_mask_t error_mask = CAN_ERR_MASK;
  const int on = 1;
  sockaddr_can address{};
  address.can_family = AF_CAN;
  address.can_ifindex = static_cast<int>(index);
  if (os_.setsockopt(s, SOL_CAN_RAW, CAN_RAW_FILTER, filters, sizeof filters) < 0 ||
      os_.setsockopt(s, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &error_mask, sizeof error_mask) < 0 ||
      os_.setsockopt(s, SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof on) < 0 ||
      os_.bind(s, reinterpret_cast<const sockaddr*>(&address), sizeof address) < 0) {
    ++stats_.open_failures;
    reportf(diagnostics_, Severity::kError, kCanComponent,
            "cannot set up the raw socket on '%s' (filters, time stamps, bind): %s", name,
            std::strerror(errno));
    os_.close(s);
    return false;
  }
  socket_ = s;
  readiness_.watch(socket_);
  ++stats_.opens;
  backoff_.reset();
  encoder_seq_.reset();
  gyro_seq_.reset();
  if (stats_.opens > 1 || stats_.open_failures > 0) {
    reportf(diagnostics_, Severity::kInfo, kCanComponent, "listening on '%s' again", name);
  }
  return true;
}

void CanBaseBoard::close_socket() {
  if (socket_ >= 0) {
    readiness_.unwatch(socket_);
    os_.close(socket_);
    socket_ = -1;
  }
}

void CanBaseBoard::schedule_reopen() {
  const hal::TimeNs delay = backoff_.next();
  readiness_.arm_timer(delay);
}

bool CanBaseBoard::read(hal::SensorEvent& out) {
  if (socket_ < 0) {
    if (readiness_.timer_fired() && !open_socket()) {
      schedule_reopen();
    }
    if (socket_ < 0) {
      return false;
    }
  }
  for (int i = 0; i < config_.max_frames_per_read; ++i) {
    can_frame raw{};
    iovec io{&raw, sizeof raw};
    alignas(cmsghdr) char control[CMSG_SPACE(sizeof(timespec)) + 64];
    msghdr message{};
    message.msg_iov = &io;
    message.msg_iovlen = 1;
    message.msg_control = control;
    message.msg_controllen = sizeof control;
    const ssize_t n = os_.recvmsg(socket_, &message, MSG_DONTWAIT);
    if (n < 0) {
      if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) {
        return false;
      }
      ++stats_.receive_errors;
      reportf(diagnostics_, Severity::kError, kCanComponent,
              "receive on '%s' failed (%s): closing, reopening with back-off",
              config_.interface.c_str(), std::strerror(errno));
      close_socket();
      schedule_reopen();
      return false;
    }
    const hal::TimeNs mono_now = os_.monotonic_now();
    hal::TimeNs t_ns = mono_now;
    for (cmsghdr* c = CMSG_FIRSTHDR(&message); c != nullptr; c = CMSG_NXTHDR(&message, c)) {
      if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_TIMESTAMPNS) {
        timespec ts{};
        std::memcpy(&ts, CMSG_DATA(c), sizeof ts);
        // The kernel stamps with CLOCK_REALTIME; move it onto the monotonic clock.
        t_ns = timespec_ns(ts) - (os_.realtime_now() - mono_now);
        if (t_ns > mono_now) {
          t_ns = mono_now;
        }
      }
    }
    if (static_cast<std::size_t>(n) < sizeof raw) {
      ++stats_.wrong_length;
      if (malformed_limit_.allow(mono_now)) {
        reportf(diagnostics_, Severity::kWarning, kCanComponent,
                "short read of %zd bytes from '%s' (expected %zu): dropped", n,
                config_.interface.c_str(), sizeof raw);
      }
      continue;
    }
    ++stats_.frames;
    can_map::Frame frame;
    frame.length = raw.len;
    std::memcpy(frame.data.data(), raw.data, sizeof raw.data);
    if ((raw.can_id & CAN_ERR_FLAG) != 0) {
      frame.id = raw.can_id & CAN_ERR_MASK;
      handle_error_frame(raw.can_id, frame, t_ns);
      continue;
    }
    frame.id = raw.can_id & ((raw.can_id & CAN_EFF_FLAG) != 0 ? CAN_EFF_MASK : CAN_SFF_MASK);
    if ((raw.can_id & (CAN_EFF_FLAG | CAN_RTR_FLAG)) != 0) {
      frame.id = 0xFFFFFFFFU;  // never one of ours
    }
    if (handle_frame(frame, t_ns, out)) {
      return true;
    }
  }
  return false;
}

bool CanBaseBoard::sequence_ok(can_map::SequenceTracker& tracker, std::uint8_t seq,
                               const char* what, std::uint64_t& dropped, hal::TimeNs now) {
  using Result = can_map::SequenceTracker::Result;
  switch (tracker.observe(seq)) {
    case Result::kFirst:
    case Result::kInOrder:
      return true;
    case Result::kGap:
      dropped += tracker.last_gap();
      if (gap_limit_.allow(now)) {
        reportf(diagnostics_, Severity::kWarning, kCanComponent,
                "%u %s frame(s) missing before sequence %u (%llu missing so far)",
                tracker.last_gap(), what, static_cast<unsigned>(seq),
                static_cast<unsigned long long>(dropped));
      }
      return true;
    case Result::kDuplicate:
      ++stats_.duplicates;
      if (gap_limit_.allow(now)) {
        reportf(diagnostics_, Severity::kWarning, kCanComponent,
                "%s frame with repeated sequence %u: dropped", what, static_cast<unsigned>(seq));
      }
      return false;
    case Result::kOutOfOrder:
      ++stats_.out_of_order;
      if (gap_limit_.allow(now)) {
        reportf(diagnostics_, Severity::kWarning, kCanComponent,
                "%s sequence jumped back to %u (board reset or reordering): resynchronized", what,
                static_cast<unsigned>(seq));
      }
      return true;
  }
  return false;
}

bool CanBaseBoard::handle_frame(const can_map::Frame& frame, hal::TimeNs t_ns,
                                hal::SensorEvent& out) {
  const bool ours = frame.id == can_map::kEncoderId || frame.id == can_map::kGyroId;
  if (!ours) {
    ++stats_.unknown_id;
    if (malformed_limit_.allow(t_ns)) {
      reportf(diagnostics_, Severity::kWarning, kCanComponent,
              "frame with unknown id 0x%X on '%s' (expected 0x%X or 0x%X): dropped", frame.id,
              config_.interface.c_str(), can_map::kEncoderId, can_map::kGyroId);
    }
    return false;
  }
  if (frame.length != can_map::kFrameLength) {
    ++stats_.wrong_length;
    if (malformed_limit_.allow(t_ns)) {
      reportf(diagnostics_, Severity::kWarning, kCanComponent,
              "frame 0x%X has %u data bytes, expected %u: dropped", frame.id,
              static_cast<unsigned>(frame.length), static_cast<unsigned>(can_map::kFrameLength));
    }
    return false;
  }
  if (bus_off_) {
    note_recovered(t_ns, "frames arrive again");
  }
  if (frame.id == can_map::kEncoderId) {
    can_map::EncoderMessage m;
    if (!decode(frame, m)) {
      return false;
    }
    ++stats_.encoder_frames;
    if (!sequence_ok(encoder_seq_, m.seq, "encoder", stats_.encoder_dropped, t_ns)) {
      return false;
    }
    out = hal::SensorEvent{};
    out.kind = hal::SensorEvent::Kind::kEncoder;
    out.encoder.t_ns = t_ns;
    out.encoder.left_ticks = left_.extend(m.left_ticks24);
    out.encoder.right_ticks = right_.extend(m.right_ticks24);
    out.encoder.seq = encoder_seq_.extended();
    return true;
  }
  can_map::GyroMessage m;
  if (!decode(frame, m)) {
    return false;
  }
  ++stats_.gyro_frames;
  if (!sequence_ok(gyro_seq_, m.seq, "gyro", stats_.gyro_dropped, t_ns)) {
    return false;
  }
  stats_.gyro_temperature_c = m.temperature_c();
  if ((m.status & can_map::kGyroSaturated) != 0) {
    ++stats_.gyro_saturated;
  }
  hal::TimeNs sample_ns = t_ns;
  if (time_reference_ != nullptr && !time_reference_->sample_time(t_ns, sample_ns)) {
    sample_ns = t_ns;
  }
  out = hal::SensorEvent{};
  out.kind = hal::SensorEvent::Kind::kGyro;
  out.gyro.t_ns = sample_ns;
  out.gyro.wz_rad_s = m.rate_rad_s();
  out.gyro.seq = gyro_seq_.extended();
  return true;
}

void CanBaseBoard::note_recovered(hal::TimeNs t_ns, const char* how) {
  bus_off_ = false;
  ++stats_.bus_off_recovered;
  encoder_seq_.reset();
  gyro_seq_.reset();
  reportf(diagnostics_, Severity::kInfo, kCanComponent,
          "'%s' recovered from bus-off after %.3f s (%s)", config_.interface.c_str(),
          hal::to_seconds(t_ns - bus_off_since_ns_), how);
}

void CanBaseBoard::handle_error_frame(std::uint32_t can_id, const can_map::Frame& frame,
                                      hal::TimeNs t_ns) {
  ++stats_.error_frames;
  if ((can_id & CAN_ERR_BUSOFF) != 0) {
    ++stats_.bus_off;
    if (!bus_off_) {
      bus_off_ = true;
      bus_off_since_ns_ = t_ns;
      reportf(diagnostics_, Severity::kError, kCanComponent,
              "'%s' is bus-off: no odometry until the controller restarts (configure "
              "'ip link set %s type can restart-ms 100')",
              config_.interface.c_str(), config_.interface.c_str());
    }
    return;
  }
  if ((can_id & CAN_ERR_RESTARTED) != 0) {
    if (bus_off_) {
      note_recovered(t_ns, "controller restarted");
    }
    return;
  }
  if ((can_id & CAN_ERR_CRTL) != 0) {
    ++stats_.controller_errors;
  }
  if (error_limit_.allow(t_ns)) {
    reportf(diagnostics_, Severity::kWarning, kCanComponent,
            "error frame on '%s': class 0x%X, controller 0x%02X, protocol 0x%02X/0x%02X "
            "(%llu error frames so far)",
            config_.interface.c_str(), static_cast<unsigned>(can_id & CAN_ERR_MASK),
            static_cast<unsigned>(frame.data[1]), static_cast<unsigned>(frame.data[2]),
            static_cast<unsigned>(frame.data[3]),
            static_cast<unsigned long long>(stats_.error_frames));
  }
}

}  // namespace cleanslam::drivers
