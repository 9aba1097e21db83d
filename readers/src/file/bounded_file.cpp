#include "cleanslam/readers/bounded_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>

namespace cleanslam::readers {
namespace {

// A file descriptor closed on scope exit.
class Fd {
 public:
  explicit Fd(int fd) : fd_(fd) {}
  ~Fd() {
    if (fd_ >= 0) {
      ::close(fd_);
    }
  }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  [[nodiscard]] int get() const { return fd_; }

 private:
  int fd_;
};

std::string limit_text(FileLimit limit) {
  return "the " + std::to_string(limit.max_bytes) + " bytes " + limit.name + " allows for " +
         limit.why;
}

// Opens without blocking (a FIFO with no writer would) and checks type and size; the descriptor
// or an error message.
Result<int> open_checked(const std::string& path, FileLimit limit) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
  if (fd < 0) {
    return Result<int>::failure(path + ": cannot open: " + std::strerror(errno));
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    const int e = errno;
    ::close(fd);
    return Result<int>::failure(path + ": cannot stat: " + std::strerror(e));
  }
  if (!S_ISREG(st.st_mode)) {
    ::close(fd);
    return Result<int>::failure(path + ": is " + file_kind(st.st_mode) + ", not a regular file");
  }
  if (static_cast<std::uint64_t>(st.st_size) > limit.max_bytes) {
    ::close(fd);
    return Result<int>::failure(path + ": " + std::to_string(st.st_size) + " bytes, more than " +
                                limit_text(limit));
  }
  return fd;
}

}  // namespace

const char* file_kind(unsigned mode) {
  switch (mode & S_IFMT) {
    case S_IFREG:
      return "a regular file";
    case S_IFDIR:
      return "a directory";
    case S_IFIFO:
      return "a FIFO";
    case S_IFCHR:
      return "a character device";
    case S_IFBLK:
      return "a block device";
    case S_IFSOCK:
      return "a socket";
    case S_IFLNK:
      return "a symbolic link";
    default:
      return "not a file";
  }
}

Status check_bounded_file(const std::string& path, FileLimit limit) {
  auto fd = open_checked(path, limit);
  if (!fd.ok()) {
    return Status::failure(fd.error());
  }
  ::close(*fd);
  return Status();
}

namespace {

// Reads the whole file into a std::string or a byte vector.
template <typename Container>
Result<Container> read_whole(const std::string& path, FileLimit limit) {
  auto opened = open_checked(path, limit);
  if (!opened.ok()) {
    return Result<Container>::failure(opened.error());
  }
  const Fd fd(*opened);
  Container data;
  std::array<char, std::size_t{1} << 16> buf{};
  while (true) {
    const ssize_t n = ::read(fd.get(), buf.data(), buf.size());
    if (n < 0) {
      if (errno == EINTR) {
        continue;
      }
      return Result<Container>::failure(path + ": cannot read: " + std::strerror(errno));
    }
    if (n == 0) {
      break;
    }
    if (data.size() + static_cast<std::size_t>(n) > limit.max_bytes) {
      return Result<Container>::failure(path + ": grew while read beyond " + limit_text(limit));
    }
    data.insert(data.end(), buf.begin(), buf.begin() + n);
  }
  return data;
}

}  // namespace

Result<std::string> read_bounded_file(const std::string& path, FileLimit limit) {
  return read_whole<std::string>(path, limit);
}

Result<std::vector<std::uint8_t>> read_bounded_bytes(const std::string& path, FileLimit limit) {
  return read_whole<std::vector<std::uint8_t>>(path, limit);
}

}  // namespace cleanslam::readers
