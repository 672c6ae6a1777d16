// The DS section of a bundle (docs/bundle_format.md, "ds"): a DS-only bundle and a skill
// with a DS load; the loader refuses a map breaking the invertibility bound, non-finite
// values, wrong dimensions, shapes, checksums and overlaps, naming the map's index or the
// field.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <random>

#include "a2l/bundle.hpp"
#include "a2l/diffeo.hpp"
#include "bundle_builder.hpp"

namespace test_bundle_ds {

using a2l::DiffeoMaps;
using a2l::Status;
using a2l::testing::Array;
using a2l::testing::array_of;
using a2l::testing::json;
using a2l::testing::serialise;

// The DS part of a bundle before serialisation.
struct DsParts {
  json ds;  // the manifest's "ds" entry
  std::vector<double> centers, vectors, rhos;
  std::vector<std::int64_t> kd, k;  // array shapes
};

DsParts sample_ds(int d = 2, int k = 12, std::uint64_t seed = 5) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), mu(0.2, 0.9);
  DsParts p;
  std::vector<double> target;
  for (int j = 0; j < d; ++j) target.push_back(0.1 * u(rng));
  p.ds = {{"dim", d}, {"n_maps", k}, {"speed", 1.5}, {"direction", "to_demo"}, {"target", target}};
  for (int i = 0; i < k; ++i) {
    double n2 = 0.0;
    for (int j = 0; j < d; ++j) {
      p.centers.push_back(u(rng));
      p.vectors.push_back(0.3 * u(rng));
      n2 += p.vectors.back() * p.vectors.back();
    }
    p.rhos.push_back(mu(rng) * a2l::kDiffeoInvertibilityBound / std::sqrt(n2));
  }
  p.kd = {k, d};
  p.k = {k};
  return p;
}

std::vector<Array> ds_arrays(const DsParts& p) {
  return {array_of("ds_centers", "float64", p.kd, p.centers),
          array_of("ds_vectors", "float64", p.kd, p.vectors),
          array_of("ds_rhos", "float64", p.k, p.rhos)};
}

// The manifest of a DS-only bundle, without "arrays".
json ds_manifest(const DsParts& p) {
  return {{"schema_version", a2l::kBundleSchemaVersion},
          {"kind", "ds"},
          {"name", "reach"},
          {"created_by", "a2l tests"},
          {"ds", p.ds}};
}

std::vector<std::uint8_t> ds_bundle(const DsParts& p, const json& patch = json(),
                                    const std::function<void(json&)>& edit = nullptr) {
  json m = ds_manifest(p);
  if (edit) edit(m);
  return serialise(m, ds_arrays(p), patch);
}

// A skill bundle with a DS beside its table.
std::vector<std::uint8_t> skill_with_ds(const DsParts& p) {
  const a2l::testing::BundleParts s = a2l::testing::sample_parts();
  json m = s.manifest;
  m["ds"] = p.ds;
  std::vector<std::int64_t> pshape = s.shape;
  pshape.push_back(s.n_moves);
  std::vector<Array> arrays = {array_of("posterior", "float64", pshape, s.posterior),
                               array_of("argmax", "int32", s.shape, s.argmax)};
  for (Array& a : ds_arrays(p)) arrays.push_back(std::move(a));
  return serialise(m, arrays);
}

a2l::Result load_ds(const std::vector<std::uint8_t>& b, DiffeoMaps& out) {
  return a2l::load_ds_bundle_from_memory(b.data(), b.size(), out, "ds.a2lb");
}

void expect_error(const std::vector<std::uint8_t>& b, Status status, const std::string& needle) {
  DiffeoMaps m;
  m.dim = 42;
  const a2l::Result r = load_ds(b, m);
  EXPECT_EQ(r.status, status) << r.message;
  EXPECT_NE(r.message.find(needle), std::string::npos)
      << "message '" << r.message << "' does not name '" << needle << "'";
  EXPECT_NE(r.message.find("ds.a2lb"), std::string::npos) << r.message;
  EXPECT_EQ(m.dim, 42) << "out must stay untouched on failure";
}

TEST(BundleDs, DsOnlyBundleLoads) {
  for (int d : {2, 3}) {
    const DsParts p = sample_ds(d, 17);
    const auto b = ds_bundle(p);
    DiffeoMaps m;
    const a2l::Result r = load_ds(b, m);
    ASSERT_TRUE(r.ok()) << r.message;
    EXPECT_EQ(m.dim, d);
    EXPECT_EQ(m.n_maps(), 17);
    EXPECT_EQ(m.centers, p.centers);
    EXPECT_EQ(m.vectors, p.vectors);
    EXPECT_EQ(m.rhos, p.rhos);
    EXPECT_EQ(m.speed, 1.5);
    EXPECT_EQ(m.direction, a2l::DiffeoDirection::to_demo);
    EXPECT_EQ(m.target, p.ds["target"].get<std::vector<double>>());
    // a DS-only bundle is not a skill
    a2l::Skill s;
    const a2l::Result rs = a2l::load_bundle_from_memory(b.data(), b.size(), s, "ds.a2lb");
    EXPECT_EQ(rs.status, Status::parse_error);
    EXPECT_NE(rs.message.find("kind: 'ds'"), std::string::npos) << rs.message;
  }
  // from a file, and a DS with no maps (the linear system)
  const std::string path = ::testing::TempDir() + "/a2l_test_ds.a2lb";
  {
    const auto b = ds_bundle(sample_ds(2, 0));
    std::ofstream f(path, std::ios::binary);
    f.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
  }
  DiffeoMaps m;
  ASSERT_TRUE(a2l::load_ds_bundle(path, m).ok());
  EXPECT_EQ(m.n_maps(), 0);
  std::remove(path.c_str());
  EXPECT_EQ(a2l::load_ds_bundle("/nonexistent/ds.a2lb", m).status, Status::file_error);
}

