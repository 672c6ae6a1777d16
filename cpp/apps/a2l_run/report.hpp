// a2l-run's report (internal): the results per effect, the timings and the --summary JSON.
#pragma once

#include <fstream>
#include <vector>

#include "a2l/skill.hpp"
#include "options.hpp"
#include "records.hpp"
#include "request.hpp"
#include "robot.hpp"

namespace a2l_run {

//! What the closed loop measured; the vectors are reserved before it and never grow in it.
struct Timings {
  std::vector<double> step_us;  //!< each step() call (us)
  std::vector<double> tick_us;  //!< each control tick: differential IK + checks (us)
  std::vector<double> late_us;  //!< how late each wake-up at --rate was (us)
  long long total_steps = 0, total_ticks = 0;
  double elapsed = 0.0;  //!< s, the whole loop
};

//! Print the results per wanted effect and the timings, check the --trace file, and write the
//! --summary JSON. 0, or 1 after a message on a write error.
int report(const Args& args, const a2l::Skill& skill, const Request& request, const Robot& robot,
           const std::vector<EffectResult>& results, const Timings& timings, std::ofstream& trace);

}  // namespace a2l_run
