// Real-kernel check of the SocketCAN driver on vcan0: a recording played at its own pace arrives
// decoded, in order, with the right values and kernel time stamps; malformed frames, sequence
// gaps and bus-off are counted; pose frames go out; a vanished interface is reopened.
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cleanslam/drivers/can_base_board.hpp"
#include "cleanslam/drivers/can_messages.hpp"
#include "cleanslam/drivers/can_pose_sink.hpp"
#include "kernel_check.hpp"

namespace {

using cleanslam::hal::SensorEvent;
using cleanslam::hal::TimeNs;
using cleanslam::kernel_test::Check;
namespace drivers = cleanslam::drivers;

struct Recorded {
  double t_s = 0.0;
  can_frame frame{};
};

struct Expected {
  std::string kind;
  long long a = 0;
  long long b = 0;
};

std::vector<Recorded> load_recording(const std::string& path) {
  std::vector<Recorded> out;
  std::ifstream in(path);
  std::string line;
  double t_first = -1.0;
  while (std::getline(in, line)) {
    double t = 0.0;
    char iface[32];
    char body[64];
    if (std::sscanf(line.c_str(), "(%lf) %31s %63s", &t, iface, body) != 3) {
      continue;
    }
    std::string b(body);
    const auto hash = b.find('#');
    if (hash == std::string::npos) {
      continue;
    }
    Recorded r;
    const std::string id = b.substr(0, hash);
    r.frame.can_id = static_cast<canid_t>(std::stoul(id, nullptr, 16));
    if (id.size() == 8 && (r.frame.can_id & CAN_ERR_FLAG) == 0) {
      r.frame.can_id |= CAN_EFF_FLAG;
    }
    const std::string data = b.substr(hash + 1);
    r.frame.len = static_cast<__u8>(data.size() / 2);
    for (std::size_t i = 0; i < r.frame.len && i < 8; ++i) {
      r.frame.data[i] = static_cast<__u8>(std::stoul(data.substr(2 * i, 2), nullptr, 16));
    }
    if (t_first < 0) {
      t_first = t;
    }
    r.t_s = t - t_first;
    out.push_back(r);
  }
  return out;
}

std::vector<Expected> load_expected(const std::string& path) {
  std::vector<Expected> out;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') {
      continue;
    }
    std::stringstream ss(line);
    Expected e;
    std::string a, b;
    std::getline(ss, e.kind, ',');
    std::getline(ss, a, ',');
    std::getline(ss, b, ',');
    e.a = std::stoll(a);
    e.b = std::stoll(b);
    out.push_back(e);
  }
  return out;
}

int raw_socket(const char* interface) {
  const int s = ::socket(PF_CAN, SOCK_RAW, CAN_RAW);
  sockaddr_can address{};
  address.can_family = AF_CAN;
  address.can_ifindex = static_cast<int>(::if_nametoindex(interface));
  if (s < 0 || ::bind(s, reinterpret_cast<sockaddr*>(&address), sizeof address) < 0) {
    std::perror("raw socket");
    return -1;
  }
  return s;
}

TimeNs now_ns() {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<TimeNs>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

void play(const std::vector<Recorded>& recording, TimeNs start_ns, int* sent) {
  const int s = raw_socket("vcan0");
  for (const Recorded& r : recording) {
    const TimeNs due = start_ns + static_cast<TimeNs>(r.t_s * 1e9);
    timespec ts{static_cast<time_t>(due / 1'000'000'000), static_cast<long>(due % 1'000'000'000)};
    ::clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr);
    if (::write(s, &r.frame, sizeof r.frame) == static_cast<ssize_t>(sizeof r.frame)) {
      ++*sent;
    }
  }
  ::close(s);
}

// Runs the loop's way: poll() on fd(), then non-blocking read() until it says no.
std::vector<SensorEvent> collect(drivers::CanBaseBoard& board, TimeNs until_ns) {
  std::vector<SensorEvent> events;
  while (now_ns() < until_ns) {
    pollfd p{board.fd(), POLLIN, 0};
    ::poll(&p, 1, 20);
    SensorEvent e;
    while (board.read(e)) {
      events.push_back(e);
    }
  }
  return events;
}

