#include "cleanslam/drivers/can_pose_sink.hpp"

#include <linux/can.h>
#include <linux/can/raw.h>

#include <cerrno>
#include <cstring>
#include <utility>

#include "cleanslam/drivers/can_messages.hpp"

namespace cleanslam::drivers {
namespace {
constexpr std::string_view kPoseSinkComponent = "can-pose";
}

CanPoseSink::CanPoseSink(std::string interface, Os& os, Diagnostics& diagnostics)
    : interface_(std::move(interface)), os_(os), diagnostics_(diagnostics) {
  open_socket();
}

CanPoseSink::~CanPoseSink() {
  if (socket_ >= 0) {
    os_.close(socket_);
  }
}

bool CanPoseSink::open_socket() {
  const unsigned int index = os_.if_nametoindex(interface_.c_str());
  const int s = index == 0 ? -1 : os_.socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK, CAN_RAW);
  sockaddr_can address{};
  address.can_family = AF_CAN;
  address.can_ifindex = static_cast<int>(index);
  // Send only: receive nothing.
  const bool ok = s >= 0 && os_.setsockopt(s, SOL_CAN_RAW, CAN_RAW_FILTER, nullptr, 0) == 0 &&
                  os_.bind(s, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0;
  if (!ok) {
    ++stats_.open_failures;
    reportf(diagnostics_, Severity::kError, kPoseSinkComponent,
            "cannot open interface '%s' for pose frames (%s): poses are not sent on CAN",
            interface_.c_str(), std::strerror(errno));
    if (s >= 0) {
      os_.close(s);
    }
    retry_at_ns_ = os_.monotonic_now() + backoff_.next();
    return false;
  }
  socket_ = s;
  backoff_.reset();
  return true;
}

bool CanPoseSink::send(std::uint32_t id, const std::uint8_t* data) {
  can_frame frame{};
  frame.can_id = id;
  frame.len = can_map::kFrameLength;
  std::memcpy(frame.data, data, can_map::kFrameLength);
  const ssize_t n = os_.write(socket_, &frame, sizeof frame);
  if (n == static_cast<ssize_t>(sizeof frame)) {
    ++stats_.frames_sent;
    return true;
  }
  ++stats_.frames_dropped;
  const int error = errno;
  if (drop_limit_.allow(os_.monotonic_now())) {
    reportf(diagnostics_, Severity::kWarning, kPoseSinkComponent,
            "pose frame 0x%X not sent on '%s' (%s); %llu dropped so far", id, interface_.c_str(),
            n < 0 ? std::strerror(error) : "short write",
            static_cast<unsigned long long>(stats_.frames_dropped));
  }
  if (n < 0 && (error == ENODEV || error == ENXIO || error == EBADF)) {
    os_.close(socket_);
    socket_ = -1;
    retry_at_ns_ = os_.monotonic_now() + backoff_.next();
  }
  return false;
}

void CanPoseSink::publish(const hal::PoseEstimate& pose) {
  ++stats_.published;
  if (socket_ < 0 && (os_.monotonic_now() < retry_at_ns_ || !open_socket())) {
    stats_.frames_dropped += 2;
    return;
  }
  const can_map::PoseMessages m = can_map::encode_pose(pose, seq_++);
  if (send(m.position.id, m.position.data.data()) && socket_ >= 0) {
    send(m.yaw_quality.id, m.yaw_quality.data.data());
  } else {
    ++stats_.frames_dropped;
  }
}

}  // namespace cleanslam::drivers
