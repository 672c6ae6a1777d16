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

#include "bundle_json.hpp"

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

using namespace bundle_detail;  // NOLINT: the loader's own helpers

// The skill of a validated bundle's arrays, checked for consistency (into `out` if not null).
Result build_skill(const std::uint8_t* blob, const ArrayEntry& post, const ArrayEntry& amax,
                   std::string name, std::vector<Variable> vars,
                   const std::vector<std::int64_t>& shape, double step,
                   std::vector<Eigen::Vector3i> dirs, std::vector<std::string> labels,
                   std::vector<MovementAction> actions, const SkillSettings& settings,
                   RobotInfo robot, DSPhaseSet phases, Skill* out) {
  std::vector<double> posterior(post.nbytes / 8);
  std::vector<std::int32_t> argmax(amax.nbytes / 4);
  if (!posterior.empty()) std::memcpy(posterior.data(), blob + post.offset, post.nbytes);
  if (!argmax.empty()) std::memcpy(argmax.data(), blob + amax.offset, amax.nbytes);

  Discretizer disc;
  Result r = Discretizer::create(std::move(vars), disc);
  if (!r.ok()) return Result::failure(Status::parse_error, r.message);
  PolicyTable table;
  std::vector<int> ishape(shape.begin(), shape.end());
  r = PolicyTable::create(std::move(ishape), static_cast<int>(dirs.size() + actions.size()),
                          std::move(posterior), std::move(argmax), table);
  if (!r.ok()) return Result::failure(Status::parse_error, "arrays: " + r.message);
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
      return Result::failure(
          Status::parse_error,
          "arrays.argmax[" + std::to_string(row) +
              "]: -1 (no information) but the posterior row is not uniform within "
              "execution.uniform_tolerance");
    }
    if (a >= 0 && uniform) {
      return Result::failure(Status::parse_error, "arrays.argmax[" + std::to_string(row) +
                                                      "]: " + std::to_string(a) +
                                                      " for a uniform posterior row (must be -1)");
    }
    if (a >= 0 && p[a] < best - 1e-9) {
      return Result::failure(Status::parse_error,
                             "arrays.argmax[" + std::to_string(row) + "]: movement " +
                                 std::to_string(a) +
                                 " is not the most probable of its posterior row");
    }
  }
  MovementRepertoire moves;
  r = MovementRepertoire::create(step, std::move(dirs), std::move(labels), moves,
                                 std::move(actions));
  if (!r.ok()) return Result::failure(Status::parse_error, r.message);
  Skill skill;
  r = Skill::create(std::move(name), std::move(disc), std::move(table), std::move(moves), settings,
                    std::move(robot), skill, std::move(phases));
  if (!r.ok()) return Result::failure(Status::parse_error, r.message);
  if (out != nullptr) *out = std::move(skill);
  return Result::success();
}

// Where a bundle's parts lie: the schema version of its header, its manifest's bytes and the
// offset of its blob.
struct Frame {
  std::uint32_t version = 0;
  std::uint32_t mlen = 0;  // manifest length, bytes
  std::uint32_t mcrc = 0;  // manifest CRC-32, as the header says
  const std::uint8_t* manifest = nullptr;
  std::uint64_t blob = 0;  // the blob's offset: the manifest's end, padded to 8 bytes
};

// What a manifest holds, checked on its own (its arrays not yet against the blob).
struct Manifest {
  bool is_skill = false;  // kind "skill" (else "ds")
  std::string name;
  // the skill's parts (kind "skill")
  RobotInfo robot;
  std::vector<Variable> vars;
  double step = 0.0;
  std::vector<Eigen::Vector3i> dirs;
  std::vector<std::string> labels;
  std::vector<MovementAction> actions;
  SkillSettings settings;
  std::vector<std::int64_t> shape;  // the variables' bins (argmax's shape)
  // the DS (section "ds") and the DS phases (section "ds_phases"), when present
  bool has_ds = false, has_phases = false;
  DiffeoMaps maps;
  DSPhaseSet phases;
  std::vector<DiffeoMaps> phase_maps;
  // every array's place in the blob (a skill's posterior and argmax first)
  std::vector<ArrayEntry> entries;
};

// The 24-byte header: magic, schema version (this build's), manifest length and CRC-32, and
// a zero reserved field.
bool check_header(const std::uint8_t* data, std::size_t size, Frame& f, Errors& e) {
  if (data == nullptr && size > 0) return e.fail(Status::invalid_argument, "null data");
  if (size < kBundleHeaderSize) {
    return e.parse("truncated: " + std::to_string(size) +
                   " bytes, shorter than the 24-byte header");
  }
  if (std::memcmp(data, kBundleMagic, 8) != 0) {
    return e.parse("magic: not a skill bundle (the file does not start with 'A2LBNDL\\0')");
  }
  f.version = read_u32(data + 8);
  f.mlen = read_u32(data + 12);
  f.mcrc = read_u32(data + 16);
  const std::uint32_t reserved = read_u32(data + 20);
  if (f.version != kBundleSchemaVersion) {
    return e.fail(Status::version_mismatch, "schema version: the header says " +
                                                std::to_string(f.version) + ", this build reads " +
                                                std::to_string(kBundleSchemaVersion));
  }
  if (reserved != 0) return e.parse("header: reserved field is not 0");
  return true;
}