bool check_recording(const std::string& files) {
  Check check("can_decode");
  const auto recording = load_recording(files + "/base_board.log");
  const auto expected = load_expected(files + "/base_board_expected.csv");
  check.expect(recording.size() > 100 && expected.size() > 100,
               "recording %zu frames, expected %zu", recording.size(), expected.size());

  drivers::CanBaseBoardConfig config;
  config.interface = "vcan0";
  drivers::CanBaseBoard board(config);
  check.expect(board.connected(), "board not connected to vcan0");

  int sent = 0;
  const TimeNs start = now_ns() + 50'000'000;
  std::thread player(play, std::cref(recording), start, &sent);
  const auto events =
      collect(board, start + static_cast<TimeNs>(recording.back().t_s * 1e9) + 300'000'000);
  player.join();
  check.note("played %d frames in %.2f s, received %zu events", sent, recording.back().t_s,
             events.size());
  check.expect(sent == static_cast<int>(recording.size()), "only %d of %zu frames sent", sent,
               recording.size());
  check.expect(events.size() == expected.size(), "%zu events, expected %zu", events.size(),
               expected.size());

  std::size_t mismatches = 0;
  TimeNs last_t = 0;
  std::uint32_t last_gyro_seq = 0, last_encoder_seq = 0;
  bool first_gyro = true, first_encoder = true;
  for (std::size_t i = 0; i < std::min(events.size(), expected.size()); ++i) {
    const SensorEvent& e = events[i];
    const Expected& x = expected[i];
    bool ok = true;
    if (x.kind == "gyro") {
      ok = e.kind == SensorEvent::Kind::kGyro && std::lround(e.gyro.wz_rad_s * 1e6) == x.a &&
           (first_gyro || e.gyro.seq > last_gyro_seq);
      last_gyro_seq = e.gyro.seq;
      first_gyro = false;
    } else {
      ok = e.kind == SensorEvent::Kind::kEncoder && e.encoder.left_ticks == x.a &&
           e.encoder.right_ticks == x.b && (first_encoder || e.encoder.seq > last_encoder_seq);
      last_encoder_seq = e.encoder.seq;
      first_encoder = false;
    }
    const TimeNs t = e.kind == SensorEvent::Kind::kGyro ? e.gyro.t_ns : e.encoder.t_ns;
    ok = ok && t >= last_t && t >= start && t <= now_ns();
    last_t = t;
    if (!ok && ++mismatches <= 5) {
      check.expect(false, "event %zu: kind %d, expected %s %lld %lld", i, static_cast<int>(e.kind),
                   x.kind.c_str(), x.a, x.b);
    }
  }
  check.expect(mismatches == 0, "%zu events differ from the recording", mismatches);

  // Kernel time stamps follow the recording's pacing: the span of the stamps matches.
  if (events.size() >= 2) {
    const TimeNs t_first = events.front().kind == SensorEvent::Kind::kGyro
                               ? events.front().gyro.t_ns
                               : events.front().encoder.t_ns;
    const TimeNs t_last = events.back().kind == SensorEvent::Kind::kGyro
                              ? events.back().gyro.t_ns
                              : events.back().encoder.t_ns;
    const double span = static_cast<double>(t_last - t_first) * 1e-9;
    check.note("time-stamp span %.3f s (recording %.3f s)", span, recording.back().t_s);
    check.expect(std::fabs(span - 0.99) < 0.1, "time-stamp span %.3f s, recording 0.99 s", span);
  }

  const auto& s = board.stats();
  check.note(
      "stats: gyro %llu encoder %llu wrong_length %llu unknown %llu gyro_dropped %llu "
      "bus_off %llu recovered %llu error_frames %llu",
      static_cast<unsigned long long>(s.gyro_frames),
      static_cast<unsigned long long>(s.encoder_frames),
      static_cast<unsigned long long>(s.wrong_length),
      static_cast<unsigned long long>(s.unknown_id),
      static_cast<unsigned long long>(s.gyro_dropped), static_cast<unsigned long long>(s.bus_off),
      static_cast<unsigned long long>(s.bus_off_recovered),
      static_cast<unsigned long long>(s.error_frames));
  check.expect(s.wrong_length == 1, "wrong_length %llu, expected 1",
               static_cast<unsigned long long>(s.wrong_length));
  check.expect(s.unknown_id == 0, "the kernel filter let %llu unknown frames through",
               static_cast<unsigned long long>(s.unknown_id));
  check.expect(s.gyro_dropped == 2, "gyro_dropped %llu, expected 2",
               static_cast<unsigned long long>(s.gyro_dropped));
  check.expect(s.bus_off == 1 && s.bus_off_recovered == 1 && !board.bus_off(),
               "bus-off %llu, recovered %llu", static_cast<unsigned long long>(s.bus_off),
               static_cast<unsigned long long>(s.bus_off_recovered));
  check.expect(s.encoder_dropped == 0, "encoder_dropped %llu",
               static_cast<unsigned long long>(s.encoder_dropped));
  return check.finish() == 0;
}