TEST(BundleDs, SkillWithDsLoadsBoth) {
  const DsParts p = sample_ds(3, 9);
  const auto b = skill_with_ds(p);
  a2l::Skill s;
  const a2l::Result r = a2l::load_bundle_from_memory(b.data(), b.size(), s);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(s.n_moves(), 8);
  DiffeoMaps m;
  ASSERT_TRUE(load_ds(b, m).ok());
  EXPECT_EQ(m.rhos, p.rhos);
  // a skill without a DS has none to load
  const auto plain = a2l::testing::build(a2l::testing::sample_parts());
  expect_error(plain, Status::parse_error, "ds: missing");
}

TEST(BundleDs, MapBreakingTheBoundIsRefusedByIndex) {
  DsParts p = sample_ds(2, 12);
  const double l7 = std::hypot(p.vectors[14], p.vectors[15]);
  p.rhos[7] = 1.0001 * a2l::kDiffeoInvertibilityBound / l7;
  expect_error(ds_bundle(p), Status::parse_error, "map 7: rho * ||v||");
  expect_error(ds_bundle(p), Status::parse_error, "sqrt(e/2)");
  // the skill loader refuses a skill whose DS is bad, too
  const auto b = skill_with_ds(p);
  a2l::Skill s;
  const a2l::Result r = a2l::load_bundle_from_memory(b.data(), b.size(), s);
  EXPECT_EQ(r.status, Status::parse_error);
  EXPECT_NE(r.message.find("map 7"), std::string::npos) << r.message;
  p = sample_ds(2, 12);
  p.rhos[3] = -0.5;
  expect_error(ds_bundle(p), Status::parse_error, "map 3: rho = -0.5 < 0");
}

TEST(BundleDs, NonFiniteValuesAreRefused) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  DsParts p = sample_ds(2, 12);
  p.centers[7] = nan;
  expect_error(ds_bundle(p), Status::parse_error, "map 3: center is not finite");
  p = sample_ds(2, 12);
  p.vectors[22] = std::numeric_limits<double>::infinity();
  expect_error(ds_bundle(p), Status::parse_error, "map 11: vector is not finite");
  p = sample_ds(2, 12);
  p.rhos[0] = nan;
  expect_error(ds_bundle(p), Status::parse_error, "map 0: rho is not finite");
  p = sample_ds(2, 12);
  p.ds["target"][1] = nan;  // JSON has no NaN: written as null
  expect_error(ds_bundle(p), Status::parse_error, "ds.target[1]: must be a number");
  p = sample_ds(2, 12);
  p.ds["speed"] = 0.0;
  expect_error(ds_bundle(p), Status::parse_error, "ds.speed: must be > 0");
  p.ds["speed"] = "fast";
  expect_error(ds_bundle(p), Status::parse_error, "ds.speed: must be a number");
  p = sample_ds(2, 12);
  p.ds["direction"] = "backwards";
  expect_error(ds_bundle(p), Status::parse_error,
               "ds.direction: must be \"to_demo\" or \"to_line\", got \"backwards\"");
  p.ds["direction"] = 1;
  expect_error(ds_bundle(p), Status::parse_error, "ds.direction: must be a string");
}

TEST(BundleDs, DirectionToLineLoadsAndBuildsTheDs) {
  DsParts p = sample_ds(2, 10);
  p.ds["direction"] = "to_line";
  DiffeoMaps m;
  ASSERT_TRUE(load_ds(ds_bundle(p), m).ok());
  EXPECT_EQ(m.direction, a2l::DiffeoDirection::to_line);
  a2l::DiffeoDS<2> ds;
  ASSERT_TRUE(a2l::DiffeoDS<2>::create(m, ds).ok());
  EXPECT_EQ(ds.direction(), a2l::DiffeoDirection::to_line);
  EXPECT_EQ(ds.maps().direction, a2l::DiffeoDirection::to_line);
  // the bound is checked the same way in both directions
  p.rhos[4] = 1.01 * a2l::kDiffeoInvertibilityBound / std::hypot(p.vectors[8], p.vectors[9]);
  expect_error(ds_bundle(p), Status::parse_error, "map 4: rho * ||v||");
}

