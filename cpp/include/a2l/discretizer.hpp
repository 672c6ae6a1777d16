//! \file discretizer.hpp
//! \brief Context -> bins: the evidence variables of a skill and their bin math.
//!
//! The bin formulas are those of docs/bundle_format.md (and docs/method.md, "Context"):
//! distance saturating at both ends (equal bins over [low, high], or bins between explicit
//! edges), orientation in sections offset by half a section, inclination from the vertical,
//! and the planar offsets along the base frame's x and y axes (binned like a distance: they
//! tell a point beside a face of a box from one in front of it, which distance and
//! orientation sections do not). Discrete variables (the wanted effect,
//! high-level states) are given by the caller as value indices. A non-finite position or a discrete
//! index out of range is an *unknown context*: the discretizer reports it, it never guesses a bin.
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "a2l/status.hpp"

namespace a2l {

//! Most evidence variables a skill may have (capacity of the fixed-size buffers).
constexpr int kMaxVariables = 16;
//! Most bins (or values) one variable may have.
constexpr int kMaxBins = 1024;

//! What an evidence variable measures.
enum class VariableKind : int {
  effect = 0,       //!< the wanted effect; index given by the caller
  distance = 1,     //!< ||object - eef|| (3-D, m)
  orientation = 2,  //!< atan2(dy, dx) of (eef - object) in the table plane
  inclination = 3,  //!< angle of (eef - object) from the vertical, in [0, pi]
  high_level = 4,   //!< a discrete state (light, gripper, colour); index given by the caller
  offset_x = 5,     //!< x of (eef - object) in the base frame (m), binned like a distance
  offset_y = 6,     //!< y of (eef - object) in the base frame (m), binned like a distance
};

//! Whether `kind` is measured from the end-effector and object positions (distance,
//! orientation, inclination, offset_x, offset_y) rather than given as an index.
constexpr bool is_geometric(VariableKind kind) noexcept {
  return kind != VariableKind::effect && kind != VariableKind::high_level;
}

//! Whether a variable of `kind` has a range [low, high] (distance, offset_x, offset_y).
constexpr bool has_range(VariableKind kind) noexcept {
  return kind == VariableKind::distance || kind == VariableKind::offset_x ||
         kind == VariableKind::offset_y;
}

//! The manifest name of a kind ("effect", "distance", ...). Never allocates.
const char* variable_kind_name(VariableKind kind) noexcept;

//! Parse a manifest kind name; false if `name` is not a kind.
bool parse_variable_kind(const std::string& name, VariableKind& kind) noexcept;

//! One evidence variable: one axis of a skill's policy table.
struct Variable {
  std::string name;                            //!< unique name, e.g. "distance", "light"
  VariableKind kind = VariableKind::distance;  //!< what it measures
  int n_bins = 1;                              //!< number of bins (values for effect / high_level)
  double low = 0.0;   //!< distance, offset_x, offset_y only: lower end of the range (m)
  double high = 0.0;  //!< distance, offset_x, offset_y only: upper end of the range (m)
  std::vector<std::string> values;  //!< effect / high_level only: value names
  //! distance only, optional: the interior bin edges (m), finite, > 0, strictly increasing;
  //! n_bins = edges.size() + 1 and bin = the number of edges <= d (Discretizer::edges_bin),
  //! low and high then play no part in the bins. Empty: n_bins equal bins over [low, high].
  //! Set before Discretizer::create(), only read afterwards (the step does not allocate).
  std::vector<double> edges;
};

//! Check the explicit edges of `v` (none is fine): a distance only, at most kMaxBins - 1,
//! finite, > 0, strictly increasing, and v.n_bins = edges + 1.
//! \return `invalid_argument` with a message starting with `where` (e.g. "variables[1]
//!         ('distance')") and naming the field (".edges[2]: ..."), else `ok`.
Result check_edges(const Variable& v, const std::string& where);

//! The upper edge of the first bin of a variable with a range (has_range()): edges[0] with
//! explicit edges, else low + (high - low) / n_bins. Skill::fallback_near() is this edge of
//! the skill's distance.
double first_bin_edge(const Variable& v) noexcept;

//! The upper end of the range of a variable with a range (has_range()): edges.back() with
//! explicit edges (the lower edge of the last, saturated bin), else high.
//! Skill::fallback_reach() is this end of the skill's distance.
double range_upper_end(const Variable& v) noexcept;

//! The centre of bin `b` of a variable with a range (has_range()), the point the `approach`
//! fallback heads for: without edges low + (b + 0.5) * w, w = (high - low) / n_bins (the end
//! bins' middles within [low, high]); with edges the middle of [edges[b - 1], edges[b]], the
//! first bin's [0, edges[0]] (a distance is >= 0), and for the last, saturated bin the middle
//! of a bin as wide as the one before it, starting at edges.back().
double bin_centre(const Variable& v, int b) noexcept;

//! The current situation, as the runtime sees it at one instant. Fixed size, no allocation.
struct Context {
  Eigen::Vector3d eef = Eigen::Vector3d::Zero();     //!< end-effector position (m)
  Eigen::Vector3d object = Eigen::Vector3d::Zero();  //!< object centre (m)
  int effect = 0;  //!< index of the wanted effect in the skill's effect variable's values
  //! Value index of each high-level variable, by the variable's axis in the skill (entries of
  //! other axes are ignored).
  std::array<int, kMaxVariables> high_level{};
  //! Set by the caller once it observed that the object moved (the effect was produced): the
  //! next step() then ends the run with Status::effect_produced.
  bool effect_produced = false;
};

//! Context -> bin of every evidence variable, in axis order. Immutable once created.
class Discretizer {
 public:
  //! An empty discretizer (no variables).
  Discretizer() = default;

