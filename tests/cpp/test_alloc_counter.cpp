// The counting heap allocator of the test executable (see alloc_counter.hpp), and its
// self-tests: the counter sees every kind of heap allocation, and the check every
// real-time test makes (`EXPECT_EQ(guard.allocations(), 0u)`) fails when a section allocates.
#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>
#include <malloc.h>

#include <Eigen/Core>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include "../../cpp/src/rt_guard.hpp"
#include "alloc_counter.hpp"

// glibc's own allocator, which the replacements below forward to (exported by libc.so.6).
extern "C" {
void* __libc_malloc(std::size_t size);
void* __libc_calloc(std::size_t n, std::size_t size);
void* __libc_realloc(void* p, std::size_t size);
void __libc_free(void* p);
void* __libc_memalign(std::size_t alignment, std::size_t size);
void* __libc_valloc(std::size_t size);
void* __libc_pvalloc(std::size_t size);
}

namespace test_alloc_counter {
// Constant-initialized: valid before any constructor runs (the loader allocates early).
std::atomic<std::size_t> g_allocations{0};

inline void count() noexcept { g_allocations.fetch_add(1, std::memory_order_relaxed); }
}  // namespace test_alloc_counter

// The C allocator of the whole executable: the executable's definitions interpose on libc's,
// so libstdc++'s operator new, Eigen and every library call land here.
extern "C" {
void* malloc(std::size_t size) noexcept {
  test_alloc_counter::count();
  return __libc_malloc(size);
}
void* calloc(std::size_t n, std::size_t size) noexcept {
  test_alloc_counter::count();
  return __libc_calloc(n, size);
}
void* realloc(void* p, std::size_t size) noexcept {
  test_alloc_counter::count();
  return __libc_realloc(p, size);
}
void* reallocarray(void* p, std::size_t n, std::size_t size) noexcept {
  test_alloc_counter::count();
  if (size != 0 && n > SIZE_MAX / size) {
    errno = ENOMEM;
    return nullptr;
  }
  return __libc_realloc(p, n * size);
}
void free(void* p) noexcept { __libc_free(p); }
void* memalign(std::size_t alignment, std::size_t size) noexcept {
  test_alloc_counter::count();
  return __libc_memalign(alignment, size);
}
void* aligned_alloc(std::size_t alignment, std::size_t size) noexcept {
  test_alloc_counter::count();
  return __libc_memalign(alignment, size);
}
int posix_memalign(void** out, std::size_t alignment, std::size_t size) noexcept {
  test_alloc_counter::count();
  if (alignment % sizeof(void*) != 0 || (alignment & (alignment - 1)) != 0 || alignment == 0)
    return EINVAL;
  void* p = __libc_memalign(alignment, size);
  if (p == nullptr) return ENOMEM;
  *out = p;
  return 0;
}
void* valloc(std::size_t size) noexcept {
  test_alloc_counter::count();
  return __libc_valloc(size);
}
void* pvalloc(std::size_t size) noexcept {
  test_alloc_counter::count();
  return __libc_pvalloc(size);
}
}  // extern "C"

namespace a2l::test {
std::size_t allocation_count() noexcept {
  return test_alloc_counter::g_allocations.load(std::memory_order_relaxed);
}
}  // namespace a2l::test

