//! \file alloc_counter.hpp
//! \brief A counting heap allocator for the tests: every heap allocation made by the test
//! executable increments a counter, so a test proves that a section allocates nothing.
//!
//! test_alloc_counter.cpp replaces the C allocator of the whole a2l_tests executable
//! (`malloc`, `calloc`, `realloc`, `reallocarray`, `posix_memalign`, `aligned_alloc`,
//! `memalign`, `valloc`, `pvalloc`, forwarding to glibc's own `__libc_*` functions). The C++
//! `operator new` (every form) and Eigen's `aligned_malloc` allocate through these, so they
//! are counted too; the counter's self-tests prove it for each kind. It is defined once:
//! include this header and use AllocationGuard, never define another allocator.
//!
//! Convention: a test that proves a real-time function allocates nothing has `NoAlloc` in
//! its suite or test name (`StepNoAlloc`, `ExecutorNoAlloc`, ...). `make test` runs every
//! such test a second time in a build with Eigen's allocation guard on (`A2L_MALLOC_GUARD`,
//! assertions enabled): `ctest -R 'NoAlloc|AllocationCounter'` in `build/cpp-guard`.
//! tests/python/test_rt_test_convention.py fails if a test uses AllocationGuard without
//! that name.
#pragma once

#include <cstddef>

namespace a2l::test {

//! Number of heap allocations (malloc, calloc, realloc, reallocarray, posix_memalign,
//! aligned_alloc, memalign, valloc, pvalloc, and every operator new through them) since the
//! program started, in every thread.
std::size_t allocation_count() noexcept;

//! Counts the allocations made while it lives.
class AllocationGuard {
 public:
  AllocationGuard() noexcept : start_(allocation_count()) {}
  //! Allocations made since construction.
  std::size_t allocations() const noexcept { return allocation_count() - start_; }

 private:
  std::size_t start_;
};

}  // namespace a2l::test
