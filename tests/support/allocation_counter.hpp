#pragma once

#include <cstddef>

// Counts global operator new calls made while a scope is armed. Link cleanslam_test_alloc into a
// test binary to replace the global allocation functions; pair it with Eigen's run-time malloc
// check (Eigen::internal::set_is_malloc_allowed(false)), which catches Eigen's own allocations.
namespace cleanslam::test {

std::size_t allocations_so_far();

class AllocationScope {
 public:
  AllocationScope();
  ~AllocationScope();
  AllocationScope(const AllocationScope&) = delete;
  AllocationScope& operator=(const AllocationScope&) = delete;
  // operator new calls since construction.
  [[nodiscard]] std::size_t count() const;

 private:
  std::size_t start_;
};

}  // namespace cleanslam::test
