// a2l-run's request (internal): what the command line asks of the skill (the effects, the
// high-level states, the task), resolved against the skill's variables.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "a2l/skill.hpp"
#include "options.hpp"
#include "task.hpp"

namespace a2l_run {

//! The command line resolved against a skill.
struct Request {
  std::vector<std::string> effect_names;             //!< the values of the skill's effect variable
  std::vector<int> wanted;                           //!< indices of the effects to run (--effect)
  std::array<int, a2l::kMaxVariables> high_level{};  //!< table value index per axis (--state)
  a2l::DSStateValues ds_values{};                    //!< the DS phases' state values (--state)
  Task task = Task::push;
  bool ds_mode = false;  //!< --mode ds
  bool light = false;    //!< --state light=on
  bool gripper = false;  //!< --state gripper=closed
};

//! Resolve --effect, --state, --task and --mode against `skill` into `out`, and fill the
//! task's defaults of --start-height and --radius-range into `args`. 0, or 2 after a message
//! naming the option.
int resolve_request(Args& args, const a2l::Skill& skill, Request& out);

}  // namespace a2l_run