  //! Validate `variables` and build a discretizer.
  //! \return `invalid_argument` naming the variable and the check (duplicate name, bin count
  //!         outside [1, kMaxBins], low >= high, edges on a variable other than a distance,
  //!         edges not finite, not > 0 or not strictly increasing, n_bins != edges + 1, more
  //!         than one variable of a geometric kind or of kind effect, more than kMaxVariables
  //!         variables), else `ok`.
  static Result create(std::vector<Variable> variables, Discretizer& out);

  //! Number of variables (axes).
  int n_variables() const noexcept { return static_cast<int>(variables_.size()); }
  //! The variables, in axis order.
  const std::vector<Variable>& variables() const noexcept { return variables_; }
  //! The variable of axis `i`.
  const Variable& variable(int i) const { return variables_.at(static_cast<size_t>(i)); }
  //! Axis of the variable called `name`, or -1.
  int find(const std::string& name) const noexcept;
  //! Axis of the effect variable, or -1 if the skill has none.
  int effect_axis() const noexcept { return effect_axis_; }

  //! Distance bin: clamp(floor((d - low) / (high - low) * n), 0, n - 1); -1 if d is not finite.
  static int distance_bin(double d, double low, double high, int n) noexcept;
  //! Bin of d between explicit edges: the number of edges <= d (0 below edges[0], n_edges at
  //! or above the last edge); -1 if d is not finite. `edges` sorted ascending.
  static int edges_bin(double d, const double* edges, int n_edges) noexcept;
  //! Orientation bin of theta (rad): floor(((theta + pi + w/2) mod 2pi) / w) mod n, w = 2pi/n;
  //! -1 if theta is not finite.
  static int orientation_bin(double theta, int n) noexcept;
  //! Inclination bin of phi in [0, pi]: min(floor(phi / pi * n), n - 1), clamped at 0;
  //! -1 if phi is not finite.
  static int inclination_bin(double phi, int n) noexcept;

  //! Bin of the geometric variable `v` (distance, orientation, inclination, offset_x or
  //! offset_y) for an end-effector at `eef` and an object at `object`, by the formulas above
  //! applied to r = eef - object (distance sqrt(rx*rx + ry*ry + rz*rz), binned by edges_bin
  //! when the variable has edges, else by distance_bin; orientation atan2(ry, rx),
  //! inclination atan2(sqrt(rx*rx + ry*ry), rz); offset_x and offset_y: distance_bin of rx
  //! and ry over [low, high]). The one implementation of the context bins:
  //! discretize() and the Python learning side (a2l._core.context_bins) call it.
  //! \return the bin, or -1 if r is not finite (an unknown context) or `v` is not of a
  //!         geometric kind. Allocates nothing.
  static int context_bin(const Variable& v, const Eigen::Vector3d& eef,
                         const Eigen::Vector3d& object) noexcept;

  //! The bins of `context`, one per variable, into `bins[0 .. n_variables())`.
  //! \return `unknown_context` if eef - object is not finite (see context_bin()) or a discrete
  //!         index is out of range (bins then holds -1 at that axis), else `ok`. Allocates
  //!         nothing.
  Status discretize(const Context& context, int* bins) const noexcept;

 private:
  std::vector<Variable> variables_;
  int effect_axis_ = -1;
};

}  // namespace a2l
