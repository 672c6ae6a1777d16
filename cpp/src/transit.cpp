// The transit planner (transit.hpp): a request's checks, OMPL's RRT-Connect search at a coarse
// then a fine resolution, the shortening, and plan(); the timing is in transit_timing.cpp.
#include "a2l/transit.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "transit_timing.hpp"

#if A2L_HAVE_BULLET && A2L_HAVE_OMPL
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/PathSimplifier.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include <mutex>
#endif

namespace a2l {

const char* transit_status_name(TransitStatus status) noexcept {
  switch (status) {
    case TransitStatus::ok:
      return "ok";
    case TransitStatus::invalid_argument:
      return "invalid_argument";
    case TransitStatus::start_out_of_limits:
      return "start_out_of_limits";
    case TransitStatus::goal_out_of_limits:
      return "goal_out_of_limits";
    case TransitStatus::start_in_collision:
      return "start_in_collision";
    case TransitStatus::goal_in_collision:
      return "goal_in_collision";
    case TransitStatus::no_path:
      return "no_path";
  }
  return "unknown";
}

bool transit_available() noexcept {
#if A2L_HAVE_BULLET && A2L_HAVE_OMPL
  return true;
#else
  return false;
#endif
}

#if A2L_HAVE_BULLET && A2L_HAVE_OMPL

namespace ob = ompl::base;
namespace og = ompl::geometric;

namespace {

// Uniform sampling with a per-call seed (OMPL's samplers otherwise draw from a global seed).
class SeededSampler : public ob::RealVectorStateSampler {
 public:
  SeededSampler(const ob::StateSpace* space, std::uint32_t seed) : RealVectorStateSampler(space) {
    rng_.setLocalSeed(seed);
  }
};

void seed_ompl_once(std::uint32_t seed) {
  static std::once_flag flag;
  std::call_once(flag, [seed] {
    ompl::msg::setLogLevel(ompl::msg::LOG_NONE);
    ompl::RNG::setSeed(seed == 0 ? 1u : seed);  // OMPL reads 0 as "pick one from the clock"
  });
}

std::string pairs_text(const std::vector<CollisionPair>& pairs) {
  std::ostringstream ss;
  for (size_t i = 0; i < pairs.size() && i < 3; ++i)
    ss << (i ? ", " : "") << "'" << pairs[i].first << "'/'" << pairs[i].second << "'";
  if (pairs.size() > 3) ss << " and " << pairs.size() - 3 << " more";
  return ss.str();
}

// The wall time of one plan() call: elapsed since its start, left of its time limit (s).
struct Deadline {
  using clock = std::chrono::steady_clock;
  clock::time_point t0;
  double time_limit;
  double elapsed() const { return std::chrono::duration<double>(clock::now() - t0).count(); }
  double left() const { return time_limit - elapsed(); }
};

// True if an option is out of its domain (the message of invalid_argument says which).
bool bad_options(const TransitOptions& o) {
  return !(o.time_limit > 0) || !(o.resolution > 0) || !(o.velocity_scale > 0) ||
         o.velocity_scale > 1 || !(o.acceleration > 0) || !(o.sample_period > 0) ||
         !(o.default_velocity > 0) || o.shortcut_rounds < 0 || o.shortcut_patience < 0 ||
         !(o.coarse_resolution >= 0) || !std::isfinite(o.coarse_resolution);
}

// A request's verdict: TransitStatus::ok, or why plan() refuses it (status and message).
struct Verdict {
  TransitStatus status = TransitStatus::ok;
  std::string message;
};

// Whether a transit from `q_start` to `q_goal` can be planned on `model`: the model loaded,
// sizes, finite values, options, joint limits and collisions of the end points, in this order.
Verdict check_request(CollisionModel& model, const Eigen::Ref<const Eigen::VectorXd>& q_start,
                      const Eigen::Ref<const Eigen::VectorXd>& q_goal, const TransitOptions& o) {
  using S = TransitStatus;
  if (!model.loaded()) return {S::invalid_argument, "the model is not loaded"};
  const Kinematics& kin = model.kinematics();
  const int n = kin.n_joints();
  if (q_start.size() != n || q_goal.size() != n)
    return {S::invalid_argument, "q_start and q_goal must have " + std::to_string(n) + " entries"};
  if (!q_start.allFinite() || !q_goal.allFinite())
    return {S::invalid_argument, "q_start or q_goal contains NaN or inf"};
  if (bad_options(o))
    return {S::invalid_argument,
            "options: time_limit, resolution, acceleration, sample_period and "
            "default_velocity must be > 0, velocity_scale in (0, 1], shortcut_rounds, "
            "shortcut_patience and coarse_resolution >= 0"};
  if (!kin.within_limits(q_start, 1e-9))
    return {S::start_out_of_limits, "the start violates the joint limits"};
  if (!kin.within_limits(q_goal, 1e-9))
    return {S::goal_out_of_limits, "the goal violates the joint limits"};
  if (auto p = model.colliding_pairs(q_start); !p.empty())
    return {S::start_in_collision, "the start collides: " + pairs_text(p)};
  if (auto p = model.colliding_pairs(q_goal); !p.empty())
    return {S::goal_in_collision, "the goal collides: " + pairs_text(p)};
  return {};
}

// The joint limits as the state space's bounds (+-pi for an unlimited joint).
ob::RealVectorBounds joint_bounds(const Kinematics& kin) {
  const int n = kin.n_joints();
  ob::RealVectorBounds bounds(n);
  for (int i = 0; i < n; ++i) {
    bounds.setLow(i, std::isfinite(kin.lower()[i]) ? kin.lower()[i] : -M_PI);
    bounds.setHigh(i, std::isfinite(kin.upper()[i]) ? kin.upper()[i] : M_PI);
  }
  return bounds;
}

// A joint space within `bounds`, sampled from `seed`, whose states are valid within the bounds
// and free of collisions on `model` (`q`, of n entries, is the checker's buffer), its motions
// checked every `resolution` rad.
ob::SpaceInformationPtr make_space_info(const ob::RealVectorBounds& bounds, double resolution,
                                        std::uint32_t seed, CollisionModel& model,
                                        Eigen::VectorXd& q) {
  const int n = static_cast<int>(q.size());
  auto space = std::make_shared<ob::RealVectorStateSpace>(n);
  space->setBounds(bounds);
  space->setStateSamplerAllocator(
      [seed](const ob::StateSpace* s) { return std::make_shared<SeededSampler>(s, seed); });
  auto si = std::make_shared<ob::SpaceInformation>(space);
  ob::SpaceInformation* raw_si = si.get();
  si->setStateValidityChecker([&model, &q, n, raw_si](const ob::State* s) {
    const auto* rv = s->as<ob::RealVectorStateSpace::StateType>();
    for (int i = 0; i < n; ++i) q[i] = rv->values[i];
    return raw_si->satisfiesBounds(s) && !model.in_collision(q);
  });
  // (OMPL takes a fraction of the space's extent, below 1)
  si->setStateValidityCheckingResolution(std::min(0.5, resolution / space->getMaximumExtent()));
  si->setup();
  return si;
}

// Two motion-check resolutions: `coarse` for the search and the shortening, `fine`
// (options.resolution) for the path returned; each its own state space, as OMPL keeps the
// resolution in the space (its states are alike: either space checks the other's paths).
struct Spaces {
  ob::SpaceInformationPtr fine, coarse;
  bool two_pass = false;  // coarse is not fine
};

// The fine and the coarse space of a plan() call on `model` (coarse is fine when
// options.coarse_resolution is not above options.resolution).
Spaces make_spaces(CollisionModel& model, const TransitOptions& o, Eigen::VectorXd& q) {
  const ob::RealVectorBounds bounds = joint_bounds(model.kinematics());
  Spaces s;
  s.fine = make_space_info(bounds, o.resolution, o.seed, model, q);
  s.two_pass = o.coarse_resolution > o.resolution;
  s.coarse = s.two_pass ? make_space_info(bounds, o.coarse_resolution, o.seed, model, q) : s.fine;
  return s;
}

// True if every edge of `p` passes the check at `fine`'s resolution (its vertices were checked
// by the search).
bool fine_ok(const ob::SpaceInformationPtr& fine, const og::PathGeometric& p) {
  for (size_t k = 0; k + 1 < p.getStateCount(); ++k)
    if (!fine->checkMotion(p.getState(k), p.getState(k + 1))) return false;
  return true;
}

// Shorten `path` at `si`'s resolution with bounded work, in slices that stop at the time limit
// (no smoothing, which would add vertices where the trajectory stops): drop needless vertices,
// up to shortcut_rounds x 10 shortcut attempts (fewer once shortcut_patience rounds in a row
// changed nothing), drop again.
void shorten_path(const ob::SpaceInformationPtr& si, const TransitOptions& o,
                  const Deadline& deadline, og::PathGeometric& path) {
  og::PathSimplifier simplifier(si);
  if (deadline.left() > 0) simplifier.reduceVertices(path);
  int stalled = 0;
  for (int k = 0; k < o.shortcut_rounds && deadline.left() > 0; ++k) {
    stalled = simplifier.shortcutPath(path, 10) ? 0 : stalled + 1;
    if (o.shortcut_patience > 0 && stalled >= o.shortcut_patience) break;
  }
  if (deadline.left() > 0) simplifier.reduceVertices(path);
}

// What a search is for: the end points, the options and the call's deadline.
struct Query {
  const Eigen::Ref<const Eigen::VectorXd>& q_start;
  const Eigen::Ref<const Eigen::VectorXd>& q_goal;
  const TransitOptions& o;
  const Deadline& deadline;
};

// Search with RRT-Connect (until 90 % of the time left) and shorten (if options.shorten) at
// `si`'s resolution: the planner's path into `raw`, the shortened one into `path`; false: no
// path (`st` says why).
bool search(const ob::SpaceInformationPtr& si, const Query& query, og::PathGeometric& raw,
            og::PathGeometric& path, ob::PlannerStatus& st) {
  const int n = static_cast<int>(query.q_start.size());
  ob::ScopedState<ob::RealVectorStateSpace> start(si), goal(si);
  for (int i = 0; i < n; ++i) start[i] = query.q_start[i], goal[i] = query.q_goal[i];
  auto pdef = std::make_shared<ob::ProblemDefinition>(si);
  pdef->setStartAndGoalStates(start, goal);
  auto planner = std::make_shared<og::RRTConnect>(si);
  planner->setProblemDefinition(pdef);
  planner->setup();
  st = planner->solve(ob::timedPlannerTerminationCondition(0.9 * query.deadline.left()));
  if (st != ob::PlannerStatus::EXACT_SOLUTION) return false;
  raw = *pdef->getSolutionPath()->as<og::PathGeometric>();
  path = raw;
  if (query.o.shorten) shorten_path(si, query.o, query.deadline, path);
  return true;
}

// A path whose every edge passes the fine check into `path`; false: none (`st` says why).
// The shortened path's new edges are checked at other points than the planner's, and a
// coarse search's edges only coarsely: keep the first of the shortened path and the
// planner's own path whose every edge passes the fine check, else search again finely.
bool find_path(const Spaces& sp, const Query& query, og::PathGeometric& path,
               ob::PlannerStatus& st) {
  const bool shorten = query.o.shorten;
  og::PathGeometric raw(sp.fine);
  bool found = search(sp.coarse, query, raw, path, st);
  if (found && (sp.two_pass || shorten) && !fine_ok(sp.fine, path)) {
    const bool raw_ok = !sp.two_pass || (shorten && fine_ok(sp.fine, raw));
    path = raw;
    if (!raw_ok) {
      found = search(sp.fine, query, raw, path, st);
      if (found && shorten && !fine_ok(sp.fine, path)) path = raw;
    }
  }
  return found;
}

// The message of a search that found no path.
std::string no_path_message(const TransitOptions& o, const ob::PlannerStatus& st) {
  std::ostringstream ss;
  ss << "no collision-free path found within the time limit of " << o.time_limit << " s ("
     << st.asString() << ")";
  return ss.str();
}

// The vertices of `path` as res.waypoints (m, n), and their joint-space length res.path_length.
void store_waypoints(const og::PathGeometric& path, int n, TransitResult& res) {
  res.waypoints.resize(path.getStateCount(), n);
  for (size_t k = 0; k < path.getStateCount(); ++k) {
    const auto* rv = path.getState(k)->as<ob::RealVectorStateSpace::StateType>();
    for (int i = 0; i < n; ++i) res.waypoints(k, i) = rv->values[i];
  }
  res.path_length = 0;
  for (Eigen::Index k = 0; k + 1 < res.waypoints.rows(); ++k)
    res.path_length += (res.waypoints.row(k + 1) - res.waypoints.row(k)).norm();
}
}  // namespace

struct TransitPlanner::Impl {
  CollisionModel model;
};

TransitPlanner::TransitPlanner(CollisionModel model) : impl_(std::make_unique<Impl>()) {
  impl_->model = std::move(model);
}
TransitPlanner::~TransitPlanner() = default;
TransitPlanner::TransitPlanner(TransitPlanner&&) noexcept = default;
TransitPlanner& TransitPlanner::operator=(TransitPlanner&&) noexcept = default;

CollisionModel& TransitPlanner::model() noexcept { return impl_->model; }

TransitResult TransitPlanner::plan(const Eigen::Ref<const Eigen::VectorXd>& q_start,
                                   const Eigen::Ref<const Eigen::VectorXd>& q_goal,
                                   const TransitOptions& o) {
  const Deadline deadline{Deadline::clock::now(), o.time_limit};
  TransitResult res;
  CollisionModel& model = impl_->model;
  const long long checks0 = model.loaded() ? model.checks() : 0;
  auto finish = [&](TransitStatus s, std::string msg) {
    res.status = s;
    res.message = std::move(msg);
    res.planning_time = deadline.elapsed();
    res.collision_checks = model.loaded() ? model.checks() - checks0 : 0;
    return res;
  };
  Verdict verdict = check_request(model, q_start, q_goal, o);
  if (verdict.status != TransitStatus::ok)
    return finish(verdict.status, std::move(verdict.message));

  const Kinematics& kin = model.kinematics();
  const int n = kin.n_joints();
  seed_ompl_once(o.seed);
  Eigen::VectorXd q(n);  // the validity checkers' buffer
  const Spaces spaces = make_spaces(model, o, q);
  og::PathGeometric path(spaces.fine);
  ob::PlannerStatus st;
  if (!find_path(spaces, Query{q_start, q_goal, o, deadline}, path, st)) {
    return finish(TransitStatus::no_path, no_path_message(o, st));
  }
  store_waypoints(path, n, res);
  Eigen::VectorXd vel, acc;
  detail::trajectory_limits(kin, o, vel, acc);
  const Result r = time_parameterize(res.waypoints, vel, acc, o.sample_period, res);
  if (!r.ok()) return finish(TransitStatus::invalid_argument, r.message);
  return finish(TransitStatus::ok, "");
}

#endif  // A2L_HAVE_BULLET && A2L_HAVE_OMPL

}  // namespace a2l
