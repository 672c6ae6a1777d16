#include "a2l/bundle.hpp"

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

namespace a2l {

const char kBundleMagic[8] = {'A', '2', 'L', 'B', 'N', 'D', 'L', '\0'};

std::uint32_t bundle_crc32(const void* data, std::size_t size) noexcept {
  uLong crc = crc32(0L, Z_NULL, 0);
  const auto* p = static_cast<const Bytef*>(data);
  while (size > 0) {
    const uInt chunk = size > (1u << 30) ? (1u << 30) : static_cast<uInt>(size);
    crc = crc32(crc, p, chunk);
    p += chunk;
    size -= chunk;
  }
  return static_cast<std::uint32_t>(crc);
}

namespace {

using json = nlohmann::json;

std::uint32_t read_u32(const std::uint8_t* p) noexcept {
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

const char* type_name(const json& j) noexcept { return j.type_name(); }

bool get_member(const json& obj, const std::string& where, const char* key, const json*& out,
                Errors& e) {
  const auto it = obj.find(key);
  if (it == obj.end()) return e.parse(where + key + ": missing");
  out = &*it;
  return true;
}

bool get_object(const json& obj, const std::string& where, const char* key, const json*& out,
                Errors& e) {
  if (!get_member(obj, where, key, out, e)) return false;
  if (!out->is_object()) {
    return e.parse(where + key + ": must be an object, got " + type_name(*out));
  }
  return true;
}

bool get_array(const json& obj, const std::string& where, const char* key, const json*& out,
               Errors& e) {
  if (!get_member(obj, where, key, out, e)) return false;
  if (!out->is_array()) return e.parse(where + key + ": must be an array, got " + type_name(*out));
  return true;
}

bool as_string(const json& j, const std::string& field, std::string& out, Errors& e) {
  if (!j.is_string()) return e.parse(field + ": must be a string, got " + type_name(j));
  out = j.get<std::string>();
  return true;
}

bool get_string(const json& obj, const std::string& where, const char* key, std::string& out,
                Errors& e) {
  const json* j = nullptr;
  return get_member(obj, where, key, j, e) && as_string(*j, where + key, out, e);
}

bool as_int(const json& j, const std::string& field, std::int64_t lo, std::int64_t hi,
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

bool get_int(const json& obj, const std::string& where, const char* key, std::int64_t lo,
             std::int64_t hi, std::int64_t& out, Errors& e) {
  const json* j = nullptr;
  return get_member(obj, where, key, j, e) && as_int(*j, where + key, lo, hi, out, e);
}

bool get_number(const json& obj, const std::string& where, const char* key, double& out,
                Errors& e) {
  const json* j = nullptr;
  if (!get_member(obj, where, key, j, e)) return false;
  if (!j->is_number()) return e.parse(where + key + ": must be a number, got " + type_name(*j));
  out = j->get<double>();
  if (!std::isfinite(out)) return e.parse(where + key + ": must be finite");
  return true;
}

bool get_bool(const json& obj, const std::string& where, const char* key, bool& out, Errors& e) {
  const json* j = nullptr;
  if (!get_member(obj, where, key, j, e)) return false;
  if (!j->is_boolean()) return e.parse(where + key + ": must be a boolean, got " + type_name(*j));
  out = j->get<bool>();
  return true;
}

bool parse_robot(const json& m, RobotInfo& robot, Errors& e) {
  const json* r = nullptr;
  if (!get_member(m, "", "robot", r, e)) return false;
  robot = RobotInfo{};
  if (r->is_null()) return true;
  if (!r->is_object())
    return e.parse(std::string("robot: must be an object or null, got ") + type_name(*r));
  robot.present = true;
  return get_string(*r, "robot.", "name", robot.name, e) &&
         get_string(*r, "robot.", "urdf_sha256", robot.urdf_sha256, e) &&
         get_string(*r, "robot.", "base_link", robot.base_link, e) &&
         get_string(*r, "robot.", "tip_link", robot.tip_link, e);
}

bool parse_variables(const json& m, std::vector<Variable>& vars, Errors& e) {
  const json* arr = nullptr;
  if (!get_array(m, "", "variables", arr, e)) return false;
  if (arr->size() > static_cast<size_t>(kMaxVariables)) {
    return e.parse("variables: " + std::to_string(arr->size()) + " variables, at most " +
                   std::to_string(kMaxVariables) + " are supported");
  }
  for (size_t i = 0; i < arr->size(); ++i) {
    const json& jv = (*arr)[i];
    const std::string where = "variables[" + std::to_string(i) + "].";
    if (!jv.is_object()) return e.parse(where.substr(0, where.size() - 1) + ": must be an object");
    Variable v;
    std::string kind;
    if (!get_string(jv, where, "name", v.name, e) || !get_string(jv, where, "kind", kind, e)) {
      return false;
    }
    if (!parse_variable_kind(kind, v.kind)) {
      return e.parse(where + "kind: unknown kind '" + kind +
                     "' (effect, distance, orientation, inclination, high_level)");
    }
    if (v.kind == VariableKind::effect || v.kind == VariableKind::high_level) {
      const json* values = nullptr;
      if (!get_array(jv, where, "values", values, e)) return false;
      if (values->empty() || values->size() > static_cast<size_t>(kMaxBins)) {
        return e.parse(where + "values: needs 1 to " + std::to_string(kMaxBins) + " values, got " +
                       std::to_string(values->size()));
      }
      for (size_t k = 0; k < values->size(); ++k) {
        std::string s;
        if (!as_string((*values)[k], where + "values[" + std::to_string(k) + "]", s, e)) {
          return false;
        }
        v.values.push_back(std::move(s));
      }
      v.n_bins = static_cast<int>(v.values.size());
    } else {
      std::int64_t n = 0;
      if (!get_int(jv, where, "n_bins", 1, kMaxBins, n, e)) return false;
      v.n_bins = static_cast<int>(n);
    }
    if (v.kind == VariableKind::distance) {
      if (!get_number(jv, where, "low", v.low, e) || !get_number(jv, where, "high", v.high, e)) {
        return false;
      }
      if (!(v.low < v.high)) return e.parse(where + "low/high: requires low < high");
    }
    vars.push_back(std::move(v));
  }
  return true;
}

bool parse_movements(const json& m, double& step, std::vector<Eigen::Vector3i>& dirs,
                     std::vector<std::string>& labels, Errors& e) {
  const json* mv = nullptr;
  if (!get_object(m, "", "movements", mv, e)) return false;
  if (!get_number(*mv, "movements.", "step", step, e)) return false;
  if (!(step > 0.0)) return e.parse("movements.step: must be > 0");
  const json* d = nullptr;
  if (!get_array(*mv, "movements.", "directions", d, e)) return false;
  if (d->empty() || d->size() > static_cast<size_t>(kMaxMoves)) {
    return e.parse("movements.directions: needs 1 to " + std::to_string(kMaxMoves) +
                   " movements, got " + std::to_string(d->size()));
  }
  for (size_t i = 0; i < d->size(); ++i) {
    const json& row = (*d)[i];
    const std::string field = "movements.directions[" + std::to_string(i) + "]";
    if (!row.is_array() || row.size() != 3) return e.parse(field + ": must be an array of 3 signs");
    Eigen::Vector3i v;
    for (int k = 0; k < 3; ++k) {
      std::int64_t x = 0;
      if (!as_int(row[static_cast<size_t>(k)], field + "[" + std::to_string(k) + "]", -1, 1, x,
                  e)) {
        return false;
      }
      v[k] = static_cast<int>(x);
    }
    if (v.isZero()) return e.parse(field + ": all zero (not a movement)");
    dirs.push_back(v);
  }
  const json* l = nullptr;
  if (!get_array(*mv, "movements.", "labels", l, e)) return false;
  if (l->size() != d->size()) {
    return e.parse("movements.labels: " + std::to_string(l->size()) + " labels for " +
                   std::to_string(d->size()) + " directions");
  }
  for (size_t i = 0; i < l->size(); ++i) {
    std::string s;
    if (!as_string((*l)[i], "movements.labels[" + std::to_string(i) + "]", s, e)) return false;
    labels.push_back(std::move(s));
  }
  return true;
}

bool parse_execution(const json& m, SkillSettings& s, Errors& e) {
  const json* x = nullptr;
  if (!get_object(m, "", "execution", x, e)) return false;
  std::int64_t cap = 0;
  if (!get_int(*x, "execution.", "step_cap", 1, 1000000, cap, e)) return false;
  s.step_cap = static_cast<int>(cap);
  if (!get_bool(*x, "execution.", "smoothing", s.smoothing, e)) return false;
  if (!get_number(*x, "execution.", "uniform_tolerance", s.uniform_tolerance, e)) return false;
  if (s.uniform_tolerance < 0.0) return e.parse("execution.uniform_tolerance: must be >= 0");
  return true;
}

struct ArrayEntry {
  std::string name;
  std::uint64_t offset = 0, nbytes = 0;
  std::uint32_t crc = 0;
};

// Parse arrays.<name> and check it against the expected dtype and shape.
bool parse_array(const json& arrays, const char* name, const char* dtype, std::size_t itemsize,
                 const std::vector<std::int64_t>& shape, std::uint64_t max_bytes, ArrayEntry& a,
                 Errors& e) {
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
    return e.parse(where + "shape: has " + std::to_string(sh->size()) +
                   " axes, the variables and movements give " + want.str());
  }
  for (size_t i = 0; i < shape.size(); ++i) {
    std::int64_t x = 0;
    if (!as_int((*sh)[i], where + "shape[" + std::to_string(i) + "]", 0, kMaxBins, x, e)) {
      return false;
    }
    if (x != shape[i]) {
      return e.parse(where + "shape: does not match the variables and movements, which give " +
                     want.str());
    }
  }
  std::int64_t off = 0, nb = 0, crc = 0;
  const std::int64_t big = std::numeric_limits<std::int64_t>::max();
  if (!get_int(*j, where, "offset", 0, big, off, e) ||
      !get_int(*j, where, "nbytes", 0, big, nb, e) ||
      !get_int(*j, where, "crc32", 0, 0xFFFFFFFFll, crc, e)) {
    return false;
  }
  // product(shape) * itemsize, saturating above max_bytes (the shape's entries are <= 1024).
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

Result parse(const std::uint8_t* data, std::size_t size, Skill& out, const std::string& source) {
  auto fail = [&](Status s, const std::string& msg) {
    return Result::failure(s, "skill bundle '" + source + "': " + msg);
  };
  if (data == nullptr && size > 0) return fail(Status::invalid_argument, "null data");
  if (size < kBundleHeaderSize) {
    return fail(Status::parse_error,
                "truncated: " + std::to_string(size) + " bytes, shorter than the 24-byte header");
  }
  if (std::memcmp(data, kBundleMagic, 8) != 0) {
    return fail(Status::parse_error,
                "magic: not a skill bundle (the file does not start with "
                "'A2LBNDL\\0')");
  }
  const std::uint32_t version = read_u32(data + 8);
  const std::uint32_t mlen = read_u32(data + 12);
  const std::uint32_t mcrc = read_u32(data + 16);
  const std::uint32_t reserved = read_u32(data + 20);
  if (version != kBundleSchemaVersion) {
    return fail(Status::version_mismatch, "schema version: the header says " +
                                              std::to_string(version) + ", this build reads " +
                                              std::to_string(kBundleSchemaVersion));
  }
  if (reserved != 0) return fail(Status::parse_error, "header: reserved field is not 0");
  if (mlen > size - kBundleHeaderSize) {
    return fail(Status::parse_error, "manifest length: " + std::to_string(mlen) +
                                         " bytes do not fit in the file (" + std::to_string(size) +
                                         " bytes): truncated?");
  }
  const std::uint8_t* manifest = data + kBundleHeaderSize;
  const std::uint32_t got_crc = bundle_crc32(manifest, mlen);
  if (got_crc != mcrc) {
    return fail(Status::checksum_mismatch, "manifest CRC-32: the header says " +
                                               std::to_string(mcrc) + ", the manifest gives " +
                                               std::to_string(got_crc));
  }
  const std::uint64_t blob = (kBundleHeaderSize + static_cast<std::uint64_t>(mlen) + 7) / 8 * 8;
  if (blob > size) return fail(Status::parse_error, "truncated: the file ends before its blob");
  for (std::uint64_t i = kBundleHeaderSize + mlen; i < blob; ++i) {
    if (data[i] != 0) return fail(Status::parse_error, "padding after the manifest is not zero");
  }

  json m;
  try {
    m = json::parse(manifest, manifest + mlen);
  } catch (const json::exception& ex) {
    return fail(Status::parse_error, std::string("manifest JSON: ") + ex.what());
  }
  if (!m.is_object()) return fail(Status::parse_error, "manifest: must be a JSON object");

  Errors e;
  auto err = [&]() { return fail(e.status, e.message); };
  std::int64_t mversion = 0;
  if (!get_int(m, "", "schema_version", 0, std::numeric_limits<std::int64_t>::max(), mversion, e)) {
    return err();
  }
  if (mversion != version) {
    return fail(Status::version_mismatch, "schema_version: the manifest says " +
                                              std::to_string(mversion) + ", the header " +
                                              std::to_string(version));
  }
  std::string kind, name, created_by, target;
  if (!get_string(m, "", "kind", kind, e)) return err();
  if (kind != "skill")
    return fail(Status::parse_error, "kind: must be 'skill', got '" + kind + "'");
  if (!get_string(m, "", "name", name, e) || !get_string(m, "", "created_by", created_by, e) ||
      !get_string(m, "", "target", target, e)) {
    return err();
  }
  RobotInfo robot;
  std::vector<Variable> vars;
  double step = 0.0;
  std::vector<Eigen::Vector3i> dirs;
  std::vector<std::string> labels;
  SkillSettings settings;
  if (!parse_robot(m, robot, e) || !parse_variables(m, vars, e) ||
      !parse_movements(m, step, dirs, labels, e) || !parse_execution(m, settings, e)) {
    return err();
  }
  std::vector<std::int64_t> shape;
  for (const Variable& v : vars) shape.push_back(v.n_bins);
  std::vector<std::int64_t> pshape = shape;
  pshape.push_back(static_cast<std::int64_t>(dirs.size()));

  const json* arrays = nullptr;
  if (!get_object(m, "", "arrays", arrays, e)) return err();
  ArrayEntry post, amax;
  const std::uint64_t room = size - blob;
  if (!parse_array(*arrays, "posterior", "float64", 8, pshape, room, post, e) ||
      !parse_array(*arrays, "argmax", "int32", 4, shape, room, amax, e)) {
    return err();
  }
  for (const ArrayEntry* a : {&post, &amax}) {
    if (a->offset > room || a->nbytes > room - a->offset) {
      return fail(Status::parse_error,
                  "arrays." + a->name + ": bytes [" + std::to_string(a->offset) + ", +" +
                      std::to_string(a->nbytes) + ") lie outside the file's blob (" +
                      std::to_string(room) + " bytes): truncated?");
    }
  }
  if (post.offset < amax.offset + amax.nbytes && amax.offset < post.offset + post.nbytes) {
    return fail(Status::parse_error, "arrays: posterior and argmax overlap");
  }
  const std::uint64_t end = std::max(post.offset + post.nbytes, amax.offset + amax.nbytes);
  if (end != room) {
    return fail(Status::parse_error, "file size: " + std::to_string(size) +
                                         " bytes, the arrays end at " + std::to_string(blob + end) +
                                         " (trailing bytes)");
  }
  for (const ArrayEntry* a : {&post, &amax}) {
    const std::uint32_t c = bundle_crc32(data + blob + a->offset, a->nbytes);
    if (c != a->crc) {
      return fail(Status::checksum_mismatch, "arrays." + a->name + ".crc32: the manifest says " +
                                                 std::to_string(a->crc) + ", the data give " +
                                                 std::to_string(c));
    }
  }
  std::vector<double> posterior(post.nbytes / 8);
  std::vector<std::int32_t> argmax(amax.nbytes / 4);
  if (!posterior.empty()) std::memcpy(posterior.data(), data + blob + post.offset, post.nbytes);
  if (!argmax.empty()) std::memcpy(argmax.data(), data + blob + amax.offset, amax.nbytes);

  Discretizer disc;
  Result r = Discretizer::create(std::move(vars), disc);
  if (!r.ok()) return fail(Status::parse_error, r.message);
  PolicyTable table;
  std::vector<int> ishape(shape.begin(), shape.end());
  r = PolicyTable::create(std::move(ishape), static_cast<int>(dirs.size()), std::move(posterior),
                          std::move(argmax), table);
  if (!r.ok()) return fail(Status::parse_error, "arrays: " + r.message);
  // argmax agrees with the posterior: -1 exactly where the row is uniform within
  // execution.uniform_tolerance, else a most probable movement (so the runtime never guesses).
  const int nm = table.n_moves();
  for (std::size_t row = 0; row < table.n_rows(); ++row) {
    const double* p = table.posterior_row(row);
    bool uniform = true;
    double best = p[0];
    for (int k = 0; k < nm; ++k) {
      uniform = uniform && std::abs(p[k] - 1.0 / nm) <= settings.uniform_tolerance;
      best = std::max(best, p[k]);
    }
    const int a = table.argmax(row);
    if (a < 0 && !uniform) {
      return fail(Status::parse_error,
                  "arrays.argmax[" + std::to_string(row) +
                      "]: -1 (no information) but the posterior row is not uniform within "
                      "execution.uniform_tolerance");
    }
    if (a >= 0 && uniform) {
      return fail(Status::parse_error, "arrays.argmax[" + std::to_string(row) +
                                           "]: " + std::to_string(a) +
                                           " for a uniform posterior row (must be -1)");
    }
    if (a >= 0 && p[a] < best - 1e-9) {
      return fail(Status::parse_error, "arrays.argmax[" + std::to_string(row) + "]: movement " +
                                           std::to_string(a) +
                                           " is not the most probable of its posterior row");
    }
  }
  MovementRepertoire moves;
  r = MovementRepertoire::create(step, std::move(dirs), std::move(labels), moves);
  if (!r.ok()) return fail(Status::parse_error, r.message);
  Skill skill;
  r = Skill::create(std::move(name), std::move(disc), std::move(table), std::move(moves), settings,
                    std::move(robot), skill);
  if (!r.ok()) return fail(Status::parse_error, r.message);
  out = std::move(skill);
  return Result::success();
}

}  // namespace

Result load_bundle_from_memory(const std::uint8_t* data, std::size_t size, Skill& out,
                               const std::string& source) {
  try {
    return parse(data, size, out, source);
  } catch (const std::bad_alloc&) {
    return Result::failure(Status::parse_error,
                           "skill bundle '" + source + "': out of memory while loading");
  } catch (const std::exception& ex) {
    return Result::failure(Status::parse_error, "skill bundle '" + source + "': " + ex.what());
  } catch (...) {
    return Result::failure(Status::internal_error,
                           "skill bundle '" + source + "': unexpected exception");
  }
}

Result load_bundle(const std::string& path, Skill& out) {
  std::vector<std::uint8_t> bytes;
  try {
    std::ifstream f(path, std::ios::binary);
    if (!f) {
      return Result::failure(Status::file_error, "skill bundle '" + path +
                                                     "': cannot open the file (missing or "
                                                     "unreadable)");
    }
    bytes.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
    if (f.bad()) {
      return Result::failure(Status::file_error, "skill bundle '" + path + "': read error");
    }
  } catch (const std::exception& ex) {
    return Result::failure(Status::file_error,
                           "skill bundle '" + path + "': cannot read: " + ex.what());
  }
  return load_bundle_from_memory(bytes.data(), bytes.size(), out, path);
}

}  // namespace a2l
