// a2l-run's helpers outside the loop: the URDF, start points, percentiles (internal).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "a2l/skill.hpp"
#include "options.hpp"

namespace a2l_run {

//! Baxter's URDF: $A2L_ROBOTS_DIR, else the example-robot-data of the venv holding a2l-run;
//! "" if none (`tried` lists the paths tried).
std::string find_baxter_urdf(std::string& tried);

//! Percentiles of a sample (us).
struct Percentiles {
  double p50 = 0, p90 = 0, p99 = 0, p999 = 0, max = 0, mean = 0;
  std::size_t n = 0;
};

//! The percentiles of `v`.
Percentiles percentiles(std::vector<double> v);

//! As the summary's JSON.
nlohmann::json to_json(const Percentiles& p);

//! The bundle's URDF hash against the URDF loaded: 0 if they agree (or the bundle names no
//! URDF), else 2 after a message naming both hashes.
int check_urdf_hash(const a2l::Skill& skill, const std::string& bundle, const std::string& urdf,
                    std::string& urdf_hash);

//! The episodes' start points around `object`, the same for every effect (see --starts).
std::vector<Eigen::Vector3d> start_points(const Args& args, const Eigen::Vector3d& object);

//! How the start points were drawn, for a human.
std::string describe_starts(const Args& args);

}  // namespace a2l_run
