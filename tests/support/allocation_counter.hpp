#pragma once

#include <cstddef>

// Counts heap allocations made while a scope is armed. Link cleanslam_test_alloc into a test binary
// to replace its allocation functions: the C allocator's (malloc, calloc, realloc, the aligned and
// page-aligned ones), which operator new and Eigen both use; under ASan, which owns malloc,
// operator new's only. Pair it with Eigen's run-time malloc check
// (Eigen::internal::set_is_malloc_allowed(false)), which catches Eigen's own allocations in the
// builds that keep assertions.
namespace cleanslam::test {

std::size_t allocations_so_far();

class AllocationScope {
 public:
  AllocationScope();
  AllocationScope(const AllocationScope&) = delete;
  AllocationScope& operator=(const AllocationScope&) = delete;
  // Allocations since construction.
  [[nodiscard]] std::size_t count() const;

 private:
  std::size_t start_;
};

}  // namespace cleanslam::test
