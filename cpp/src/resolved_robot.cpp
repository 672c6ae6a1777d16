// A robot resolved by Python for the runtime (resolved_robot.hpp): the JSON read with the
// bundle loader's helpers (bundle_json.hpp), every message naming the file and the key.
#include "a2l/resolved_robot.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <sstream>

#include "bundle_json.hpp"

namespace a2l {

using namespace bundle_detail;  // NOLINT: the JSON helpers of the bundle loader

namespace {

constexpr const char* kTopKeys[] = {"format",      "version",   "name",      "urdf",
                                    "urdf_sha256", "base_link", "tool_link", "joint_names",
                                    "neutral",     "tool_down", "scene"};
constexpr const char* kSceneKeys[] = {"table_z",       "work_point",    "scale",
                                      "push_box_size", "workspace_min", "workspace_max"};

// Every key of `obj` one of `valid` (`where` the prefix of its name, "scene.").
template <std::size_t N>
bool known_keys(const json& obj, const std::string& where, const char* const (&valid)[N],
                Errors& e) {
  for (auto it = obj.begin(); it != obj.end(); ++it) {
    bool found = false;
    std::string names;
    for (const char* k : valid) {
      found = found || it.key() == k;
      names += (names.empty() ? "" : ", ") + where + k;
    }
    if (!found) return e.parse(where + it.key() + ": unknown key; the valid keys are " + names);
  }
  return true;
}

// A non-empty string.
bool get_name(const json& obj, const std::string& where, const char* key, std::string& out,
              Errors& e) {
  if (!get_string(obj, where, key, out, e)) return false;
  if (out.empty()) return e.parse(where + key + ": must not be empty");
  return true;
}

// `a`, an array of finite numbers, into `out`: `size` of them unless size < 0 (then at
// least one); `field` names it in messages.
bool as_numbers(const json& a, const std::string& field, int size, std::vector<double>& out,
                Errors& e) {
  if (!a.is_array()) return e.parse(field + ": must be an array, got " + type_name(a));
  if (size >= 0 && a.size() != static_cast<std::size_t>(size)) {
    return e.parse(field + ": must hold " + std::to_string(size) + " numbers, got " +
                   std::to_string(a.size()));
  }
  if (a.empty()) return e.parse(field + ": must not be empty");
  out.clear();
  for (std::size_t i = 0; i < a.size(); ++i) {
    const json& x = a[i];
    const std::string at = field + "[" + std::to_string(i) + "]";
    if (!x.is_number()) return e.parse(at + ": must be a number, got " + type_name(x));
    out.push_back(x.get<double>());
    if (!std::isfinite(out.back())) return e.parse(at + ": must be finite");
  }
  return true;
}

// obj[key], an array of finite numbers (as_numbers).
bool get_numbers(const json& obj, const std::string& where, const char* key, int size,
                 std::vector<double>& out, Errors& e) {
  const json* a = nullptr;
  return get_member(obj, where, key, a, e) && as_numbers(*a, where + key, size, out, e);
}

// The version: 1, else version_mismatch.
bool check_format(const json& j, Errors& e) {
  std::string format;
  const json* f = nullptr;
  if (j.find("format") == j.end()) {
    return e.parse(
        "format: missing; a2l-run takes a robot resolved by `a2l robot export ROBOT --out "
        "FILE.json`, not a robot file");
  }
  if (!get_member(j, "", "format", f, e) || !as_string(*f, "format", format, e)) return false;
  if (format != kResolvedRobotFormat) {
    return e.parse("format: must be '" + std::string(kResolvedRobotFormat) + "', got '" + format +
                   "'");
  }
  std::int64_t version = 0;
  if (!get_int(j, "", "version", 0, 1 << 30, version, e)) return false;
  if (version != kResolvedRobotVersion) {
    return e.fail(Status::version_mismatch,
                  "version: " + std::to_string(version) + ", this build reads version " +
                      std::to_string(kResolvedRobotVersion) + " (export the robot again)");
  }
  return true;
}

// tool_down: null, or 3 rows of 3 finite numbers forming a rotation (R^T R = I, det R = 1,
// to 1e-4, as a2l.robot.check_entry).
bool parse_tool_down(const json& j, ResolvedRobot& out, Errors& e) {
  const json* t = nullptr;
  if (!get_member(j, "", "tool_down", t, e)) return false;
  out.has_tool_down = !t->is_null();
  if (!out.has_tool_down) return true;
  if (!t->is_array() || t->size() != 3) {
    return e.parse(std::string("tool_down: must be null or 3 rows of 3 numbers, got ") +
                   (t->is_array() ? std::to_string(t->size()) + " rows" : type_name(*t)));
  }
  std::vector<double> row;
  for (int r = 0; r < 3; ++r) {
    const std::string field = "tool_down[" + std::to_string(r) + "]";
    if (!as_numbers((*t)[static_cast<std::size_t>(r)], field, 3, row, e)) return false;
    for (int c = 0; c < 3; ++c) out.tool_down(r, c) = row[static_cast<std::size_t>(c)];
  }
  const Eigen::Matrix3d& R = out.tool_down;
  const double orth = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (orth > 1e-4 || std::abs(R.determinant() - 1.0) > 1e-4) {
    std::ostringstream s;
    s << "tool_down: not a rotation (|R^T R - I| = " << orth << ", det R = " << R.determinant()
      << "; both must be within 1e-4 of I and 1)";
    return e.parse(s.str());
  }
  return true;
}

// scene: the table height, the work point, the scale in (0, 1], the push box's size (> 0) and
// a non-empty workspace.
bool parse_scene(const json& j, RobotSceneGeometry& g, Errors& e) {
  const json* s = nullptr;
  if (!get_object(j, "", "scene", s, e) || !known_keys(*s, "scene.", kSceneKeys, e)) return false;
  std::vector<double> wp, box, lo, hi;
  if (!get_number(*s, "scene.", "table_z", g.table_z, e) ||
      !get_numbers(*s, "scene.", "work_point", 2, wp, e) ||
      !get_number(*s, "scene.", "scale", g.scale, e) ||
      !get_numbers(*s, "scene.", "push_box_size", 3, box, e) ||
      !get_numbers(*s, "scene.", "workspace_min", 3, lo, e) ||
      !get_numbers(*s, "scene.", "workspace_max", 3, hi, e)) {
    return false;
  }
  if (!(g.scale > 0.0 && g.scale <= 1.0)) {
    std::ostringstream m;
    m << "scene.scale: must be in (0, 1], got " << g.scale;
    return e.parse(m.str());
  }
  g.push_box_size = Eigen::Vector3d(box[0], box[1], box[2]);
  if (!(g.push_box_size.array() > 0.0).all()) {
    return e.parse("scene.push_box_size: every extent must be > 0");
  }
  g.work_point = Eigen::Vector2d(wp[0], wp[1]);
  g.workspace_min = Eigen::Vector3d(lo[0], lo[1], lo[2]);
  g.workspace_max = Eigen::Vector3d(hi[0], hi[1], hi[2]);
  if (!(g.workspace_min.array() < g.workspace_max.array()).all()) {
    return e.parse("scene.workspace_max: must be above scene.workspace_min on every axis");
  }
  return true;
}

bool parse_robot_json(const json& j, const std::string& folder, ResolvedRobot& out, Errors& e) {
  if (!j.is_object()) {
    return e.parse(std::string("must hold a JSON object, got ") + type_name(j));
  }
  if (!check_format(j, e) || !known_keys(j, "", kTopKeys, e)) return false;
  if (!get_name(j, "", "name", out.name, e) || !get_name(j, "", "urdf", out.urdf, e) ||
      !get_name(j, "", "urdf_sha256", out.urdf_sha256, e) ||
      !get_name(j, "", "base_link", out.base_link, e) ||
      !get_name(j, "", "tool_link", out.tool_link, e)) {
    return false;
  }
  std::filesystem::path urdf(out.urdf);
  if (urdf.is_relative()) out.urdf = (std::filesystem::path(folder) / urdf).string();
  const json* names = nullptr;
  if (!get_array(j, "", "joint_names", names, e)) return false;
  out.joint_names.clear();
  for (std::size_t i = 0; i < names->size(); ++i) {
    std::string n;
    if (!as_string((*names)[i], "joint_names[" + std::to_string(i) + "]", n, e)) return false;
    out.joint_names.push_back(n);
  }
  if (!get_numbers(j, "", "neutral", -1, out.neutral, e)) return false;
  if (out.neutral.size() != out.joint_names.size()) {
    return e.parse("neutral: has " + std::to_string(out.neutral.size()) + " values for " +
                   std::to_string(out.joint_names.size()) + " joint_names");
  }
  return parse_tool_down(j, out, e) && parse_scene(j, out.scene, e);
}

}  // namespace

Result load_resolved_robot(const std::string& path, ResolvedRobot& out) {
  const std::string src = "robot file '" + path + "'";
  try {
    std::ifstream f(path, std::ios::binary);
    if (!f) return Result::failure(Status::file_error, src + ": cannot open the file");
    const std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    if (f.bad()) return Result::failure(Status::file_error, src + ": read error");
    json j;
    try {
      j = json::parse(text);
    } catch (const json::parse_error& ex) {
      return Result::failure(Status::parse_error, src + ": not valid JSON: " + ex.what());
    }
    out = ResolvedRobot{};
    out.source = path;
    Errors e;
    const std::string folder = std::filesystem::path(path).parent_path().string();
    if (!parse_robot_json(j, folder.empty() ? "." : folder, out, e)) {
      return Result::failure(e.status, src + ": " + e.message);
    }
  } catch (const std::exception& ex) {
    return Result::failure(Status::parse_error, src + ": " + ex.what());
  }
  return Result::success();
}

}  // namespace a2l
