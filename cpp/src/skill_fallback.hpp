//! \file skill_fallback.hpp
//! \brief Private to the skill library: what Skill::create compiles for a skill's fallback
//! (a context cell without data), so that the step only looks it up.
#pragma once

#include <cstdint>
#include <vector>

#include "a2l/skill.hpp"

namespace a2l::detail {

//! The nearest-cell fallback of every row (Skill::fallback_row) into `out`: a row's own index
//! where it is informative; else the nearest informative row with the same effect and
//! high-level values (geometric bins by L1 distance, orientations wrapping), or -1.
//! Fails (invalid_argument) when the table is too large to compile (kMaxFallbackWork).
Result compile_fallback(const Discretizer& disc, const PolicyTable& table,
                        std::vector<std::int32_t>& out);

//! The centre of every fallback row's cell (Skill::fallback_target) into `out` (2 per row:
//! x, y relative to the object), or `out` empty unless the discretizer's geometric variables
//! are one distance and one orientation (a cell is then a sector of a ring around the object).
void compile_targets(const Discretizer& disc, const PolicyTable& table,
                     const std::vector<std::int32_t>& fallback, std::vector<double>& out);

}  // namespace a2l::detail
