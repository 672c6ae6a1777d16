// Internal to the bundle loader (not installed): the JSON and array helpers shared by
// bundle.cpp (header, skill section) and bundle_ds.cpp (the DS section).
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "a2l/diffeo.hpp"
#include "a2l/skill.hpp"
#include "a2l/status.hpp"

namespace a2l::bundle_detail {

using json = nlohmann::json;

inline std::uint32_t read_u32(const std::uint8_t* p) noexcept {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

// Collects the first error; every parse helper returns false after setting it.
struct Errors {
  Status status = Status::ok;
  std::string message;
  bool fail(Status s, std::string msg) {
    status = s;
    message = std::move(msg);
    return false;
  }
  bool parse(std::string msg) { return fail(Status::parse_error, std::move(msg)); }
};

inline const char* type_name(const json& j) noexcept { return j.type_name(); }

inline bool get_member(const json& obj, const std::string& where, const char* key, const json*& out,
                       Errors& e) {
  const auto it = obj.find(key);
  if (it == obj.end()) return e.parse(where + key + ": missing");
  out = &*it;
  return true;
}

inline bool get_object(const json& obj, const std::string& where, const char* key, const json*& out,
                       Errors& e) {
  if (!get_member(obj, where, key, out, e)) return false;
  if (!out->is_object()) {
    return e.parse(where + key + ": must be an object, got " + type_name(*out));
  }
  return true;
}

inline bool get_array(const json& obj, const std::string& where, const char* key, const json*& out,
                      Errors& e) {
  if (!get_member(obj, where, key, out, e)) return false;
  if (!out->is_array()) return e.parse(where + key + ": must be an array, got " + type_name(*out));
  return true;
}

inline bool as_string(const json& j, const std::string& field, std::string& out, Errors& e) {
  if (!j.is_string()) return e.parse(field + ": must be a string, got " + type_name(j));
  out = j.get<std::string>();
  return true;
}

inline bool get_string(const json& obj, const std::string& where, const char* key, std::string& out,
                       Errors& e) {
  const json* j = nullptr;
  return get_member(obj, where, key, j, e) && as_string(*j, where + key, out, e);
}

inline bool as_int(const json& j, const std::string& field, std::int64_t lo, std::int64_t hi,
                   std::int64_t& out, Errors& e) {
  if (j.is_number_unsigned()) {
    const auto u = j.get<std::uint64_t>();
    if (u > static_cast<std::uint64_t>(hi)) {
      return e.parse(field + ": " + std::to_string(u) + " is outside [" + std::to_string(lo) +
                     ", " + std::to_string(hi) + "]");
    }
    out = static_cast<std::int64_t>(u);
  } else if (j.is_number_integer()) {
    out = j.get<std::int64_t>();
  } else {
    return e.parse(field + ": must be an integer, got " + type_name(j));
  }
  if (out < lo || out > hi) {
    return e.parse(field + ": " + std::to_string(out) + " is outside [" + std::to_string(lo) +
                   ", " + std::to_string(hi) + "]");
  }
  return true;
}

inline bool get_int(const json& obj, const std::string& where, const char* key, std::int64_t lo,
                    std::int64_t hi, std::int64_t& out, Errors& e) {
  const json* j = nullptr;
  return get_member(obj, where, key, j, e) && as_int(*j, where + key, lo, hi, out, e);
}

inline bool get_number(const json& obj, const std::string& where, const char* key, double& out,
                       Errors& e) {
  const json* j = nullptr;
  if (!get_member(obj, where, key, j, e)) return false;
  if (!j->is_number()) return e.parse(where + key + ": must be a number, got " + type_name(*j));
  out = j->get<double>();
  if (!std::isfinite(out)) return e.parse(where + key + ": must be finite");
  return true;
}

inline bool get_bool(const json& obj, const std::string& where, const char* key, bool& out,
                     Errors& e) {
  const json* j = nullptr;
  if (!get_member(obj, where, key, j, e)) return false;
  if (!j->is_boolean()) return e.parse(where + key + ": must be a boolean, got " + type_name(*j));
  out = j->get<bool>();
  return true;
}

struct ArrayEntry {
  std::string name;
  std::uint64_t offset = 0, nbytes = 0;
  std::uint32_t crc = 0;
};

// Parse arrays.<name> and check it against the expected dtype and shape.
// `given_by` names what fixes the expected shape in messages; every extent is <= max_extent.
inline bool parse_array(const json& arrays, const char* name, const char* dtype,
                        std::size_t itemsize, const std::vector<std::int64_t>& shape,
                        std::uint64_t max_bytes, ArrayEntry& a, Errors& e,
                        const char* given_by = "the variables and movements",
                        std::int64_t max_extent = kMaxBins) {
  const json* j = nullptr;
  const std::string where = std::string("arrays.") + name + ".";
  if (!get_object(arrays, "arrays.", name, j, e)) return false;
  a.name = name;
  std::string dt;
  if (!get_string(*j, where, "dtype", dt, e)) return false;
  if (dt != dtype) return e.parse(where + "dtype: must be '" + dtype + "', got '" + dt + "'");
  const json* sh = nullptr;
  if (!get_array(*j, where, "shape", sh, e)) return false;
  std::ostringstream want;
  want << "[";
  for (size_t i = 0; i < shape.size(); ++i) want << (i ? ", " : "") << shape[i];
  want << "]";
  if (sh->size() != shape.size()) {
    return e.parse(where + "shape: has " + std::to_string(sh->size()) + " axes, " + given_by +
                   " give " + want.str());
  }
  for (size_t i = 0; i < shape.size(); ++i) {
    std::int64_t x = 0;
    if (!as_int((*sh)[i], where + "shape[" + std::to_string(i) + "]", 0, max_extent, x, e)) {
      return false;
    }
    if (x != shape[i]) {
      return e.parse(where + "shape: does not match " + given_by + ", which give " + want.str());
    }
  }
  std::int64_t off = 0, nb = 0, crc = 0;
  const std::int64_t big = std::numeric_limits<std::int64_t>::max();
  if (!get_int(*j, where, "offset", 0, big, off, e) ||
      !get_int(*j, where, "nbytes", 0, big, nb, e) ||
      !get_int(*j, where, "crc32", 0, 0xFFFFFFFFll, crc, e)) {
    return false;
  }
  // product(shape) * itemsize, saturating above max_bytes (the entries are <= max_extent).
  std::uint64_t expected = itemsize;
  for (std::int64_t x : shape) {
    expected *= static_cast<std::uint64_t>(x);
    if (expected > max_bytes) break;
  }
  if (static_cast<std::uint64_t>(nb) != expected) {
    return e.parse(where + "nbytes: " + std::to_string(nb) + " != product(shape) * " +
                   std::to_string(itemsize) +
                   (expected > max_bytes ? std::string(" (larger than the file)")
                                         : " = " + std::to_string(expected)));
  }
  if (off % 8 != 0)
    return e.parse(where + "offset: " + std::to_string(off) + " is not a multiple of 8");
  a.offset = static_cast<std::uint64_t>(off);
  a.nbytes = static_cast<std::uint64_t>(nb);
  a.crc = static_cast<std::uint32_t>(crc);
  return true;
}

//! The robot entry of manifest `m` (bundle_skill.cpp; every message names the field).
bool parse_robot(const json& m, RobotInfo& robot, Errors& e);
//! The evidence variables of manifest `m`, in axis order.
bool parse_variables(const json& m, std::vector<Variable>& vars, Errors& e);
//! The movement repertoire of manifest `m`: step, directions, labels and actions.
bool parse_movements(const json& m, double& step, std::vector<Eigen::Vector3i>& dirs,
                     std::vector<std::string>& labels, std::vector<MovementAction>& actions,
                     Errors& e);
//! The execution settings of manifest `m`.
bool parse_execution(const json& m, SkillSettings& s, Errors& e);

//! Parse a DS description object `ds` (dim, n_maps, speed, target; messages start with `where`,
//! e.g. "ds.") and check its arrays `<prefix>centers`, `<prefix>vectors`, `<prefix>rhos`
//! (appended to `entries`). `maps` gets dim, target and speed (bundle_ds.cpp).
bool parse_ds_object(const json& ds, const std::string& where, const json& arrays,
                     const std::string& prefix, std::uint64_t room, DiffeoMaps& maps,
                     std::vector<ArrayEntry>& entries, Errors& e);

//! Copy the arrays `<prefix>centers|vectors|rhos` of `entries` from the blob into `maps` and
//! validate the maps (the message, after `where`, names the bad map's index).
bool read_ds_maps(const std::uint8_t* blob, const std::vector<ArrayEntry>& entries,
                  const std::string& prefix, const std::string& where, DiffeoMaps& maps, Errors& e);

//! Parse the optional "ds_phases" section of manifest `m` (bundle_phases.cpp): the states and
//! the phases (name, when, end_action, tolerance, ds), each phase's DS arrays
//! `ds_phase<i>_centers|vectors|rhos` appended to `entries`. Messages name the phase's index
//! and field ("ds_phases.phases[1].tolerance: ...").
bool parse_ds_phases(const json& m, const json& arrays, std::uint64_t room, DSPhaseSet& set,
                     std::vector<DiffeoMaps>& maps, std::vector<ArrayEntry>& entries, Errors& e);

//! Read the phases' DS arrays from the blob, validate them and build each phase's DiffeoDS<3>.
bool read_ds_phases(const std::uint8_t* blob, const std::vector<ArrayEntry>& entries,
                    std::vector<DiffeoMaps>& maps, DSPhaseSet& set, Errors& e);

//! Parse the optional "ds" section of manifest `m` (bundle_ds.cpp): ds.dim, ds.n_maps,
//! ds.target, ds.speed and the arrays ds_centers, ds_vectors, ds_rhos (appended to `entries`;
//! their bytes are read later by read_ds_arrays). `maps` gets dim, target and speed.
bool parse_ds_section(const json& m, const json& arrays, std::uint64_t room, DiffeoMaps& maps,
                      std::vector<ArrayEntry>& entries, Errors& e);

//! Copy the DS arrays (entries named ds_*) from the blob into `maps` and validate the maps
//! (validate_diffeo_maps: the message names the map's index).
bool read_ds_arrays(const std::uint8_t* blob, const std::vector<ArrayEntry>& entries,
                    DiffeoMaps& maps, Errors& e);

//! Parse and validate bundle bytes: the skill section into `skill` (kind "skill"; may be null),
//! the DS section into `ds` (may be null; then a DS present is still validated). Fails if a
//! requested section is absent. Defined in bundle.cpp.
Result parse_bundle(const std::uint8_t* data, std::size_t size, const std::string& source,
                    Skill* skill, DiffeoMaps* ds);

//! Read a whole file into `bytes`. \return `file_error` naming `path` on failure.
Result read_file(const std::string& path, std::vector<std::uint8_t>& bytes);

}  // namespace a2l::bundle_detail
