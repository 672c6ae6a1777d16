//! \file skill.hpp
//! \brief A skill (immutable, loaded from a bundle), its preallocated run state, and step().
//!
//! As Pinocchio's Model/Data split: a `Skill` is read-only after loading and may be shared by
//! threads; a `SkillState` holds everything that changes during a run (step counter, scratch
//! buffers, the trace ring buffer), allocated once by its constructor. `step()` maps the
//! current context to the next movement through the compiled table: it allocates nothing,
//! throws nothing and does no I/O (tests/cpp/test_skill_noalloc.cpp proves it).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "a2l/discretizer.hpp"
#include "a2l/ds_phases.hpp"
#include "a2l/movement_repertoire.hpp"
#include "a2l/policy_table.hpp"
#include "a2l/status.hpp"

namespace a2l {

//! The robot a skill was learned for (the bundle's "robot" entry).
struct RobotInfo {
  bool present = false;     //!< false when the bundle's robot is null (virtual scene)
  std::string name;         //!< robot name, e.g. "baxter"
  std::string urdf_sha256;  //!< SHA-256 (hex) of the URDF's bytes
  std::string base_link;    //!< first link of the arm chain
  std::string tip_link;     //!< last link of the arm chain
};

//! What step() does in a context cell the table has no information for (a uniform row).
enum class Fallback : int {
  none = 0,  //!< stop with `unknown_context`
  //! take the nearest informative cell's movement (Skill::fallback_row), never one that
  //! carries the end-effector past the distance range (Skill::fallback_reach) or into its
  //! first bin (Skill::fallback_near)
  nearest = 1,
  //! as `nearest`, but the step heads for the nearest informative cell instead of taking
  //! its movement: of the movements within the same two limits, the one that ends nearest
  //! the centre of that cell (Skill::fallback_target) (`nearest`'s answer where the
  //! skill's geometric variables are not a distance and an orientation); and no step, with
  //! data or without, undoes the run's previous movement unless no other is allowed
  approach = 2,
};

//! The manifest name of a fallback rule ("none", "nearest", "approach"). Never allocates.
const char* fallback_name(Fallback f) noexcept;

//! Parse a manifest fallback name; false if `name` is not one.
bool parse_fallback(const std::string& name, Fallback& out) noexcept;

//! The clearance rule's bar of a bundle that does not set one (SkillSettings::clearance_ratio).
constexpr double kClearanceRatio = 0.5;

//! How step() chooses among the movements of a known context.
struct SkillSettings {
  int step_cap = 12;                   //!< most movements a run may take
  bool smoothing = false;              //!< neighbour smoothing (docs/method.md)
  double uniform_tolerance = 1e-9;     //!< a row within this of uniform carries no information
  Fallback fallback = Fallback::none;  //!< the answer for a cell with no information
  //! The clearance rule (m; 0 = off): away from the side the wanted push effect pushes from
  //! (more than 45 degrees off it, seen from the object), a movement that would end nearer
  //! the object than this gives way to the best-scored one that does not, if that one scores
  //! at least `clearance_ratio` of it (a near-equal choice, never a rare one).
  double clearance = 0.0;
  //! The clearance rule's bar, in (0, 1]: an alternative keeps clearance only if its
  //! (smoothed) probability is at least this share of the chosen movement's.
  double clearance_ratio = kClearanceRatio;
  //! The alignment rule (m; 0 = off), the clearance rule's counterpart on the pushing side:
  //! there, a movement towards the object (along the push direction) that would end nearer
  //! it than `clearance`, started more than `align` off the push line through the object's
  //! centre, gives way to the allowed movement that does not approach the object along the
  //! push direction and ends nearest that line (if nearer than the start). A push started
  //! at the object's corner turns it into the neighbouring effect; a push along the line
  //! does not. Needs `clearance` > 0.
  double align = 0.0;
  //! The revisit rule: when a run comes back within half a movement of points of its path
  //! (eef - object) that it has left since (staying put, e.g. held, is no return), the
  //! movements it chose there are spent: the step takes the best-scored allowed movement not
  //! spent (nor undoing the previous one), if there is one. A table step is a function of the
  //! context's cell, so without it a run that comes back repeats the loop that brought it
  //! back, to the step cap.
  bool avoid_revisits = false;
};

//! Most points of a run's path a SkillState remembers for the revisit rule.
constexpr std::size_t kMaxPath = 256;

//! Most row-pair comparisons Skill::create may spend on the nearest-cell fallback
//! (uniform rows x cells sharing their effect and high-level values); a larger table is
//! refused with `invalid_argument` rather than loaded slowly.
constexpr std::size_t kMaxFallbackWork = std::size_t{1} << 28;

//! A skill: discretizer, policy table and movement repertoire, loaded from a bundle, and
//! optionally its DS phases (run by step_ds()). Immutable: every method is const and may be
//! called from several threads at once.
class Skill {
 public:
  //! An empty skill; load one with load_bundle().
  Skill() = default;