// The manifest's bytes after the header: within the file, matching the header's CRC-32, and
// followed by zero padding up to the blob.
bool check_manifest_bytes(const std::uint8_t* data, std::size_t size, Frame& f, Errors& e) {
  if (f.mlen > size - kBundleHeaderSize) {
    return e.parse("manifest length: " + std::to_string(f.mlen) +
                   " bytes do not fit in the file (" + std::to_string(size) +
                   " bytes): truncated?");
  }
  f.manifest = data + kBundleHeaderSize;
  const std::uint32_t got_crc = bundle_crc32(f.manifest, f.mlen);
  if (got_crc != f.mcrc) {
    return e.fail(Status::checksum_mismatch, "manifest CRC-32: the header says " +
                                                 std::to_string(f.mcrc) + ", the manifest gives " +
                                                 std::to_string(got_crc));
  }
  f.blob = (kBundleHeaderSize + static_cast<std::uint64_t>(f.mlen) + 7) / 8 * 8;
  if (f.blob > size) return e.parse("truncated: the file ends before its blob");
  for (std::uint64_t i = kBundleHeaderSize + f.mlen; i < f.blob; ++i) {
    if (data[i] != 0) return e.parse("padding after the manifest is not zero");
  }
  return true;
}

// The manifest's bytes as a JSON object.
bool parse_manifest_json(const Frame& f, json& m, Errors& e) {
  try {
    m = json::parse(f.manifest, f.manifest + f.mlen);
  } catch (const json::exception& ex) {
    return e.parse(std::string("manifest JSON: ") + ex.what());
  }
  if (!m.is_object()) return e.parse("manifest: must be a JSON object");
  return true;
}

// The manifest's schema_version (the header's `version`), kind ("skill" when `want_skill`),
// name and created_by.
bool parse_identity(const json& m, std::uint32_t version, bool want_skill, Manifest& out,
                    Errors& e) {
  std::int64_t mversion = 0;
  if (!get_int(m, "", "schema_version", 0, std::numeric_limits<std::int64_t>::max(), mversion, e)) {
    return false;
  }
  if (mversion != version) {
    return e.fail(Status::version_mismatch, "schema_version: the manifest says " +
                                                std::to_string(mversion) + ", the header " +
                                                std::to_string(version));
  }
  std::string kind, created_by;
  if (!get_string(m, "", "kind", kind, e)) return false;
  if (kind != "skill" && kind != "ds") {
    return e.parse("kind: must be 'skill' or 'ds', got '" + kind + "'");
  }
  out.is_skill = kind == "skill";
  if (want_skill && !out.is_skill) {
    return e.parse("kind: 'ds', a bundle holding only a DS (no skill table): load it as a DS");
  }
  return get_string(m, "", "name", out.name, e) && get_string(m, "", "created_by", created_by, e);
}

// The skill's sections of a kind "skill" manifest (target, robot, variables, movements,
// execution), its "arrays" object, and its arrays posterior and argmax (entries 0 and 1)
// within `room` bytes of blob.
bool parse_skill_sections(const json& m, std::uint64_t room, const json*& arrays, Manifest& out,
                          Errors& e) {
  std::string target;
  if (!get_string(m, "", "target", target, e) || !parse_robot(m, out.robot, e) ||
      !parse_variables(m, out.vars, e) ||
      !parse_movements(m, out.step, out.dirs, out.labels, out.actions, e) ||
      !parse_execution(m, out.settings, e)) {
    return false;
  }
  for (const Variable& v : out.vars) out.shape.push_back(v.n_bins);
  std::vector<std::int64_t> pshape = out.shape;
  pshape.push_back(static_cast<std::int64_t>(out.dirs.size() + out.actions.size()));
  if (!get_object(m, "", "arrays", arrays, e)) return false;
  out.entries.resize(2);
  return parse_array(*arrays, "posterior", "float64", 8, pshape, room, out.entries[0], e) &&
         parse_array(*arrays, "argmax", "int32", 4, out.shape, room, out.entries[1], e);
}

// The manifest's "ds" section (required unless it is a skill and no DS is asked for:
// `want_ds`) and its optional "ds_phases" section, their arrays appended to out.entries.
bool parse_ds_sections(const json& m, const json& arrays, std::uint64_t room, bool want_ds,
                       Manifest& out, Errors& e) {
  out.has_ds = m.contains("ds");
  if (!out.has_ds && (!out.is_skill || want_ds)) {
    return e.parse("ds: missing (this bundle holds no DS)");
  }
  if (out.has_ds && !parse_ds_section(m, arrays, room, out.maps, out.entries, e)) return false;
  out.has_phases = m.contains("ds_phases");
  return !out.has_phases ||
         parse_ds_phases(m, arrays, room, out.phases, out.phase_maps, out.entries, e);
}

