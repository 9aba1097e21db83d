#include <cstddef>
#include <cstdlib>
#include <new>

#include <malloc.h>

#include <gtest/gtest.h>
#include <Eigen/Core>

#include "allocation_counter.hpp"

// The allocation tests are only as good as their counter: these check that it sees what the
// estimator's tests must not do.
namespace {

volatile std::size_t g_size = 64;  // volatile: the compiler may not elide an allocation of it
volatile double g_sink = 0.0;

TEST(AllocationCounter, CountsOperatorNew) {
  const cleanslam::test::AllocationScope scope;
  void* p = ::operator new(g_size);
  const std::size_t n = scope.count();
  ::operator delete(p);
  EXPECT_EQ(n, 1U);
}

TEST(AllocationCounter, CountsNothingWithoutAllocation) {
  Eigen::Matrix<double, 8, 8> m;
  const cleanslam::test::AllocationScope scope;
  m.setConstant(static_cast<double>(g_size));
  g_sink = (m * m).sum();
  EXPECT_EQ(scope.count(), 0U);
}

#if defined(__SANITIZE_ADDRESS__)
// Here the counter sees only operator new; Eigen's heap use is caught by its assertion.
TEST(AllocationCounterDeathTest, EigenCheckStopsAHeapMatrix) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_DEATH(
      {
        Eigen::internal::set_is_malloc_allowed(false);
        Eigen::MatrixXd m(static_cast<Eigen::Index>(g_size), 4);
        m.setConstant(1.0);
        g_sink = m.sum();
      },
      "heap allocation is forbidden");
}
#else
// The C allocator's count sees Eigen's heap use, also where NDEBUG compiles Eigen's check out.
TEST(AllocationCounter, CountsAnEigenHeapMatrix) {
  const cleanslam::test::AllocationScope scope;
  {
    Eigen::MatrixXd m(static_cast<Eigen::Index>(g_size), 4);
    if (m.data() != nullptr) {  // armhf GCC's -Wnull-dereference otherwise flags the sum
      m.setConstant(1.0);
      g_sink = m.sum();
    }
  }
  EXPECT_EQ(scope.count(), 1U);
}

TEST(AllocationCounter, CountsMallocCallocReallocAndAligned) {
  void* (*volatile allocate)(std::size_t) = std::malloc;
  const cleanslam::test::AllocationScope scope;
  void* a = allocate(g_size);
  void* b = std::calloc(g_size, 2);
  void* c = std::realloc(a, 2 * g_size);
  void* d = std::aligned_alloc(64, 2 * g_size);
  void* e = nullptr;
  const int rc = posix_memalign(&e, 64, g_size);
  void* f = valloc(g_size);
  void* g = pvalloc(g_size);
  const std::size_t n = scope.count();
  std::free(b);
  std::free(c);
  std::free(d);
  std::free(e);
  std::free(f);
  std::free(g);
  EXPECT_EQ(rc, 0);
  EXPECT_EQ(n, 7U);
}
#endif

}  // namespace
