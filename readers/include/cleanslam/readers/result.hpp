#pragma once

#include <string>
#include <utility>
#include <variant>

namespace cleanslam::readers {

// A value or an error message (which names the file, line and key at fault). Nothing in readers
// throws to its callers; fallible functions return a Result.
template <typename T>
class Result {
 public:
  Result(T value) : v_(std::in_place_index<0>, std::move(value)) {}  // NOLINT implicit
  static Result failure(std::string message) {
    return Result(std::in_place_index<1>, std::move(message));
  }

  [[nodiscard]] bool ok() const { return v_.index() == 0; }
  explicit operator bool() const { return ok(); }
  [[nodiscard]] const T& value() const& { return std::get<0>(v_); }
  [[nodiscard]] T& value() & { return std::get<0>(v_); }
  [[nodiscard]] T&& value() && { return std::get<0>(std::move(v_)); }
  [[nodiscard]] const std::string& error() const { return std::get<1>(v_); }
  const T& operator*() const& { return value(); }
  T& operator*() & { return value(); }
  const T* operator->() const { return &value(); }
  T* operator->() { return &value(); }

 private:
  template <std::size_t I>
  Result(std::in_place_index_t<I> tag, std::string message) : v_(tag, std::move(message)) {}
  std::variant<T, std::string> v_;
};

// Result of an operation without a value.
class Status {
 public:
  Status() = default;
  static Status failure(std::string message) {
    Status s;
    s.ok_ = false;
    s.error_ = std::move(message);
    return s;
  }
  [[nodiscard]] bool ok() const { return ok_; }
  explicit operator bool() const { return ok_; }
  [[nodiscard]] const std::string& error() const { return error_; }

 private:
  bool ok_ = true;
  std::string error_;
};

}  // namespace cleanslam::readers