  //! Assemble a skill from its parts, checking that they agree (table axes = variables'
  //! bins, table movements = repertoire size; phase conditions name declared states and
  //! values, at most kMaxDSPhases phases, tolerances finite and > 0). With
  //! `settings.fallback` `nearest` or `approach` it compiles the fallback of every uniform
  //! row (fallback_row()), with `approach` also its target point (fallback_target()).
  //! \return `size_mismatch` or `invalid_argument` naming the check, else `ok`.
  static Result create(std::string name, Discretizer discretizer, PolicyTable table,
                       MovementRepertoire movements, SkillSettings settings, RobotInfo robot,
                       Skill& out, DSPhaseSet ds_phases = {});

  //! True once loaded.
  bool loaded() const noexcept { return table_.n_moves() > 0; }
  //! The skill's name.
  const std::string& name() const noexcept { return name_; }
  //! The evidence variables and their bin math.
  const Discretizer& discretizer() const noexcept { return discretizer_; }
  //! The compiled table.
  const PolicyTable& table() const noexcept { return table_; }
  //! The movement repertoire.
  const MovementRepertoire& movements() const noexcept { return movements_; }
  //! Step cap, smoothing and uniform tolerance.
  const SkillSettings& settings() const noexcept { return settings_; }
  //! The robot it was learned for.
  const RobotInfo& robot() const noexcept { return robot_; }
  //! Number of evidence variables.
  int n_variables() const noexcept { return discretizer_.n_variables(); }
  //! Number of movements.
  int n_moves() const noexcept { return table_.n_moves(); }
  //! The DS phases (empty if the bundle has none).
  const DSPhaseSet& ds_phases() const noexcept { return ds_phases_; }
  //! The row step() reads for table row `row`: `row` itself where it is informative; for a
  //! uniform row with the `nearest` fallback, the nearest informative row with the same
  //! effect and high-level values (distance: the sum over the geometric axes of the bin
  //! differences, orientation's bins counted around the circle; the lowest row on a tie),
  //! -1 where there is none or without a fallback. Compiled by create(), O(1) here.
  std::int32_t fallback_row(std::size_t row) const noexcept {
    return fallback_.empty() ? (table_.argmax(row) < 0 ? -1 : static_cast<std::int32_t>(row))
                             : fallback_[row];
  }
  //! How far a fallback step may carry the end-effector from the object (m): the upper end
  //! of the skill's first `distance` variable (range_upper_end(): high, or its last edge),
  //! or a negative value when it has none (no limit). A fallback movement may not end
  //! farther than max(current distance, this).
  double fallback_reach() const noexcept { return fallback_reach_; }
  //! How close a fallback step may carry the end-effector to the object (m): the upper edge
  //! of the first bin of the skill's first `distance` variable (first_bin_edge(); negative
  //! without one). A fallback movement may not end nearer than min(current distance, this):
  //! contact with the object is left to cells with data.
  double fallback_near() const noexcept { return fallback_near_; }
  //! With the `approach` fallback, whether uniform row `row` heads for a point, and the
  //! point (eef - object, m, in the table plane): the centre of its fallback row's cell
  //! (the middle of its distance bin, bin_centre(), at the middle angle of its orientation
  //! bin). False for an informative row, without the `approach` fallback, or unless the
  //! skill's geometric variables are one distance and one orientation.
  //! The planar direction (unit) the object moves for value `effect` of the skill's effect
  //! variable, when that value names a push effect (effect_direction()); zero otherwise
  //! (another effect, no effect variable, an index out of range). The clearance rule's
  //! pushing side is opposite it.
  Eigen::Vector2d push_direction(int effect) const noexcept {
    if (effect < 0 || static_cast<std::size_t>(effect) >= push_directions_.size()) {
      return Eigen::Vector2d::Zero();
    }
    return push_directions_[static_cast<std::size_t>(effect)];
  }
  bool fallback_target(std::size_t row, double& x, double& y) const noexcept {
    if (targets_.empty() || table_.argmax(row) >= 0 || fallback_[row] < 0) return false;
    x = targets_[2 * row];
    y = targets_[2 * row + 1];
    return true;
  }

