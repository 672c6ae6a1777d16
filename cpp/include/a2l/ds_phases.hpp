//! \file ds_phases.hpp
//! \brief The DS phases of a skill (docs/bundle_format.md, section `ds_phases`): diffeomorphic
//! DSs expressed relative to the object, each applying under some high-level state values,
//! with an action to emit at its target. Run by a2l::step_ds() (skill.hpp).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "a2l/diffeo.hpp"
#include "a2l/discretizer.hpp"
#include "a2l/movement_repertoire.hpp"

namespace a2l {

//! Most phases a skill may hold.
constexpr int kMaxDSPhases = 64;

//! A high-level state the phases are conditioned on (e.g. light: off, on).
struct DSStateVariable {
  std::string name;                 //!< state name
  std::vector<std::string> values;  //!< value names, in index order
};

//! One condition of a phase: state `state` (index into DSPhaseSet::states) has value `value`.
struct DSCondition {
  int state = 0;  //!< index of the state variable
  int value = 0;  //!< index of the required value
};

//! One phase: a 3-D DS in the object's frame (x = eef - object, its target relative to the
//! object), the state values it applies under, and what to do at its target.
struct DSPhase {
  std::string name;                                  //!< phase name (traces)
  DiffeoDS<3> ds;                                    //!< the DS, relative to the object
  std::vector<DSCondition> when;                     //!< all must hold; empty = always
  MovementAction end_action = MovementAction::none;  //!< emitted once within tolerance
  double tolerance = 0.01;                           //!< target reached within this (m)
};

//! The value index of each DS state variable (DSPhaseSet::states order); an index outside
//! [0, n_values) matches no condition on that state.
using DSStateValues = std::array<int, kMaxVariables>;

//! A skill's DS phases: the state variables they name, and the phases in priority order (the
//! first whose conditions hold applies).
struct DSPhaseSet {
  std::vector<DSStateVariable> states;  //!< at most kMaxVariables
  std::vector<DSPhase> phases;          //!< at most kMaxDSPhases

  //! True if the skill has no phase.
  bool empty() const noexcept { return phases.empty(); }
  //! Index of the state variable `name`, or -1.
  int find_state(const std::string& name) const noexcept {
    for (std::size_t i = 0; i < states.size(); ++i) {
      if (states[i].name == name) return static_cast<int>(i);
    }
    return -1;
  }
  //! Index of the first phase whose conditions all hold for `values`, or -1. No allocation.
  int select(const DSStateValues& values) const noexcept {
    for (std::size_t p = 0; p < phases.size(); ++p) {
      bool ok = true;
      for (const DSCondition& c : phases[p].when) {
        ok = ok && values[static_cast<std::size_t>(c.state)] == c.value;
      }
      if (ok) return static_cast<int>(p);
    }
    return -1;
  }
};

}  // namespace a2l