bool check_pose_sink() {
  Check check("can_pose");
  const int listener = raw_socket("vcan0");
  drivers::CanPoseSink sink("vcan0");
  cleanslam::hal::PoseEstimate pose;
  pose.position_m = {1.5, -2.25, 0.0};
  pose.orientation_wxyz = {std::cos(0.3), 0.0, 0.0, std::sin(0.3)};  // yaw 0.6
  pose.covariance[0] = 0.0004;
  pose.covariance[35] = 0.0001;
  sink.publish(pose);
  can_frame f[2]{};
  for (auto& frame : f) {
    pollfd p{listener, POLLIN, 0};
    if (::poll(&p, 1, 500) <= 0 || ::read(listener, &frame, sizeof frame) != sizeof frame) {
      check.expect(false, "pose frame not received");
    }
  }
  const auto x =
      static_cast<std::int32_t>((f[0].data[0] | (f[0].data[1] << 8) | (f[0].data[2] << 16)) << 8) >>
      8;
  const auto y =
      static_cast<std::int32_t>((f[0].data[3] | (f[0].data[4] << 8) | (f[0].data[5] << 16)) << 8) >>
      8;
  const auto yaw = static_cast<std::int16_t>(f[1].data[0] | (f[1].data[1] << 8));
  check.expect(f[0].can_id == 0x201 && f[1].can_id == 0x202, "ids 0x%X 0x%X", f[0].can_id,
               f[1].can_id);
  check.expect(x == 15000 && y == -22500, "position %d %d (1e-4 m)", x, y);
  check.expect(yaw == 6000, "yaw %d (1e-4 rad)", yaw);
  check.expect((f[1].data[2] | (f[1].data[3] << 8)) == 200, "sigma_xy %d",
               f[1].data[2] | (f[1].data[3] << 8));
  ::close(listener);
  return check.finish() == 0;
}

bool check_reopen() {
  Check check("can_reopen");
  drivers::CanBaseBoardConfig config;
  config.interface = "vcan0";
  config.reopen_min_ns = 50'000'000;
  drivers::CanBaseBoard board(config);
  const int fd_before = board.fd();
  std::system("ip link del vcan0");
  collect(board, now_ns() + 200'000'000);
  check.expect(!board.connected(), "still connected after vcan0 was deleted");
  std::system("ip link add dev vcan0 type vcan && ip link set vcan0 up");
  collect(board, now_ns() + 1'000'000'000);
  check.expect(board.connected(), "not reconnected within 1 s of vcan0 coming back");
  check.expect(board.fd() == fd_before, "fd() changed across the reopen");
  int sent = 0;
  std::vector<Recorded> one(1);
  one[0].frame.can_id = 0x102;
  one[0].frame.len = 8;
  one[0].frame.data[6] = 1;
  std::thread player(play, std::cref(one), now_ns() + 20'000'000, &sent);
  const auto events = collect(board, now_ns() + 200'000'000);
  player.join();
  check.expect(events.size() == 1, "%zu events after the reopen, expected 1", events.size());
  check.note("opens %llu, receive errors %llu",
             static_cast<unsigned long long>(board.stats().opens),
             static_cast<unsigned long long>(board.stats().receive_errors));
  return check.finish() == 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string files = argc > 1 ? argv[1] : "/files";
  bool ok = check_recording(files);
  ok = check_pose_sink() && ok;
  ok = check_reopen() && ok;
  return ok ? 0 : 1;
}