 private:
  std::string name_;
  Discretizer discretizer_;
  PolicyTable table_;
  MovementRepertoire movements_;
  SkillSettings settings_;
  RobotInfo robot_;
  DSPhaseSet ds_phases_;
  std::vector<std::int32_t> fallback_;  // per row, with Fallback::nearest (fallback_row())
  double fallback_reach_ = -1.0;        // fallback_reach()
  double fallback_near_ = -1.0;         // fallback_near()
  std::vector<double> targets_;         // 2 per row, with Fallback::approach (fallback_target())
  std::vector<Eigen::Vector2d> push_directions_;  // per effect value (push_direction())
};

//! One step of a skill as the trace records it (docs/method.md: context bins, movement,
//! probability). Fixed size.
struct TraceRecord {
  std::int64_t step = 0;  //!< index of the step() call since the last reset
  int n_variables = 0;    //!< valid entries of `bins`
  std::array<std::int16_t, kMaxVariables> bins{};  //!< bin per variable, -1 = unknown
  int movement = -1;                               //!< chosen movement, -1 if none
  double probability = 0.0;                        //!< its (smoothed) probability, 0 if none
  Status status = Status::not_initialized;         //!< what the step returned
  int phase = -1;         //!< the DS phase of a step_ds() call, -1 for a table step or none
  bool fallback = false;  //!< the cell had no information: the movement is its fallback's
};

//! What one step() returns.
struct StepOutput {
  Status status = Status::not_initialized;                 //!< ok, or why the run stops
  int movement = -1;                                       //!< chosen movement (ok only), else -1
  double probability = 0.0;                                //!< its probability (ok only), else 0
  Eigen::Vector3d displacement = Eigen::Vector3d::Zero();  //!< its displacement (m)
  //! The movement's action (`open`, `close`, `stay`; displacement zero), `none` for a
  //! displacement or when the run stops.
  MovementAction action = MovementAction::none;
  TraceRecord record;  //!< what was pushed into the trace
};

//! Smoothing choice of a run: the bundle's setting or an override.
enum class Smoothing : int {
  from_skill = 0,  //!< use the skill's `execution.smoothing`
  off = 1,         //!< never smooth
  on = 2,          //!< always smooth
};

//! The mutable state of one run of a skill. Everything is allocated by the constructor;
//! step() and reset() allocate nothing.
class SkillState {
 public:
  //! An unusable state (step() returns not_initialized).
  SkillState() = default;
  //! A state sized for `skill`, with a trace ring buffer of `trace_capacity` records
  //! (at least 1).
  explicit SkillState(const Skill& skill, std::size_t trace_capacity = 1024);

  //! Start a new run: step counter to 0, no DS end action emitted yet. Keeps the trace (see
  //! clear_trace()). No allocation.
  void reset() noexcept {
    steps_ = 0;
    path_size_ = 0;
    calls_ = 0;
    ds_emitted_ = 0;
  }
  //! Movements taken since the last reset.
  int steps() const noexcept { return steps_; }
  //! Smoothing choice for the next steps.
  Smoothing smoothing = Smoothing::from_skill;

  //! Records held (at most the capacity).
  std::size_t trace_size() const noexcept { return trace_size_; }
  //! Capacity of the ring buffer.
  std::size_t trace_capacity() const noexcept { return trace_.size(); }
  //! Records overwritten because the buffer was full.
  std::uint64_t trace_dropped() const noexcept { return dropped_; }
  //! Record i, oldest first (i < trace_size()).
  const TraceRecord& trace(std::size_t i) const noexcept {
    return trace_[(trace_head_ + i) % trace_.size()];
  }
  //! Points of this run's path the revisit rule remembers (SkillSettings::avoid_revisits):
  //! one per movement taken, at most min(step cap, kMaxPath).
  std::size_t path_size() const noexcept { return path_size_; }
  //! Point i of the path (eef - object when movement i was chosen, m), i < path_size().
  const Eigen::Vector3d& path_point(std::size_t i) const noexcept { return path_[i]; }
  //! The movement chosen at point i, i < path_size().
  int path_movement(std::size_t i) const noexcept { return path_moves_[i]; }
  //! Empty the trace. No allocation.
  void clear_trace() noexcept {
    trace_head_ = trace_size_ = 0;
    dropped_ = 0;
  }