TEST(BundleDs, WrongDimensionsAndShapesAreRefused) {
  DsParts p = sample_ds(2, 12);
  p.ds["dim"] = 4;
  expect_error(ds_bundle(p), Status::parse_error, "ds.dim: 4 is outside [2, 3]");
  p = sample_ds(2, 12);
  p.ds["dim"] = 3;  // target has 2 coordinates
  expect_error(ds_bundle(p), Status::parse_error, "ds.target: has 2 coordinates, ds.dim is 3");
  p = sample_ds(2, 12);
  p.ds["n_maps"] = 11;
  expect_error(ds_bundle(p), Status::parse_error, "arrays.ds_centers.shape");
  p = sample_ds(2, 12);
  p.k = {11};
  p.rhos.pop_back();
  expect_error(ds_bundle(p), Status::parse_error, "arrays.ds_rhos.shape");
  p = sample_ds(2, 12);
  p.kd = {12, 3};
  p.vectors.resize(36, 0.0);
  p.centers.resize(36, 0.0);
  expect_error(ds_bundle(p), Status::parse_error, "arrays.ds_centers.shape");
  p = sample_ds(2, 12);
  p.ds["n_maps"] = -1;
  expect_error(ds_bundle(p), Status::parse_error, "ds.n_maps");
  expect_error(ds_bundle(sample_ds(), {{"ds_vectors", {{"dtype", "float32"}}}}),
               Status::parse_error, "arrays.ds_vectors.dtype");
  expect_error(ds_bundle(sample_ds(), {{"ds_rhos", {{"nbytes", 8}}}}), Status::parse_error,
               "arrays.ds_rhos.nbytes");
}

TEST(BundleDs, MissingKeysAreNamed) {
  for (const char* key : {"dim", "n_maps", "speed", "direction", "target"}) {
    DsParts p = sample_ds();
    p.ds.erase(key);
    expect_error(ds_bundle(p), Status::parse_error, std::string("ds.") + key + ": missing");
  }
  expect_error(ds_bundle(sample_ds(), json(), [](json& m) { m.erase("ds"); }), Status::parse_error,
               "ds: missing");
  expect_error(ds_bundle(sample_ds(), json(), [](json& m) { m["ds"] = 3; }), Status::parse_error,
               "ds: must be an object");
  for (const char* name : {"ds_centers", "ds_vectors", "ds_rhos"}) {
    expect_error(ds_bundle(sample_ds(), {{name, nullptr}}), Status::parse_error,
                 std::string("arrays.") + name + ": missing");
  }
  expect_error(ds_bundle(sample_ds(), json(), [](json& m) { m["kind"] = "policy"; }),
               Status::parse_error, "kind: must be 'skill' or 'ds'");
}

TEST(BundleDs, ArraysMissingOrNotAnObject) {
  // a DS-only manifest reaches "arrays" by another way than a skill's
  expect_error(a2l::testing::frame(ds_manifest(sample_ds()).dump()), Status::parse_error,
               "arrays: missing");
  expect_error(ds_bundle(sample_ds(), json::array()), Status::parse_error,
               "arrays: must be an object, got array");
  expect_error(ds_bundle(sample_ds(), json("ds_centers")), Status::parse_error,
               "arrays: must be an object, got string");
}

TEST(BundleDs, CorruptionIsDetected) {
  auto b = ds_bundle(sample_ds(2, 12));
  b[b.size() - 3] ^= 0x20;  // inside ds_rhos
  expect_error(b, Status::checksum_mismatch, "arrays.ds_rhos.crc32");
  expect_error(ds_bundle(sample_ds(2, 12), {{"ds_vectors", {{"offset", 0}}}}), Status::parse_error,
               "overlap");
  b = ds_bundle(sample_ds(2, 12));
  b.push_back(0);
  expect_error(b, Status::parse_error, "trailing bytes");
  // every truncation fails cleanly, named: "truncated" (before the header, the manifest's end,
  // the blob or an array's end), or an array's nbytes "larger than the file"
  b = ds_bundle(sample_ds(3, 5));
  for (std::size_t n = 0; n < b.size(); n += 7) {
    DiffeoMaps m;
    const a2l::Result r = a2l::load_ds_bundle_from_memory(b.data(), n, m);
    EXPECT_EQ(r.status, Status::parse_error) << n << " bytes: " << r.message;
    EXPECT_EQ(r.message.rfind("skill bundle '<memory>': ", 0), 0u) << r.message;
    EXPECT_TRUE(r.message.find("truncated") != std::string::npos ||
                r.message.find("larger than the file") != std::string::npos)
        << n << " bytes: " << r.message;
  }
}

TEST(BundleDs, LoadedMapsBuildTheDs) {
  const DsParts p = sample_ds(3, 30);
  DiffeoMaps m;
  ASSERT_TRUE(load_ds(ds_bundle(p), m).ok());
  a2l::DiffeoDS<3> ds;
  ASSERT_TRUE(a2l::DiffeoDS<3>::create(m, ds).ok());
  EXPECT_EQ(ds.n_maps(), 30);
  const DiffeoMaps back = ds.maps();
  EXPECT_EQ(back.centers, m.centers);
  EXPECT_EQ(back.rhos, m.rhos);
  EXPECT_EQ(back.target, m.target);
}

}  // namespace test_bundle_ds
