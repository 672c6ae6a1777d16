// Bundle loading: a valid bundle loads; every corruption gives a clear error naming the field
// or the check (null data, truncation, the header's reserved field, padding, checksums,
// versions, a manifest not an object, shapes, keys, types, values, random bytes).
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <random>
#include <utility>
#include <vector>

#include "a2l/bundle.hpp"
#include "bundle_builder.hpp"

namespace test_bundle {

using a2l::Status;
using a2l::testing::build;
using a2l::testing::BundleParts;
using a2l::testing::json;
using a2l::testing::sample_parts;

a2l::Result load(const std::vector<std::uint8_t>& b) {
  a2l::Skill s;
  return a2l::load_bundle_from_memory(b.data(), b.size(), s, "corrupt.a2lb");
}

void expect_error(const a2l::Result& r, Status status, const std::string& needle) {
  EXPECT_EQ(r.status, status) << r.message;
  EXPECT_NE(r.message.find(needle), std::string::npos)
      << "message '" << r.message << "' does not name '" << needle << "'";
  EXPECT_NE(r.message.find("corrupt.a2lb"), std::string::npos) << r.message;
}

// Whether `message` is a loader's message about corrupt.a2lb naming one of `parts`.
::testing::AssertionResult names_one_of(const std::string& message,
                                        const std::vector<std::string>& parts) {
  const std::string prefix = "skill bundle 'corrupt.a2lb': ";
  if (message.rfind(prefix, 0) != 0 || message.size() == prefix.size()) {
    return ::testing::AssertionFailure() << "message '" << message << "' names nothing";
  }
  for (const std::string& part : parts) {
    if (message.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << "message '" << message << "' names none of the parts";
}

// The checks of a bundle's frame: header, manifest bytes, and the file's length.
const std::vector<std::string> kFrameChecks = {
    "truncated",       "magic",           "schema version", "header: reserved",
    "manifest length", "manifest CRC-32", "padding"};

// Parts with one manifest change (the arrays stay consistent).
std::vector<std::uint8_t> with(const std::function<void(json&)>& edit) {
  BundleParts p = sample_parts();
  edit(p.manifest);
  return build(p);
}

// The manifest length the header of bundle `b` gives.
std::uint32_t manifest_length(const std::vector<std::uint8_t>& b) {
  return b[12] | (b[13] << 8) | (b[14] << 16) | (static_cast<std::uint32_t>(b[15]) << 24);
}

// A valid bundle whose manifest does not end on 8 bytes (zero padding follows it), its
// manifest's end in `manifest_end` and its blob's offset in `blob`.
std::vector<std::uint8_t> padded_bundle(std::size_t& manifest_end, std::size_t& blob) {
  BundleParts p = sample_parts();
  std::vector<std::uint8_t> b = build(p);
  while (manifest_length(b) % 8 == 0) {
    p.manifest["name"] = p.manifest["name"].get<std::string>() + "x";
    b = build(p);
  }
  manifest_end = 24 + manifest_length(b);
  blob = (manifest_end + 7) / 8 * 8;
  return b;
}

TEST(Bundle, ValidBundleLoadsFromMemoryAndFile) {
  const auto b = build(sample_parts());
  a2l::Skill s;
  const a2l::Result r = a2l::load_bundle_from_memory(b.data(), b.size(), s);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(s.name(), "push");
  EXPECT_EQ(s.n_variables(), 5);
  EXPECT_EQ(s.n_moves(), 8);
  EXPECT_FALSE(s.robot().present);
  EXPECT_EQ(s.settings().step_cap, 12);
  const std::string path = ::testing::TempDir() + "/a2l_test_bundle.a2lb";
  {
    std::ofstream f(path, std::ios::binary);
    f.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
  }
  a2l::Skill s2;
  ASSERT_TRUE(a2l::load_bundle(path, s2).ok());
  EXPECT_EQ(s2.table().posterior(), s.table().posterior());
  std::remove(path.c_str());
}

TEST(Bundle, RobotEntryIsRead) {
  const auto b = with([](json& m) {
    m["robot"] = {{"name", "baxter"},
                  {"urdf_sha256", "ab"},
                  {"base_link", "base"},
                  {"tip_link", "right_gripper"}};
  });
  a2l::Skill s;
  ASSERT_TRUE(a2l::load_bundle_from_memory(b.data(), b.size(), s).ok());
  EXPECT_TRUE(s.robot().present);
  EXPECT_EQ(s.robot().tip_link, "right_gripper");
  expect_error(load(with([](json& m) {
                 m["robot"] = {{"x", 1}};
               })),
               Status::parse_error, "robot.name");
}

TEST(Bundle, MissingFile) {
  a2l::Skill s;
  const a2l::Result r = a2l::load_bundle("/nonexistent/dir/skill.a2lb", s);
  EXPECT_EQ(r.status, Status::file_error);
  EXPECT_NE(r.message.find("/nonexistent/dir/skill.a2lb"), std::string::npos);
}

TEST(Bundle, TruncatedAnywhere) {
  const auto b = build(sample_parts());
  std::vector<std::size_t> lengths = {0, 1, 7, 8, 12, 23, 24, 25, 100, b.size() - 1, b.size() - 8};
  for (std::size_t n = 0; n < b.size(); n += 97) lengths.push_back(n);
  for (std::size_t n : lengths) {
    const std::vector<std::uint8_t> t(b.begin(), b.begin() + static_cast<long>(n));
    const a2l::Result r = load(t);
    EXPECT_FALSE(r.ok()) << n;
    EXPECT_TRUE(r.status == Status::parse_error) << n << ": " << r.message;
    EXPECT_FALSE(r.message.empty());
    // a short file is named: "truncated" (before the header, the manifest's end, the blob or an
    // array's end), or an array's nbytes "larger than the file"
    EXPECT_TRUE(names_one_of(r.message, {"truncated", "larger than the file"})) << n;
  }
  expect_error(load({b.begin(), b.begin() + 10}), Status::parse_error, "header");
  expect_error(load({b.begin(), b.begin() + 200}), Status::parse_error, "manifest length");
  expect_error(load({b.begin(), b.end() - 4}), Status::parse_error, "outside the file");
}

TEST(Bundle, NullData) {
  a2l::Skill s;
  expect_error(a2l::load_bundle_from_memory(nullptr, 100, s, "corrupt.a2lb"),
               Status::invalid_argument, "null data");
  // null and no bytes: an empty file
  expect_error(a2l::load_bundle_from_memory(nullptr, 0, s, "corrupt.a2lb"), Status::parse_error,
               "truncated: 0 bytes, shorter than the 24-byte header");
}

TEST(Bundle, ReservedHeaderFieldMustBeZero) {
  for (const std::size_t at : {20, 23}) {  // the first and the last byte of the field
    auto b = build(sample_parts());
    b[at] = 0x01;
    expect_error(load(b), Status::parse_error, "header: reserved field is not 0");
  }
}

TEST(Bundle, FileEndingBeforeItsBlob) {
  std::size_t manifest_end = 0, blob = 0;
  const auto b = padded_bundle(manifest_end, blob);
  ASSERT_LT(manifest_end, blob);
  // the whole manifest (its CRC-32 right), cut within the padding that leads to the blob
  for (std::size_t n = manifest_end; n < blob; ++n) {
    expect_error(load({b.begin(), b.begin() + static_cast<long>(n)}), Status::parse_error,
                 "truncated: the file ends before its blob");
  }
}

TEST(Bundle, PaddingAfterTheManifestMustBeZero) {
  std::size_t manifest_end = 0, blob = 0;
  const auto valid = padded_bundle(manifest_end, blob);
  ASSERT_TRUE(load(valid).ok());
  for (std::size_t i = manifest_end; i < blob; ++i) {
    auto b = valid;
    b[i] = ' ';  // JSON whitespace, but outside the manifest's length
    expect_error(load(b), Status::parse_error, "padding after the manifest is not zero");
  }
}

TEST(Bundle, ManifestMustBeAJsonObject) {
  for (const char* text : {"[1, 2, 3]", "42", "\"skill\"", "null", "true"}) {
    expect_error(load(a2l::testing::frame(text)), Status::parse_error,
                 "manifest: must be a JSON object");
  }
}

TEST(Bundle, ArraysMissingOrNotAnObject) {
  const BundleParts p = sample_parts();  // its manifest has no "arrays" (build() adds them)
  expect_error(load(a2l::testing::frame(p.manifest.dump())), Status::parse_error,
               "arrays: missing");
  // a patch that is not an object replaces "arrays" (JSON merge patch)
  const std::vector<std::pair<json, std::string>> wrong = {
      {json::array({1, 2}), "array"}, {json(7), "number"}, {json("posterior"), "string"}};
  for (const auto& [arrays, type] : wrong) {
    expect_error(load(build(p, arrays)), Status::parse_error,
                 "arrays: must be an object, got " + type);
  }
}

TEST(Bundle, BadMagic) {
  auto b = build(sample_parts());
  b[0] = 'X';
  expect_error(load(b), Status::parse_error, "magic");
}

TEST(Bundle, WrongChecksums) {
  auto b = build(sample_parts());
  b[30] ^= 0x01;  // inside the manifest
  expect_error(load(b), Status::checksum_mismatch, "manifest CRC-32");
  b = build(sample_parts());
  b[b.size() - 4000] ^= 0x10;  // inside the posterior
  expect_error(load(b), Status::checksum_mismatch, "arrays.posterior.crc32");
  b = build(sample_parts());
  b[b.size() - 1] ^= 0x10;  // inside the argmax
  expect_error(load(b), Status::checksum_mismatch, "arrays.argmax.crc32");
  expect_error(load(build(sample_parts(), {{"argmax", {{"crc32", 5}}}})), Status::checksum_mismatch,
               "arrays.argmax.crc32");
}

TEST(Bundle, WrongVersions) {
  const std::uint32_t next = a2l::kBundleSchemaVersion + 1;
  expect_error(load(build(sample_parts(), json(), next)), Status::version_mismatch,
               "schema version");
  // versions 1 (before the DS section) and 2 (before movement actions) are not read either
  expect_error(load(build(sample_parts(), json(), 1)), Status::version_mismatch, "schema version");
  expect_error(load(build(sample_parts(), json(), 2)), Status::version_mismatch, "schema version");
  expect_error(load(with([&](json& m) { m["schema_version"] = next; })), Status::version_mismatch,
               "schema_version");
}

TEST(Bundle, WrongShapes) {
  expect_error(load(build(sample_parts(), {{"posterior", {{"shape", {4, 3, 8, 4, 2}}}}})),
               Status::parse_error, "arrays.posterior.shape");
  expect_error(load(build(sample_parts(), {{"argmax", {{"shape", {4, 3, 8, 2, 4}}}}})),
               Status::parse_error, "arrays.argmax.shape");
  // A variable whose bins disagree with the arrays.
  expect_error(load(with([](json& m) { m["variables"][2]["n_bins"] = 16; })), Status::parse_error,
               "arrays.posterior.shape");
  expect_error(load(with([](json& m) {
                 m["movements"]["directions"].erase(7);
                 m["movements"]["labels"].erase(7);
               })),
               Status::parse_error, "arrays.posterior.shape");
  expect_error(load(build(sample_parts(), {{"argmax", {{"nbytes", 16}}}})), Status::parse_error,
               "arrays.argmax.nbytes");
  expect_error(load(build(sample_parts(), {{"argmax", {{"dtype", "int64"}}}})), Status::parse_error,
               "arrays.argmax.dtype");
}

TEST(Bundle, OffsetsOverlapAndTrailingBytes) {
  expect_error(load(build(sample_parts(), {{"argmax", {{"offset", 4}}}})), Status::parse_error,
               "multiple of 8");
  expect_error(load(build(sample_parts(), {{"argmax", {{"offset", 0}}}})), Status::parse_error,
               "overlap");
  auto b = build(sample_parts());
  b.insert(b.end(), 8, 0);
  expect_error(load(b), Status::parse_error, "trailing");
  expect_error(load(build(sample_parts(), {{"argmax", {{"offset", 1LL << 40}}}})),
               Status::parse_error, "outside the file");
}

TEST(Bundle, MissingKeysAndWrongTypes) {
  for (const char* key : {"schema_version", "kind", "name", "created_by", "robot", "target",
                          "variables", "movements", "execution"}) {
    expect_error(load(with([&](json& m) { m.erase(key); })), Status::parse_error,
                 std::string(key) + ": missing");
  }
  expect_error(load(build(sample_parts(), {{"posterior", nullptr}})), Status::parse_error,
               "arrays.posterior: missing");
  expect_error(load(with([](json& m) { m["execution"]["step_cap"] = "12"; })), Status::parse_error,
               "execution.step_cap: must be an integer");
  expect_error(load(with([](json& m) { m["execution"]["step_cap"] = 0; })), Status::parse_error,
               "execution.step_cap");
  expect_error(load(with([](json& m) { m["execution"]["smoothing"] = 1; })), Status::parse_error,
               "execution.smoothing: must be a boolean");
  expect_error(load(with([](json& m) { m["execution"].erase("uniform_tolerance"); })),
               Status::parse_error, "execution.uniform_tolerance: missing");
  expect_error(load(with([](json& m) { m["kind"] = "dataset"; })), Status::parse_error, "kind");
  expect_error(load(with([](json& m) { m["variables"] = json::object(); })), Status::parse_error,
               "variables: must be an array");
}

TEST(Bundle, BadVariablesAndMovements) {
  expect_error(load(with([](json& m) { m["variables"][1]["kind"] = "colour"; })),
               Status::parse_error, "variables[1].kind");
  expect_error(load(with([](json& m) { m["variables"][2]["n_bins"] = 0; })), Status::parse_error,
               "variables[2].n_bins");
  expect_error(load(with([](json& m) { m["variables"][2]["n_bins"] = 2000; })), Status::parse_error,
               "variables[2].n_bins");
  expect_error(load(with([](json& m) { m["variables"][1]["low"] = 0.3; })), Status::parse_error,
               "variables[1].low/high");
  expect_error(load(with([](json& m) { m["variables"][3]["name"] = "distance"; })),
               Status::parse_error, "duplicate name");
  expect_error(load(with([](json& m) {
                 m["variables"][0]["values"] = {"a", "b", "c", 4};
               })),
               Status::parse_error, "variables[0].values[3]");
  expect_error(load(with([](json& m) {
                 m["movements"]["directions"][3] = {0, 0, 0};
               })),
               Status::parse_error, "movements.directions[3]");
  expect_error(load(with([](json& m) {
                 m["movements"]["directions"][3] = {2, 0, 0};
               })),
               Status::parse_error, "movements.directions[3][0]");
  expect_error(load(with([](json& m) { m["movements"]["labels"].erase(0); })), Status::parse_error,
               "movements.labels");
  expect_error(load(with([](json& m) { m["movements"]["step"] = -0.05; })), Status::parse_error,
               "movements.step");
}

TEST(Bundle, BadProbabilitiesAndArgmax) {
  BundleParts p = sample_parts();
  p.posterior[3] += 0.01;  // row 0 no longer sums to 1
  expect_error(load(build(p)), Status::parse_error, "sums to");
  p = sample_parts();
  p.posterior[8] = -p.posterior[8];
  expect_error(load(build(p)), Status::parse_error, "negative or non-finite");
  p = sample_parts();
  p.posterior[9] = std::nan("");
  expect_error(load(build(p)), Status::parse_error, "negative or non-finite");
  p = sample_parts();
  p.argmax[5] = 8;
  expect_error(load(build(p)), Status::parse_error, "argmax[5]");
  p.argmax[5] = -2;
  expect_error(load(build(p)), Status::parse_error, "argmax[5]");
}

TEST(Bundle, ArgmaxMustAgreeWithThePosterior) {
  const BundleParts good = sample_parts();
  std::size_t uniform = 0, informative = 0;
  while (good.argmax[uniform] != -1) ++uniform;
  while (good.argmax[informative] == -1) ++informative;
  BundleParts p = good;
  p.argmax[informative] = -1;  // a guess hidden as "no information"
  expect_error(load(build(p)), Status::parse_error,
               "argmax[" + std::to_string(informative) + "]: -1 (no information)");
  p = good;
  p.argmax[uniform] = 3;  // a guess on an uninformative row
  expect_error(load(build(p)), Status::parse_error,
               "argmax[" + std::to_string(uniform) + "]: 3 for a uniform posterior row");
  p = good;
  p.argmax[informative] = (good.argmax[informative] + 1) % 8;
  expect_error(load(build(p)), Status::parse_error, "is not the most probable");
}

TEST(Bundle, InvalidJson) {
  BundleParts p = sample_parts();
  auto b = build(p);
  // Replace the manifest's closing brace with garbage and fix the CRC.
  const std::uint32_t m =
      b[12] | (b[13] << 8) | (b[14] << 16) | (static_cast<std::uint32_t>(b[15]) << 24);
  b[24 + m - 1] = '#';
  const std::uint32_t crc = a2l::bundle_crc32(b.data() + 24, m);
  for (int i = 0; i < 4; ++i)
    b[16 + static_cast<size_t>(i)] = static_cast<std::uint8_t>(crc >> (8 * i));
  expect_error(load(b), Status::parse_error, "manifest JSON");
}

TEST(Bundle, RandomBytesNeverLoad) {
  std::mt19937_64 rng(9);
  std::uniform_int_distribution<int> byte(0, 255);
  const auto valid = build(sample_parts());
  for (int i = 0; i < 2000; ++i) {
    std::vector<std::uint8_t> b(std::uniform_int_distribution<std::size_t>(0, 4096)(rng));
    for (auto& x : b) x = static_cast<std::uint8_t>(byte(rng));
    if (i % 2 == 1 && b.size() >= 24) std::copy(valid.begin(), valid.begin() + 24, b.begin());
    const a2l::Result r = load(b);
    EXPECT_FALSE(r.ok());
    EXPECT_FALSE(r.message.empty());
    // refused by a check of the frame (the manifest's CRC-32 when the header is valid)
    EXPECT_TRUE(names_one_of(r.message, kFrameChecks)) << i;
  }
  // Random bit flips of a valid bundle: never a crash; an error unless the flip is harmless.
  std::vector<std::string> checks = kFrameChecks;
  checks.push_back(".crc32");  // an array's bytes
  int failures = 0;
  for (int i = 0; i < 300; ++i) {
    auto b = valid;
    b[std::uniform_int_distribution<std::size_t>(0, b.size() - 1)(rng)] ^=
        static_cast<std::uint8_t>(1 << byte(rng) % 8);
    const a2l::Result r = load(b);
    failures += !r.ok();
    EXPECT_TRUE(names_one_of(r.message, checks)) << i;
  }
  EXPECT_EQ(failures, 300);  // every byte is covered by a check or a checksum, which is named
}

}  // namespace test_bundle
