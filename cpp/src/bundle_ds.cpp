// The DS section of a skill bundle (docs/bundle_format.md, "ds"): parsing, and loading a
// bundle's DS (kind "ds", or kind "skill" with a DS).
#include <cstring>

#include "a2l/bundle.hpp"
#include "bundle_json.hpp"

namespace a2l {

bool bundle_detail::parse_ds_object(const json& ds, const std::string& where, const json& arrays,
                                    const std::string& prefix, std::uint64_t room, DiffeoMaps& maps,
                                    std::vector<ArrayEntry>& entries, Errors& e) {
  std::int64_t dim = 0, k = 0;
  if (!get_int(ds, where, "dim", 2, 3, dim, e) ||
      !get_int(ds, where, "n_maps", 0, kDiffeoMaxMaps, k, e)) {
    return false;
  }
  maps = DiffeoMaps{};
  maps.dim = static_cast<int>(dim);
  if (!get_number(ds, where, "speed", maps.speed, e)) return false;
  if (!(maps.speed > 0.0)) return e.parse(where + "speed: must be > 0");
  std::string direction;
  if (!get_string(ds, where, "direction", direction, e)) return false;
  if (direction == "to_demo") {
    maps.direction = DiffeoDirection::to_demo;
  } else if (direction == "to_line") {
    maps.direction = DiffeoDirection::to_line;
  } else {
    return e.parse(where + "direction: must be \"to_demo\" or \"to_line\", got \"" + direction +
                   "\"");
  }
  const json* target = nullptr;
  if (!get_array(ds, where, "target", target, e)) return false;
  if (target->size() != static_cast<std::size_t>(dim)) {
    return e.parse(where + "target: has " + std::to_string(target->size()) + " coordinates, " +
                   where + "dim is " + std::to_string(dim));
  }
  for (std::size_t j = 0; j < target->size(); ++j) {
    const json& t = (*target)[j];
    const std::string field = where + "target[" + std::to_string(j) + "]";
    if (!t.is_number()) return e.parse(field + ": must be a number, got " + type_name(t));
    const double x = t.get<double>();
    if (!std::isfinite(x)) return e.parse(field + ": must be finite");
    maps.target.push_back(x);
  }
  const std::string given_by = where + "n_maps and " + where + "dim";
  const std::vector<std::int64_t> kd = {k, dim}, kk = {k};
  const std::string nc = prefix + "centers", nv = prefix + "vectors", nr = prefix + "rhos";
  ArrayEntry c, v, r;
  if (!parse_array(arrays, nc.c_str(), "float64", 8, kd, room, c, e, given_by.c_str(),
                   kDiffeoMaxMaps) ||
      !parse_array(arrays, nv.c_str(), "float64", 8, kd, room, v, e, given_by.c_str(),
                   kDiffeoMaxMaps) ||
      !parse_array(arrays, nr.c_str(), "float64", 8, kk, room, r, e, given_by.c_str(),
                   kDiffeoMaxMaps)) {
    return false;
  }
  entries.push_back(c);
  entries.push_back(v);
  entries.push_back(r);
  return true;
}

bool bundle_detail::parse_ds_section(const json& m, const json& arrays, std::uint64_t room,
                                     DiffeoMaps& maps, std::vector<ArrayEntry>& entries,
                                     Errors& e) {
  const json* ds = nullptr;
  if (!get_object(m, "", "ds", ds, e)) return false;
  return parse_ds_object(*ds, "ds.", arrays, "ds_", room, maps, entries, e);
}

bool bundle_detail::read_ds_maps(const std::uint8_t* blob, const std::vector<ArrayEntry>& entries,
                                 const std::string& prefix, const std::string& where,
                                 DiffeoMaps& maps, Errors& e) {
  for (const ArrayEntry& a : entries) {
    std::vector<double>* dst = a.name == prefix + "centers"   ? &maps.centers
                               : a.name == prefix + "vectors" ? &maps.vectors
                               : a.name == prefix + "rhos"    ? &maps.rhos
                                                              : nullptr;
    if (dst == nullptr) continue;
    dst->resize(a.nbytes / 8);
    if (a.nbytes > 0) std::memcpy(dst->data(), blob + a.offset, a.nbytes);
  }
  // the validator names the first bad map ("map 7: rho * ||v|| = ... >= sqrt(e/2)")
  const Result r = validate_diffeo_maps(maps);
  if (!r.ok()) return e.parse(where + r.message);
  return true;
}

bool bundle_detail::read_ds_arrays(const std::uint8_t* blob, const std::vector<ArrayEntry>& entries,
                                   DiffeoMaps& maps, Errors& e) {
  return read_ds_maps(blob, entries, "ds_", "ds: ", maps, e);
}

Result load_ds_bundle_from_memory(const std::uint8_t* data, std::size_t size, DiffeoMaps& out,
                                  const std::string& source) {
  return bundle_detail::parse_bundle(data, size, source, nullptr, &out);
}

Result load_ds_bundle(const std::string& path, DiffeoMaps& out) {
  std::vector<std::uint8_t> bytes;
  Result r = bundle_detail::read_file(path, bytes);
  if (!r.ok()) return r;
  return load_ds_bundle_from_memory(bytes.data(), bytes.size(), out, path);
}

}  // namespace a2l
