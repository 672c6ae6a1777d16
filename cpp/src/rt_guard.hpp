// Private: Eigen's allocation guard inside real-time sections, as dmpbbo does. Active when the
// core is built with -DA2L_MALLOC_GUARD=ON (EIGEN_RUNTIME_NO_MALLOC; CMake then keeps
// assertions on in every build type): any Eigen heap allocation inside the section then fails
// an assertion. `make test` runs every NoAlloc test in such a build (build/cpp-guard); the
// counting allocator of tests/cpp/alloc_counter.hpp proves the same in every build.
#pragma once

#include <Eigen/Core>

namespace a2l::detail {

#if defined(A2L_MALLOC_GUARD) && defined(EIGEN_RUNTIME_NO_MALLOC)
class RealTimeSection {
 public:
  RealTimeSection() noexcept : previous_(Eigen::internal::is_malloc_allowed()) {
    Eigen::internal::set_is_malloc_allowed(false);
  }
  ~RealTimeSection() { Eigen::internal::set_is_malloc_allowed(previous_); }
  RealTimeSection(const RealTimeSection&) = delete;
  RealTimeSection& operator=(const RealTimeSection&) = delete;

 private:
  bool previous_;
};
#else
class RealTimeSection {
 public:
  RealTimeSection() noexcept = default;
};
#endif

}  // namespace a2l::detail
