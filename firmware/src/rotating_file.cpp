#include "cleanslam/firmware/rotating_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdarg>
#include <cstring>

namespace cleanslam::firmware {

std::vector<std::string> rotation_names(const std::string& path, int files) {
  std::vector<std::string> names{path};
  for (int i = 1; i < files; ++i) {
    names.push_back(path + "." + std::to_string(i));
  }
  return names;
}

void shift_rotation_names(const std::vector<std::string>& names) {
  if (names.size() < 2) {
    return;
  }
  ::unlink(names.back().c_str());
  for (std::size_t i = names.size() - 1; i > 0; --i) {
    ::rename(names[i - 1].c_str(), names[i].c_str());
  }
}

RotatingFile::~RotatingFile() {
  (void)close();
}

bool RotatingFile::open(const std::string& path, Rotation rotation, std::string& error) {
  (void)close();
  rotation_ = rotation;
  if (rotation_.max_files < 1) {
    rotation_.max_files = 1;
  }
  names_ = rotation_names(path, rotation_.max_files);
  bytes_ = 0;
  rotations_ = 0;
  errno_ = 0;
  file_ = std::fopen(path.c_str(), "w");
  if (file_ == nullptr) {
    error = path + ": cannot create: " + std::strerror(errno);
    return false;
  }
  struct stat st {};
  rotatable_ = ::fstat(::fileno(file_), &st) == 0 && S_ISREG(st.st_mode);
  buffer_.assign(std::size_t{1} << 16, 0);
  std::setvbuf(file_, buffer_.data(), _IOFBF, buffer_.size());
  return true;
}

void RotatingFile::fail(int e) {
  if (errno_ == 0) {
    errno_ = e != 0 ? e : EIO;
  }
}

void RotatingFile::print(const char* format, ...) {
  if (file_ == nullptr) {
    return;
  }
  std::va_list args;
  va_start(args, format);
  const int n = std::vfprintf(file_, format, args);
  va_end(args);
  if (n < 0) {
    fail(errno);
    return;
  }
  bytes_ += static_cast<std::size_t>(n);
}

void RotatingFile::rotate(const char* header) {
  if (file_ == nullptr || !rotatable_) {
    return;
  }
  if (std::fflush(file_) != 0) {
    fail(errno);
  }
  shift_rotation_names(names_);
  // A new file under the same FILE and buffer: nothing is allocated.
  const int fd = ::open(names_[0].c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0 || ::dup2(fd, ::fileno(file_)) < 0) {
    fail(errno);
  }
  if (fd >= 0) {
    ::close(fd);
  }
  bytes_ = 0;
  ++rotations_;
  if (header != nullptr) {
    print("%s", header);
  }
}

void RotatingFile::flush() {
  if (file_ != nullptr && std::fflush(file_) != 0) {
    fail(errno);
  }
}

bool RotatingFile::close() {
  if (file_ != nullptr) {
    if (std::fflush(file_) != 0) {
      fail(errno);
    }
    if (std::ferror(file_) != 0) {
      fail(EIO);
    }
    if (std::fclose(file_) != 0) {
      fail(errno);
    }
    file_ = nullptr;
  }
  return errno_ == 0;
}

std::string RotatingFile::error() const {
  if (errno_ == 0) {
    return {};
  }
  return path() + ": cannot write: " + std::strerror(errno_);
}

}  // namespace cleanslam::firmware
