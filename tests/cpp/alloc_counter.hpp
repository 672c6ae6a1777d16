//! \file alloc_counter.hpp
//! \brief A counting global allocator for the tests: every operator new in the test
//! executable increments a counter, so a test proves that a section allocates nothing.
//! Defined once, in test_alloc_counter.cpp (the only replacement of operator new in
//! a2l_tests): include this header and use AllocationGuard, never define another one.
#pragma once

#include <cstddef>

namespace a2l::test {

//! Number of calls to operator new (all forms) since the program started.
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
