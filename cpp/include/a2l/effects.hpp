//! \file effects.hpp
//! \brief The effect vocabulary, one definition for the core, a2l-run and Python (a2l._core):
//! the push effects' names in index order, the classification of an object displacement into
//! them, and the effect tests (push, away) with their constants.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace a2l {

//! Most push effects: the 4 axis effects, then the 4 diagonals.
constexpr int kMaxPushEffects = 8;
//! Default smallest planar displacement that counts as an effect (m).
constexpr double kEffectThreshold = 0.01;
//! Default dominance ratio of an axis effect with 8 effects.
constexpr double kEffectRatio = 3.0;
//! `grasped`: the object held at least this high above where it started (m).
constexpr double kLiftThreshold = 0.05;
//! Push test: the produced displacement that ends a push, along or across its direction (m).
constexpr double kPushDistance = 0.05;
//! `away`: largest distance of the end-effector from the retreat pose (m).
constexpr double kAwayRadius = 0.04;
//! `away`: largest displacement of the object (m).
constexpr double kAwayTolerance = 0.01;

//! `away`: where the end-effector waits, relative to the object (m): back and up (x, y, z).
Eigen::Vector3d retreat_offset() noexcept;

//! Name of push effect `index` in classify_effect's order: 0 left (+y), 1 right (-y),
//! 2 close (-x), 3 far (+x), 4 close_left, 5 close_right, 6 far_left, 7 far_right;
//! "none" for any other index (-1: no effect).
const char* effect_name(int index) noexcept;

//! Names of the `n_effects` (4 or 8) push effects in index order; empty for another count.
std::vector<std::string> effect_names(int n_effects);

//! Index of the push effect named `name` among the 8, or -1.
int effect_index(const std::string& name) noexcept;

//! Planar direction (x, y) the object moves for push effect `index` (unit for an axis
//! effect, (+-1, +-1) for a diagonal); zero for an index outside [0, 8).
Eigen::Vector2d effect_direction(int index) noexcept;

//! Effect index of an object displacement, as a2l.skills.EffectDiscretizer: with 4 effects
//! (left = +y, right = -y, close = -x, far = +x, in this order) the dominant planar axis
//! decides; with 8, an axis effect needs that axis to move more than `ratio` times the
//! other, else it is a diagonal (4 close_left, 5 close_right, 6 far_left, 7 far_right).
//! Real-time safe.
//! \return the index, or -1 if the planar displacement is shorter than `threshold` (m) or
//!         not finite, or n_effects is neither 4 nor 8.
int classify_effect(const Eigen::Vector3d& displacement, int n_effects = 4,
                    double threshold = kEffectThreshold, double ratio = kEffectRatio) noexcept;

//! The outcome of an effect test so far: `done` ends the run, `success` says how.
struct TestOutcome {
  bool done = false;     //!< the test has decided
  bool success = false;  //!< the effect was produced (meaningful once done)
};

//! The push test of axis effect `index` (0..3): done when the produced planar displacement
//! reaches `distance` along the effect's direction (success when that axis dominates: along
//! > across) or `distance` across it (failure). Not done for another index. Real-time safe.
TestOutcome push_test(const Eigen::Vector2d& produced, int index,
                      double distance = kPushDistance) noexcept;

//! The `away` test (the light-on behaviour of grasp_light, a "hot stove"): the end-effector
//! is within `radius` of `object + retreat` and the object moved (`moved`: its displacement,
//! as the caller counts it) less than `tolerance`. False when a value is not finite.
//! Real-time safe.
bool stayed_away(const Eigen::Vector3d& eef, const Eigen::Vector3d& object,
                 const Eigen::Vector3d& moved, const Eigen::Vector3d& retreat = retreat_offset(),
                 double radius = kAwayRadius, double tolerance = kAwayTolerance) noexcept;

}  // namespace a2l
