// a2l-run's records (internal): the trace of each episode and the results per effect.
#pragma once

#include <Eigen/Core>
#include <map>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "a2l/skill.hpp"
#include "options.hpp"

namespace a2l_run {

//! One step of an episode as the trace records it.
struct TraceRow {
  a2l::TraceRecord record;
  Eigen::Vector3d eef, object;
};

//! What the episodes of one wanted effect gave.
struct EffectResult {
  int success = 0, false_positive = 0, fail = 0;
  long long steps_success = 0;
  std::map<std::string, int> stops;
};

//! The CSV trace's header line (the bins' columns named after the skill's variables).
void write_trace_header(std::ostream& out, const a2l::Skill& skill);

//! The rows of one episode: CSV, or JSON lines (with the DS phase's name).
void write_trace(std::ostream& out, bool csv, const a2l::Skill& skill, int episode,
                 const std::string& effect, const std::vector<TraceRow>& rows);

//! Print the table of results per wanted effect, record them in `summary["effects"]`, and add
//! up the successes and episodes.
void print_results(const std::vector<int>& wanted, const std::vector<std::string>& effect_names,
                   const std::vector<EffectResult>& results, nlohmann::json& summary,
                   int& total_success, int& total_episodes);

//! The value index of --state NAME=VALUE for the DS phases' states (states they do not name
//! are ignored; others 0); false after a message on an unknown value.
bool ds_state_values(const a2l::Skill& skill, const Args& args, a2l::DSStateValues& out);

}  // namespace a2l_run