namespace test_alloc_counter {

using a2l::test::AllocationGuard;

// Keeps the compiler from removing an allocation whose result is unused.
void escape(const void* p) { asm volatile("" : : "g"(p) : "memory"); }

// One allocation of each kind, released again.
struct Kind {
  const char* name;
  void (*allocate)();
};

const Kind kKinds[] = {
    {"malloc",
     [] {
       void* p = std::malloc(24);
       escape(p);
       std::free(p);
     }},
    {"calloc",
     [] {
       void* p = std::calloc(3, 8);
       escape(p);
       std::free(p);
     }},
    {"realloc",
     [] {
       void* p = std::realloc(nullptr, 40);
       escape(p);
       std::free(p);
     }},
    {"reallocarray",
     [] {
       void* p = reallocarray(nullptr, 5, 8);
       escape(p);
       std::free(p);
     }},
    {"posix_memalign",
     [] {
       void* p = nullptr;
       if (posix_memalign(&p, 64, 128) == 0) escape(p);
       std::free(p);
     }},
    {"aligned_alloc",
     [] {
       void* p = std::aligned_alloc(64, 128);
       escape(p);
       std::free(p);
     }},
    {"memalign",
     [] {
       void* p = memalign(32, 64);
       escape(p);
       std::free(p);
     }},
    {"operator new",
     [] {
       auto* p = new double(1.0);
       escape(p);
       delete p;
     }},
    {"operator new[]",
     [] {
       auto* p = new double[9];
       escape(p);
       delete[] p;
     }},
    {"nothrow operator new",
     [] {
       auto* p = new (std::nothrow) double(2.0);
       escape(p);
       delete p;
     }},
    {"aligned operator new",
     [] {
       struct alignas(64) Block {
         double x[8];
       };
       auto* p = new Block();
       escape(p);
       delete p;
     }},
    {"std::vector",
     [] {
       std::vector<int> v(100);
       escape(v.data());
     }},
    {"std::string",
     [] {
       std::string s(100, 'x');
       escape(s.data());
     }},
    {"std::make_shared",
     [] {
       auto p = std::make_shared<int>(3);
       escape(p.get());
     }},
    {"Eigen::VectorXd",
     [] {
       Eigen::VectorXd v(64);
       escape(v.data());
     }},
    {"Eigen::MatrixXd product",
     [] {
       const Eigen::MatrixXd a = Eigen::MatrixXd::Ones(6, 7);
       Eigen::MatrixXd b(7, 7);
       b.noalias() = a.transpose() * a;  // a's allocation, b's: two
       escape(b.data());
     }},
};

// The check every real-time test makes.
void expect_no_allocation(void (*section)()) {
  AllocationGuard guard;
  section();
  EXPECT_EQ(guard.allocations(), 0u) << "the section allocated";
}

class AllocationCounter : public ::testing::TestWithParam<Kind> {};

TEST_P(AllocationCounter, SeesThisKindOfAllocation) {
  const Kind& kind = GetParam();
  AllocationGuard guard;
  kind.allocate();
  const std::size_t n = guard.allocations();
  const std::string name = kind.name;
  if (name == "Eigen::MatrixXd product") {
    EXPECT_EQ(n, 2u) << kind.name;
  } else {
    EXPECT_EQ(n, 1u) << kind.name;  // seen, and seen once (operator new goes through malloc)
  }
}

// The acceptance check: a section that allocates, here through each kind, fails the
// no-allocation assertion. Expected failures, caught by gtest-spi.
TEST_P(AllocationCounter, NoAllocCheckFailsWhenTheSectionAllocates) {
  static void (*section)() = nullptr;
  section = GetParam().allocate;
  EXPECT_NONFATAL_FAILURE(expect_no_allocation(section), "the section allocated");
}

INSTANTIATE_TEST_SUITE_P(EveryKind, AllocationCounter, ::testing::ValuesIn(kKinds),
                         [](const ::testing::TestParamInfo<Kind>& info) {
                           std::string s;
                           for (const char c : std::string(info.param.name))
                             s += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
                           return s;
                         });

TEST(AllocationCounterBaseline, ArithmeticAndFixedSizeEigenAllocateNothing) {
  AllocationGuard guard;
  Eigen::Matrix<double, 6, 7> j = Eigen::Matrix<double, 6, 7>::Random();
  Eigen::Matrix<double, 7, 7> jtj;
  jtj.noalias() = j.transpose() * j;
  escape(jtj.data());
  EXPECT_EQ(guard.allocations(), 0u);
}

#if defined(A2L_MALLOC_GUARD)
// The guarded build (make test): Eigen's own guard is on inside a real-time section and
// aborts on the first heap allocation there.
TEST(AllocationCounterEigenGuard, AbortsOnAHeapAllocationInARealTimeSection) {
#ifdef NDEBUG
  FAIL() << "A2L_MALLOC_GUARD needs assertions (NDEBUG must not be defined)";
#endif
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_DEATH(
      {
        const a2l::detail::RealTimeSection rt;
        Eigen::VectorXd v(64);
        escape(v.data());
      },
      "heap allocation is forbidden");
  // Outside a section Eigen may allocate.
  Eigen::VectorXd ok(64);
  escape(ok.data());
}
#endif

}  // namespace test_alloc_counter
