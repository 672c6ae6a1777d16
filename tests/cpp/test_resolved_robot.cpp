// A robot resolved by Python (a2l/resolved_robot.hpp): a good file read field by field, and
// every refusal naming the file and the key.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "a2l/resolved_robot.hpp"

namespace test_resolved_robot {

using nlohmann::json;
namespace fs = std::filesystem;

// What `a2l robot export panda` writes (the Panda's neutral pose and tool_down).
json good_robot() {
  return {
      {"format", "a2l-resolved-robot"},
      {"version", 1},
      {"name", "panda"},
      {"urdf", "/robots/panda.urdf"},
      {"urdf_sha256", std::string(64, 'a')},
      {"base_link", "panda_link0"},
      {"tool_link", "panda_hand_tcp"},
      {"joint_names", {"j1", "j2", "j3", "j4", "j5", "j6", "j7"}},
      {"neutral", {0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785}},
      {"tool_down", {{1.0, 0.0, 0.0}, {0.0, -1.0, 0.0}, {0.0, 0.0, -1.0}}},
      {"scene",
       {{"table_z", -0.2},
        {"work_point", {0.43, 0.31}},
        {"scale", 0.5},
        {"push_box_size", {0.07, 0.085, 0.058876}},
        {"workspace_min", {0.16, -0.19, -0.19}},
        {"workspace_max", {0.76, 1.01, 0.25}}}},
  };
}

std::string write(const std::string& name, const std::string& text) {
  const fs::path dir = fs::temp_directory_path() / "a2l_test_resolved_robot";
  fs::create_directories(dir);
  const fs::path path = dir / name;
  std::ofstream(path) << text;
  return path.string();
}

TEST(ResolvedRobot, ReadsEveryField) {
  const std::string path = write("good.json", good_robot().dump());
  a2l::ResolvedRobot r;
  const a2l::Result res = a2l::load_resolved_robot(path, r);
  ASSERT_TRUE(res.ok()) << res.message;
  EXPECT_EQ(r.source, path);
  EXPECT_EQ(r.name, "panda");
  EXPECT_EQ(r.urdf, "/robots/panda.urdf");
  EXPECT_EQ(r.urdf_sha256, std::string(64, 'a'));
  EXPECT_EQ(r.base_link, "panda_link0");
  EXPECT_EQ(r.tool_link, "panda_hand_tcp");
  ASSERT_EQ(r.joint_names.size(), 7u);
  EXPECT_EQ(r.joint_names[6], "j7");
  ASSERT_EQ(r.neutral.size(), 7u);
  EXPECT_DOUBLE_EQ(r.neutral[3], -2.356);
  ASSERT_TRUE(r.has_tool_down);
  EXPECT_DOUBLE_EQ(r.tool_down(1, 1), -1.0);
  EXPECT_DOUBLE_EQ(r.tool_down(2, 2), -1.0);
  EXPECT_DOUBLE_EQ(r.scene.table_z, -0.2);
  EXPECT_DOUBLE_EQ(r.scene.work_point.x(), 0.43);
  EXPECT_DOUBLE_EQ(r.scene.work_point.y(), 0.31);
  EXPECT_DOUBLE_EQ(r.scene.scale, 0.5);
  EXPECT_DOUBLE_EQ(r.scene.push_box_size.z(), 0.058876);
  EXPECT_DOUBLE_EQ(r.scene.workspace_min.z(), -0.19);
  EXPECT_DOUBLE_EQ(r.scene.workspace_max.x(), 0.76);
}

TEST(ResolvedRobot, RelativeUrdfFromTheFilesFolderAndNoToolDown) {
  json j = good_robot();
  j["urdf"] = "arm/robot.urdf";
  j["tool_down"] = nullptr;
  const std::string path = write("relative.json", j.dump());
  a2l::ResolvedRobot r;
  ASSERT_TRUE(a2l::load_resolved_robot(path, r).ok());
  EXPECT_EQ(fs::path(r.urdf), fs::path(path).parent_path() / "arm" / "robot.urdf");
  EXPECT_FALSE(r.has_tool_down);
}

struct BadCase {
  const char* what;
  std::function<void(json&)> edit;
  a2l::Status status;
  const char* message;  // the key and why, after "robot file '<path>': "
};

TEST(ResolvedRobot, RefusesABadFileNamingTheKey) {
  const std::vector<BadCase> cases = {
      {"a robot file, not resolved", [](json& j) { j.erase("format"); }, a2l::Status::parse_error,
       "format: missing; a2l-run takes a robot resolved by `a2l robot export ROBOT"},
      {"another format", [](json& j) { j["format"] = "urdf"; }, a2l::Status::parse_error,
       "format: must be 'a2l-resolved-robot', got 'urdf'"},
      {"another version", [](json& j) { j["version"] = 2; }, a2l::Status::version_mismatch,
       "version: 2, this build reads version 1"},
      {"an unknown key", [](json& j) { j["mount"] = 1; }, a2l::Status::parse_error,
       "mount: unknown key; the valid keys are format, version, name"},
      {"a missing key", [](json& j) { j.erase("tool_link"); }, a2l::Status::parse_error,
       "tool_link: missing"},
      {"an empty name", [](json& j) { j["base_link"] = ""; }, a2l::Status::parse_error,
       "base_link: must not be empty"},
      {"a number for a name", [](json& j) { j["urdf"] = 3; }, a2l::Status::parse_error,
       "urdf: must be a string, got number"},
      {"a joint name not a string", [](json& j) { j["joint_names"][2] = 1; },
       a2l::Status::parse_error, "joint_names[2]: must be a string"},
      {"neutral too short", [](json& j) { j["neutral"].erase(6); }, a2l::Status::parse_error,
       "neutral: has 6 values for 7 joint_names"},
      {"neutral not a number", [](json& j) { j["neutral"][1] = "x"; }, a2l::Status::parse_error,
       "neutral[1]: must be a number, got string"},
      {"tool_down not 3 rows", [](json& j) { j["tool_down"].erase(2); }, a2l::Status::parse_error,
       "tool_down: must be null or 3 rows of 3 numbers, got 2 rows"},
      {"tool_down row short",
       [](json& j) {
         j["tool_down"][1] = {0.0, 1.0};
       },
       a2l::Status::parse_error, "tool_down[1]: must hold 3 numbers, got 2"},
      {"tool_down no rotation", [](json& j) { j["tool_down"][0][0] = -1.0; },
       a2l::Status::parse_error, "tool_down: not a rotation"},
      {"no scene", [](json& j) { j.erase("scene"); }, a2l::Status::parse_error, "scene: missing"},
      {"an unknown scene key", [](json& j) { j["scene"]["step"] = 0.05; }, a2l::Status::parse_error,
       "scene.step: unknown key; the valid keys are scene.table_z"},
      {"a scale above 1", [](json& j) { j["scene"]["scale"] = 2; }, a2l::Status::parse_error,
       "scene.scale: must be in (0, 1], got 2"},
      {"a zero scale", [](json& j) { j["scene"]["scale"] = 0; }, a2l::Status::parse_error,
       "scene.scale: must be in (0, 1], got 0"},
      {"a work point of 3",
       [](json& j) {
         j["scene"]["work_point"] = {0.1, 0.2, 0.3};
       },
       a2l::Status::parse_error, "scene.work_point: must hold 2 numbers, got 3"},
      {"a table height not a number", [](json& j) { j["scene"]["table_z"] = nullptr; },
       a2l::Status::parse_error, "scene.table_z: must be a number, got null"},
      {"a flat box", [](json& j) { j["scene"]["push_box_size"][2] = 0.0; },
       a2l::Status::parse_error, "scene.push_box_size: every extent must be > 0"},
      {"an empty workspace", [](json& j) { j["scene"]["workspace_max"][2] = -0.5; },
       a2l::Status::parse_error, "scene.workspace_max: must be above scene.workspace_min"},
  };
  for (const BadCase& c : cases) {
    json j = good_robot();
    c.edit(j);
    const std::string path = write("bad.json", j.dump());
    a2l::ResolvedRobot r;
    const a2l::Result res = a2l::load_resolved_robot(path, r);
    EXPECT_EQ(res.status, c.status) << c.what << ": " << res.message;
    EXPECT_NE(res.message.find("robot file '" + path + "': " + c.message), std::string::npos)
        << c.what << ": " << res.message;
  }
}

TEST(ResolvedRobot, RefusesAMissingFileAndTextThatIsNotJson) {
  a2l::ResolvedRobot r;
  a2l::Result res = a2l::load_resolved_robot("/nonexistent/a2l/panda.json", r);
  EXPECT_EQ(res.status, a2l::Status::file_error);
  EXPECT_NE(res.message.find("'/nonexistent/a2l/panda.json': cannot open"), std::string::npos);
  res = a2l::load_resolved_robot(write("cut.json", good_robot().dump().substr(0, 40)), r);
  EXPECT_EQ(res.status, a2l::Status::parse_error);
  EXPECT_NE(res.message.find("not valid JSON"), std::string::npos) << res.message;
  res = a2l::load_resolved_robot(write("list.json", "[1, 2]"), r);
  EXPECT_EQ(res.status, a2l::Status::parse_error);
  EXPECT_NE(res.message.find("must hold a JSON object, got array"), std::string::npos);
}

}  // namespace test_resolved_robot
