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

Result parse_unguarded(const std::uint8_t* data, std::size_t size, const std::string& source,
                       Skill* skill, DiffeoMaps* ds) {
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
  if (kind != "skill" && kind != "ds") {
    return fail(Status::parse_error, "kind: must be 'skill' or 'ds', got '" + kind + "'");
  }
  const bool is_skill = kind == "skill";
  if (skill != nullptr && !is_skill) {
    return fail(Status::parse_error,
                "kind: 'ds', a bundle holding only a DS (no skill table): load it as a DS");
  }
  if (!get_string(m, "", "name", name, e) || !get_string(m, "", "created_by", created_by, e)) {
    return err();
  }
  const json* arrays = nullptr;
  const std::uint64_t room = size - blob;
  std::vector<ArrayEntry> entries;
  RobotInfo robot;
  std::vector<Variable> vars;
  double step = 0.0;
  std::vector<Eigen::Vector3i> dirs;
  std::vector<std::string> labels;
  std::vector<MovementAction> actions;
  SkillSettings settings;
  std::vector<std::int64_t> shape;
  if (is_skill) {
    if (!get_string(m, "", "target", target, e) || !parse_robot(m, robot, e) ||
        !parse_variables(m, vars, e) || !parse_movements(m, step, dirs, labels, actions, e) ||
        !parse_execution(m, settings, e)) {
      return err();
    }
    for (const Variable& v : vars) shape.push_back(v.n_bins);
    std::vector<std::int64_t> pshape = shape;
    pshape.push_back(static_cast<std::int64_t>(dirs.size() + actions.size()));
    if (!get_object(m, "", "arrays", arrays, e)) return err();
    entries.resize(2);
    if (!parse_array(*arrays, "posterior", "float64", 8, pshape, room, entries[0], e) ||
        !parse_array(*arrays, "argmax", "int32", 4, shape, room, entries[1], e)) {
      return err();
    }
  } else if (!get_object(m, "", "arrays", arrays, e)) {
    return err();
  }
  DiffeoMaps maps;
  const bool has_ds = m.contains("ds");
  if (!has_ds && (!is_skill || ds != nullptr)) {
    return fail(Status::parse_error, "ds: missing (this bundle holds no DS)");
  }
  if (has_ds && !parse_ds_section(m, *arrays, room, maps, entries, e)) return err();
  DSPhaseSet phases;
  std::vector<DiffeoMaps> phase_maps;
  const bool has_phases = m.contains("ds_phases");
  if (has_phases && !parse_ds_phases(m, *arrays, room, phases, phase_maps, entries, e)) {
    return err();
  }
  for (const ArrayEntry& a : entries) {
    if (a.offset > room || a.nbytes > room - a.offset) {
      return fail(Status::parse_error, "arrays." + a.name + ": bytes [" + std::to_string(a.offset) +
                                           ", +" + std::to_string(a.nbytes) +
                                           ") lie outside the file's blob (" +
                                           std::to_string(room) + " bytes): truncated?");
    }
  }
  std::uint64_t end = 0;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const ArrayEntry& a = entries[i];
    for (std::size_t j = 0; j < i; ++j) {
      const ArrayEntry& b = entries[j];
      if (a.offset < b.offset + b.nbytes && b.offset < a.offset + a.nbytes) {
        return fail(Status::parse_error, "arrays: " + b.name + " and " + a.name + " overlap");
      }
    }
    end = std::max(end, a.offset + a.nbytes);
  }
  if (end != room) {
    return fail(Status::parse_error, "file size: " + std::to_string(size) +
                                         " bytes, the arrays end at " + std::to_string(blob + end) +
                                         " (trailing bytes)");
  }
  for (const ArrayEntry& a : entries) {
    const std::uint32_t c = bundle_crc32(data + blob + a.offset, a.nbytes);
    if (c != a.crc) {
      return fail(Status::checksum_mismatch, "arrays." + a.name + ".crc32: the manifest says " +
                                                 std::to_string(a.crc) + ", the data give " +
                                                 std::to_string(c));
    }
  }
  if (has_ds && !read_ds_arrays(data + blob, entries, maps, e)) return err();
  if (has_phases && !read_ds_phases(data + blob, entries, phase_maps, phases, e)) return err();
  if (is_skill) {
    Result r = build_skill(data + blob, entries[0], entries[1], std::move(name), std::move(vars),
                           shape, step, std::move(dirs), std::move(labels), std::move(actions),
                           settings, std::move(robot), std::move(phases), skill);
    if (!r.ok()) return fail(Status::parse_error, r.message);
  }
  if (ds != nullptr) *ds = std::move(maps);
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