// The arrays' places: each within the `room` bytes of the blob (at offset `blob` of a file of
// `size` bytes), none overlapping another, and the last ending where the file ends.
bool check_array_layout(const std::vector<ArrayEntry>& entries, std::uint64_t room,
                        std::uint64_t blob, std::size_t size, Errors& e) {
  for (const ArrayEntry& a : entries) {
    if (a.offset > room || a.nbytes > room - a.offset) {
      return e.parse("arrays." + a.name + ": bytes [" + std::to_string(a.offset) + ", +" +
                     std::to_string(a.nbytes) + ") lie outside the file's blob (" +
                     std::to_string(room) + " bytes): truncated?");
    }
  }
  std::uint64_t end = 0;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const ArrayEntry& a = entries[i];
    for (std::size_t j = 0; j < i; ++j) {
      const ArrayEntry& b = entries[j];
      if (a.offset < b.offset + b.nbytes && b.offset < a.offset + a.nbytes) {
        return e.parse("arrays: " + b.name + " and " + a.name + " overlap");
      }
    }
    end = std::max(end, a.offset + a.nbytes);
  }
  if (end != room) {
    return e.parse("file size: " + std::to_string(size) + " bytes, the arrays end at " +
                   std::to_string(blob + end) + " (trailing bytes)");
  }
  return true;
}

// Every array's bytes in `blob` against the CRC-32 the manifest gives.
bool check_array_crcs(const std::uint8_t* blob, const std::vector<ArrayEntry>& entries, Errors& e) {
  for (const ArrayEntry& a : entries) {
    const std::uint32_t c = bundle_crc32(blob + a.offset, a.nbytes);
    if (c != a.crc) {
      return e.fail(Status::checksum_mismatch, "arrays." + a.name + ".crc32: the manifest says " +
                                                   std::to_string(a.crc) + ", the data give " +
                                                   std::to_string(c));
    }
  }
  return true;
}

// Validate bundle bytes (frame, manifest, array layout, checksums) and read the skill into
// `skill` and the DS into `ds` (either may be null); every message starts with the source.
Result parse_unguarded(const std::uint8_t* data, std::size_t size, const std::string& source,
                       Skill* skill, DiffeoMaps* ds) {
  auto fail = [&](Status s, const std::string& msg) {
    return Result::failure(s, "skill bundle '" + source + "': " + msg);
  };
  Errors e;
  auto err = [&]() { return fail(e.status, e.message); };
  Frame f;
  json m;
  if (!check_header(data, size, f, e) || !check_manifest_bytes(data, size, f, e) ||
      !parse_manifest_json(f, m, e)) {
    return err();
  }
  Manifest man;
  if (!parse_identity(m, f.version, skill != nullptr, man, e)) return err();
  const std::uint64_t room = size - f.blob;
  const json* arrays = nullptr;
  if (man.is_skill ? !parse_skill_sections(m, room, arrays, man, e)
                   : !get_object(m, "", "arrays", arrays, e)) {
    return err();
  }
  const std::uint8_t* blob = data + f.blob;
  if (!parse_ds_sections(m, *arrays, room, ds != nullptr, man, e) ||
      !check_array_layout(man.entries, room, f.blob, size, e) ||
      !check_array_crcs(blob, man.entries, e)) {
    return err();
  }
  if (man.has_ds && !read_ds_arrays(blob, man.entries, man.maps, e)) return err();
  if (man.has_phases && !read_ds_phases(blob, man.entries, man.phase_maps, man.phases, e)) {
    return err();
  }
  if (man.is_skill) {
    Result r = build_skill(blob, man.entries[0], man.entries[1], std::move(man.name),
                           std::move(man.vars), man.shape, man.step, std::move(man.dirs),
                           std::move(man.labels), std::move(man.actions), man.settings,
                           std::move(man.robot), std::move(man.phases), skill);
    if (!r.ok()) return fail(Status::parse_error, r.message);
  }
  if (ds != nullptr) *ds = std::move(man.maps);
  return Result::success();
}

}  // namespace

Result bundle_detail::parse_bundle(const std::uint8_t* data, std::size_t size,
                                   const std::string& source, Skill* skill, DiffeoMaps* ds) {
  try {
    return parse_unguarded(data, size, source, skill, ds);
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

Result bundle_detail::read_file(const std::string& path, std::vector<std::uint8_t>& bytes) {
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
  return Result::success();
}

Result load_bundle_from_memory(const std::uint8_t* data, std::size_t size, Skill& out,
                               const std::string& source) {
  return parse_bundle(data, size, source, &out, nullptr);
}

Result load_bundle(const std::string& path, Skill& out) {
  std::vector<std::uint8_t> bytes;
  Result r = read_file(path, bytes);
  if (!r.ok()) return r;
  return load_bundle_from_memory(bytes.data(), bytes.size(), out, path);
}

}  // namespace a2l
