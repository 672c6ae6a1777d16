// libFuzzer target for the skill bundle loader (docs/bundle_format.md): any bytes must give a
// Result, never a crash, a leak, an exception or undefined behaviour (run under ASan + UBSan by
// `make fuzz`). Random mutations almost always break a CRC, so each input is also loaded with
// its checksums repaired (manifest CRC in the header, then the arrays' CRCs in the manifest),
// which lets the fuzzer reach the JSON parser and every validator behind the checksums. When
// the bytes do load, the skill must be consistent: step() on contexts derived from the input
// stays in bounds, and an action (open, close, stay) displaces nothing. The DS section is
// loaded too (load_ds_bundle_from_memory): loaded maps must build a DiffeoDS (either direction,
// ds.direction), whose evaluation on points derived from the input returns a status; DS phases
// step within one movement.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "a2l/bundle.hpp"
#include "a2l/diffeo.hpp"
#include "a2l/skill.hpp"

namespace {

std::uint32_t get_u32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

void put_u32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}

double coordinate(const std::uint8_t* data, std::size_t size, std::size_t at) {
  std::uint64_t bits = 0;
  if (size >= 8) std::memcpy(&bits, data + (at % (size - 7)), 8);
  return static_cast<double>(bits % 4001) / 1000.0 - 2.0;  // [-2, 2]
}

template <int D>
void exercise_ds(const a2l::DiffeoMaps& maps, const std::uint8_t* data, std::size_t size) {
  a2l::DiffeoDS<D> ds;
  if (!a2l::DiffeoDS<D>::create(maps, ds).ok()) __builtin_trap();  // the loader validated them
  using Vec = typename a2l::DiffeoDS<D>::Vec;
  Vec out[4];
  for (int k = 0; k < 8; ++k) {
    Vec x, y, z;
    for (int j = 0; j < D; ++j)
      x[j] = coordinate(data, size, static_cast<std::size_t>(k * D + j) * 8);
    typename a2l::DiffeoDS<D>::Mat j;
    for (const a2l::Status s : {ds.forward(x, y), ds.inverse(x, y), ds.velocity(x, y, z),
                                ds.jacobian(x, y, j), ds.rollout(x, 0.1, 4, out)}) {
      if (s != a2l::Status::ok && s != a2l::Status::invalid_argument) __builtin_trap();
    }
  }
}

void exercise(const std::uint8_t* data, std::size_t size) {
  a2l::DiffeoMaps maps;
  const a2l::Result rd = a2l::load_ds_bundle_from_memory(data, size, maps, "fuzz");
  if (!rd.ok() && rd.message.empty()) __builtin_trap();
  if (rd.ok()) {
    if (maps.dim == 2) {
      exercise_ds<2>(maps, data, size);
    } else if (maps.dim == 3) {
      exercise_ds<3>(maps, data, size);
    } else {
      __builtin_trap();
    }
  }
  a2l::Skill skill;
  const a2l::Result r = a2l::load_bundle_from_memory(data, size, skill, "fuzz");
  if (!r.ok()) {
    if (r.message.empty()) __builtin_trap();  // every failure names its check
    return;
  }
  a2l::SkillState state(skill, 8);
  a2l::StepOutput out;
  for (int k = 0; k < 16; ++k) {
    a2l::Context c;
    double v[6];
    for (int i = 0; i < 6; ++i) {
      std::uint64_t bits = 0;
      const std::size_t at = (static_cast<std::size_t>(k) * 6 + static_cast<std::size_t>(i)) * 8;
      if (size >= 8) std::memcpy(&bits, data + (at % (size - 7)), 8);
      v[i] = static_cast<double>(bits % 4001) / 10000.0 - 0.2;  // [-0.2, 0.2] m
    }
    c.eef = {v[0], v[1], v[2]};
    c.object = {v[3], v[4], v[5]};
    c.effect = k % 5 - 1;
    for (int i = 0; i < a2l::kMaxVariables; ++i) {
      c.high_level[static_cast<std::size_t>(i)] = (k + i) % 3;
    }
    state.smoothing = (k % 2) ? a2l::Smoothing::on : a2l::Smoothing::off;
    const a2l::Status s = a2l::step(skill, state, c, out);
    if (s == a2l::Status::ok && (out.movement < 0 || out.movement >= skill.n_moves())) {
      __builtin_trap();
    }
    if (!skill.ds_phases().empty()) {  // the DS phases: bounded steps, never a crash
      a2l::DSStateValues values{};
      for (std::size_t i = 0; i < values.size(); ++i) values[i] = (k + static_cast<int>(i)) % 3;
      a2l::StepOutput o;
      const a2l::Status sd = a2l::step_ds(skill, state, c.eef, c.object, values, o);
      if (sd == a2l::Status::ok &&
          !(o.displacement.norm() <= skill.movements().step() * 1.000001)) {
        __builtin_trap();
      }
    }
    // an action displaces nothing; a displacement is no action
    if (s == a2l::Status::ok &&
        (out.action != skill.movements().action(out.movement) ||
         (out.action != a2l::MovementAction::none && !out.displacement.isZero()))) {
      __builtin_trap();
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  exercise(data, size);
  if (size < a2l::kBundleHeaderSize) return 0;
  const std::uint32_t mlen = get_u32(data + 12);
  if (mlen > size - a2l::kBundleHeaderSize) return 0;

  // 1. The manifest CRC repaired.
  std::vector<std::uint8_t> b(data, data + size);
  put_u32(b.data() + 16, a2l::bundle_crc32(b.data() + 24, mlen));
  exercise(b.data(), b.size());

  // 2. The arrays' CRCs repaired too (when the manifest parses and names them in range).
  const std::size_t blob = (24 + static_cast<std::size_t>(mlen) + 7) / 8 * 8;
  if (blob > size) return 0;
  nlohmann::json m = nlohmann::json::parse(b.begin() + 24, b.begin() + 24 + mlen, nullptr,
                                           /*allow_exceptions=*/false);
  if (!m.is_object() || !m.contains("arrays") || !m["arrays"].is_object()) return 0;
  bool changed = false;
  for (auto& [name, a] : m["arrays"].items()) {
    if (!a.is_object() || !a.contains("offset") || !a.contains("nbytes")) continue;
    if (!a["offset"].is_number_unsigned() || !a["nbytes"].is_number_unsigned()) continue;
    const std::uint64_t off = a["offset"].get<std::uint64_t>();
    const std::uint64_t nb = a["nbytes"].get<std::uint64_t>();
    if (off > size - blob || nb > size - blob - off) continue;
    a["crc32"] = a2l::bundle_crc32(data + blob + off, nb);
    changed = true;
  }
  if (!changed) return 0;
  std::string text;
  try {
    text = m.dump();
  } catch (const nlohmann::json::exception&) {
    return 0;  // invalid UTF-8 in a string: not serialisable
  }
  std::vector<std::uint8_t> c(24, 0);
  std::memcpy(c.data(), data, 24);
  put_u32(c.data() + 12, static_cast<std::uint32_t>(text.size()));
  put_u32(c.data() + 16, a2l::bundle_crc32(text.data(), text.size()));
  c.insert(c.end(), text.begin(), text.end());
  c.resize((c.size() + 7) / 8 * 8, 0);
  c.insert(c.end(), data + blob, data + size);
  exercise(c.data(), c.size());
  return 0;
}