 private:
  friend Status step(const Skill&, SkillState&, const Context&, StepOutput&) noexcept;
  friend Status step_ds(const Skill&, SkillState&, const Eigen::Vector3d&, const Eigen::Vector3d&,
                        const DSStateValues&, StepOutput&) noexcept;
  void push(const TraceRecord& r) noexcept;
  // The revisit rule's path: point `r` (eef - object) where the run took movement `m`;
  // nothing once the path is full.
  void remember(const Eigen::Vector3d& r, int m) noexcept {
    if (path_size_ >= path_.size()) return;
    path_[path_size_] = r;
    path_moves_[path_size_] = m;
    ++path_size_;
  }
  // The opening of step() and step_ds(): `out` cleared (no movement), its record numbered
  // with this call and emptied.
  void begin_step(StepOutput& out) const noexcept;
  // The end of every step() / step_ds() call: the status into `out` and its record; the
  // record pushed into the trace and the call counted (if the state is sized). Returns `s`.
  Status finish_step(StepOutput& out, Status s) noexcept;
  // not_initialized (not loaded, or an unsized state) or size_mismatch (sized for another
  // skill), else ok.
  Status check_sized(const Skill& skill) const noexcept;

  int n_variables_ = -1;
  int n_moves_ = 0;
  int steps_ = 0;
  std::int64_t calls_ = 0;
  std::uint64_t ds_emitted_ = 0;  // bit p: phase p emitted its end action in this run
  std::array<int, kMaxVariables> bins_{};
  std::vector<double> average_;        // n_moves: smoothing's averaged posterior
  std::vector<int> votes_;             // n_moves: smoothing's argmax counts
  std::vector<char> spent_;            // n_moves: the revisit rule's spent movements
  std::vector<Eigen::Vector3d> path_;  // the run's points (eef - object), kMaxPath at most
  std::vector<int> path_moves_;        // the movement taken at each
  std::size_t path_size_ = 0;
  std::vector<TraceRecord> trace_;
  std::size_t trace_head_ = 0, trace_size_ = 0;
  std::uint64_t dropped_ = 0;
};

//! One step of a skill: context -> bins -> table -> movement (a displacement, or an action of
//! the repertoire: `out.action` set, displacement zero).
//!
//! Stops (returns a status other than `ok`, movement -1) when:
//! - `context.effect_produced` is set: `effect_produced`;
//! - `state.steps()` reached the skill's step cap: `step_cap`;
//! - the context is unknown (a non-finite position, an effect or high-level index out of
//!   range, or a uniform table row = argmax -1 without a fallback row): `unknown_context`.
//! A uniform row with a fallback row (Skill::fallback_row, the skill's `nearest` fallback)
//! is answered from that row, status `ok`, `record.fallback` set: a defined answer compiled
//! at load time, never a guess at step time. A fallback step takes the most probable
//! movement (after smoothing) that ends neither farther from the object than max(current
//! distance, Skill::fallback_reach()) (the last distance bin saturates: beyond it the cell no
//! longer changes, and an outward fallback movement would repeat until the arm's reach ends)
//! nor nearer than min(current distance, Skill::fallback_near()) (a movement borrowed from
//! another cell pushed the object with the wrong effect); if none is allowed, the
//! unrestricted choice.
//! With smoothing (docs/method.md), the posterior is averaged over the current point and
//! its 6 neighbours (eef +- step/2 along x, y, z), uniform (uninformative) neighbours left
//! out; the top movement is taken if it is alone, has p > 0.95, or the second is below 0.75
//! times the first; otherwise the one of the two that is the argmax at more of the 7 points
//! (the first on a tie). An unknown current point is still an unknown context.
//! Every call pushes one TraceRecord into the state's ring buffer.
//! \return the status, also in `out.status`. Allocates nothing, throws nothing.
Status step(const Skill& skill, SkillState& state, const Context& context,
            StepOutput& out) noexcept;

//! One step of the skill's DS phases (docs/bundle_format.md, `ds_phases`): the first phase
//! whose conditions hold for `states` (value index per DS state variable, in
//! `skill.ds_phases().states` order) applies; with x = eef - object and v its DS velocity at
//! x, the displacement is step * v / |v|, capped at the distance |x - target| to the phase's
//! target (`out.movement` -1, `out.record.phase` / `out.record.movement` -1). Within the
//! phase's tolerance of its target it emits the phase's end action, once per run (status ok,
//! `out.action` set, `out.movement` its index in the repertoire or -1, no displacement);
//! then, or without an end action, it returns `converged`.
//!
//! Stops (no displacement) with `not_initialized` (no phase, or the state was not made for
//! the skill), `step_cap` (the skill's step cap), `unknown_context` (a non-finite position,
//! no phase matching `states`, or a DS evaluation failing), `converged`. Every call pushes
//! one TraceRecord (its `phase` set, no bins). Allocates nothing, throws nothing.
Status step_ds(const Skill& skill, SkillState& state, const Eigen::Vector3d& eef,
               const Eigen::Vector3d& object, const DSStateValues& states,
               StepOutput& out) noexcept;

}  // namespace a2l
