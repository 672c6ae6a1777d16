// Test helper: build skill bundle bytes in C++ (docs/bundle_format.md), to test the loader
// and the runtime without Python. Not a test file itself (no test_ prefix).
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "a2l/bundle.hpp"
#include "a2l/skill.hpp"

namespace a2l::testing {

using json = nlohmann::json;

//! The parts of a bundle before serialisation.
struct BundleParts {
  json manifest;                    //!< without "arrays" (filled by build())
  std::vector<std::int64_t> shape;  //!< evidence bins
  int n_moves = 0;
  std::vector<double> posterior;
  std::vector<std::int32_t> argmax;
};

inline std::size_t rows_of(const std::vector<std::int64_t>& shape) {
  std::size_t r = 1;
  for (auto s : shape) r *= static_cast<std::size_t>(s);
  return r;
}

//! A skill with effect(4), distance(3), orientation(8), inclination(4), light(2) and the 8
//! planar movements; random posteriors, about `uniform_share` of the rows uniform (argmax -1).
inline BundleParts sample_parts(std::uint64_t seed = 1, double uniform_share = 0.2,
                                bool smoothing = false) {
  BundleParts p;
  p.manifest = {
      {"schema_version", kBundleSchemaVersion},
      {"kind", "skill"},
      {"name", "push"},
      {"created_by", "a2l tests"},
      {"robot", nullptr},
      {"target", "move"},
      {"variables",
       json::array(
           {{{"name", "effect"}, {"kind", "effect"}, {"values", {"left", "right", "close", "far"}}},
            {{"name", "distance"},
             {"kind", "distance"},
             {"n_bins", 3},
             {"low", 0.05},
             {"high", 0.20}},
            {{"name", "orientation"}, {"kind", "orientation"}, {"n_bins", 8}},
            {{"name", "inclination"}, {"kind", "inclination"}, {"n_bins", 4}},
            {{"name", "light"}, {"kind", "high_level"}, {"values", {"off", "on"}}}})},
      {"movements",
       {{"step", 0.05},
        {"directions",
         {{1, 0, 0},
          {-1, 0, 0},
          {0, 1, 0},
          {0, -1, 0},
          {1, 1, 0},
          {1, -1, 0},
          {-1, 1, 0},
          {-1, -1, 0}}},
        {"labels", {"+x", "-x", "+y", "-y", "+x+y", "+x-y", "-x+y", "-x-y"}},
        {"actions", json::array()}}},
      {"execution", {{"step_cap", 12}, {"smoothing", smoothing}, {"uniform_tolerance", 1e-9}}},
      {"extra", {{"note", "unknown keys are ignored"}}}};
  p.shape = {4, 3, 8, 4, 2};
  p.n_moves = 8;
  const std::size_t rows = rows_of(p.shape);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  p.posterior.resize(rows * static_cast<std::size_t>(p.n_moves));
  p.argmax.resize(rows);
  for (std::size_t r = 0; r < rows; ++r) {
    double* row = p.posterior.data() + r * static_cast<std::size_t>(p.n_moves);
    if (u(rng) < uniform_share) {
      for (int m = 0; m < p.n_moves; ++m) row[m] = 1.0 / p.n_moves;
      p.argmax[r] = -1;
      continue;
    }
    double sum = 0.0;
    for (int m = 0; m < p.n_moves; ++m) sum += (row[m] = std::pow(u(rng), 3.0) + 1e-3);
    int best = 0;
    for (int m = 0; m < p.n_moves; ++m) {
      row[m] /= sum;
      if (row[m] > row[best]) best = m;
    }
    p.argmax[r] = best;
  }
  return p;
}

//! The header and the manifest `text` (any bytes, JSON or not) of a bundle, padded with zeros
//! to 8 bytes: its blob follows. The header gives `header_version`, the manifest's length and
//! its CRC-32, and a zero reserved field.
inline std::vector<std::uint8_t> frame(const std::string& text,
                                       std::uint32_t header_version = kBundleSchemaVersion) {
  std::vector<std::uint8_t> out(24, 0);
  std::memcpy(out.data(), kBundleMagic, 8);
  auto put = [&](std::size_t at, std::uint32_t v) {
    for (int i = 0; i < 4; ++i)
      out[at + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(v >> (8 * i));
  };
  put(8, header_version);
  put(12, static_cast<std::uint32_t>(text.size()));
  put(16, bundle_crc32(text.data(), text.size()));
  out.insert(out.end(), text.begin(), text.end());
  out.resize((out.size() + 7) / 8 * 8, 0);
  return out;
}

//! Serialise `p`. The "arrays" entry is computed (offsets, nbytes, CRCs) and then patched with
//! `arrays_patch` (JSON merge patch) so that tests can corrupt it.
inline std::vector<std::uint8_t> build(const BundleParts& p, const json& arrays_patch = json(),
                                       std::uint32_t header_version = kBundleSchemaVersion) {
  json m = p.manifest;
  std::vector<std::int64_t> pshape = p.shape;
  pshape.push_back(p.n_moves);
  const std::size_t post_bytes = p.posterior.size() * 8, amax_bytes = p.argmax.size() * 4;
  const std::size_t amax_off = (post_bytes + 7) / 8 * 8;
  m["arrays"] = {{"posterior",
                  {{"dtype", "float64"},
                   {"shape", pshape},
                   {"offset", 0},
                   {"nbytes", post_bytes},
                   {"crc32", bundle_crc32(p.posterior.data(), post_bytes)}}},
                 {"argmax",
                  {{"dtype", "int32"},
                   {"shape", p.shape},
                   {"offset", amax_off},
                   {"nbytes", amax_bytes},
                   {"crc32", bundle_crc32(p.argmax.data(), amax_bytes)}}}};
  if (!arrays_patch.is_null()) m["arrays"].merge_patch(arrays_patch);
  std::vector<std::uint8_t> out = frame(m.dump(), header_version);
  const std::size_t blob = out.size();
  out.resize(blob + amax_off + amax_bytes, 0);
  std::memcpy(out.data() + blob, p.posterior.data(), post_bytes);
  std::memcpy(out.data() + blob + amax_off, p.argmax.data(), amax_bytes);
  return out;
}

//! One array of a bundle before serialisation.
struct Array {
  std::string name, dtype;
  std::vector<std::int64_t> shape;
  std::vector<std::uint8_t> bytes;
};

//! An Array holding the bytes of `v`.
template <typename T>
inline Array array_of(const std::string& name, const char* dtype, std::vector<std::int64_t> shape,
                      const std::vector<T>& v) {
  Array a{name, dtype, std::move(shape), std::vector<std::uint8_t>(v.size() * sizeof(T))};
  if (!v.empty()) std::memcpy(a.bytes.data(), v.data(), a.bytes.size());
  return a;
}

// Serialise a manifest and arrays (offsets, nbytes and CRCs computed, then `patch` merged into
// "arrays" so that tests can corrupt it).
inline std::vector<std::uint8_t> serialise(json m, const std::vector<Array>& arrays,
                                           const json& patch = json()) {
  std::size_t off = 0;
  m["arrays"] = json::object();
  for (const Array& a : arrays) {
    off = (off + 7) / 8 * 8;
    m["arrays"][a.name] = {{"dtype", a.dtype},
                           {"shape", a.shape},
                           {"offset", off},
                           {"nbytes", a.bytes.size()},
                           {"crc32", bundle_crc32(a.bytes.data(), a.bytes.size())}};
    off += a.bytes.size();
  }
  if (!patch.is_null()) m["arrays"].merge_patch(patch);
  std::vector<std::uint8_t> out = frame(m.dump());
  const std::size_t blob = out.size();
  off = 0;
  for (const Array& a : arrays) {
    off = (off + 7) / 8 * 8;
    out.resize(blob + off, 0);
    out.insert(out.end(), a.bytes.begin(), a.bytes.end());
    off += a.bytes.size();
  }
  return out;
}

//! The skill of bundle `p` (built with build()), loaded from memory; a load that fails is a
//! test failure with the loader's message.
inline a2l::Skill load_skill(const BundleParts& p) {
  const auto bytes = build(p);
  a2l::Skill s;
  const a2l::Result r = a2l::load_bundle_from_memory(bytes.data(), bytes.size(), s, "test");
  EXPECT_TRUE(r.ok()) << r.message;
  return s;
}

//! A context for sample_parts() skills: the object at (0.7, 0, 0.04), the end-effector at
//! most `half` (m) from it along x and y and `z_low`..`z_high` above it, one of the four push
//! effects and the light (high-level variable 4), all drawn from `rng`.
inline a2l::Context random_push_context(std::mt19937_64& rng, double half, double z_low = 0.0,
                                        double z_high = 0.0) {
  std::uniform_real_distribution<double> coord(-half, half), z(z_low, z_high);
  std::uniform_int_distribution<int> effect(0, 3), light(0, 1);
  a2l::Context c;
  c.object = {0.7, 0.0, 0.04};
  const double x = coord(rng), y = coord(rng);
  c.eef = c.object + Eigen::Vector3d(x, y, z_high > z_low ? z(rng) : z_low);
  c.effect = effect(rng);
  c.high_level[4] = light(rng);
  return c;
}

//! One step of `a` and one of `b`, each from a fresh state, in context `c` (into `oa` and
//! `ob`); the two statuses must be the same (a test failure otherwise). Whether both gave a
//! movement (`ok`).
inline bool step_both(const a2l::Skill& a, const a2l::Skill& b, const a2l::Context& c,
                      a2l::StepOutput& oa, a2l::StepOutput& ob) {
  a2l::SkillState sa(a), sb(b);
  const a2l::Status st_a = a2l::step(a, sa, c, oa), st_b = a2l::step(b, sb, c, ob);
  EXPECT_EQ(st_a, st_b);
  return st_a == a2l::Status::ok && st_b == a2l::Status::ok;
}

//! `a` and `b` answer each of `n` random contexts (eef within 0.25 m of the object in the
//! table plane, the four push effects in turn) with the same status, movement and
//! probability: a rule that is off changes nothing.
inline void expect_same_answers(const a2l::Skill& a, const a2l::Skill& b, int n = 2000) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> coord(-0.25, 0.25);
  for (int i = 0; i < n; ++i) {
    a2l::Context c;
    c.object = {0.7, 0.0, 0.04};
    c.eef = c.object + Eigen::Vector3d(coord(rng), coord(rng), 0.0);
    c.effect = i % 4;
    a2l::StepOutput oa, ob;
    step_both(a, b, c, oa, ob);
    EXPECT_EQ(oa.movement, ob.movement) << "context " << i;
    EXPECT_EQ(oa.probability, ob.probability) << "context " << i;
  }
}

//! Each of `bad` as the value of `execution.<key>` in sample_parts(): loading is a
//! parse_error whose message names the key.
inline void expect_execution_refused(const std::string& key, const std::vector<json>& bad) {
  for (const json& value : bad) {
    BundleParts p = sample_parts();
    p.manifest["execution"][key] = value;
    const auto bytes = build(p);
    a2l::Skill s;
    const a2l::Result r = a2l::load_bundle_from_memory(bytes.data(), bytes.size(), s, "test");
    EXPECT_EQ(r.status, a2l::Status::parse_error) << key << " = " << value;
    EXPECT_NE(r.message.find("execution." + key), std::string::npos) << r.message;
  }
}

}  // namespace a2l::testing
