//! \file bundle.hpp
//! \brief Loading skill bundles (docs/bundle_format.md): one file, header + JSON manifest +
//! binary arrays, versioned and checksummed.
//!
//! Loading validates everything the format specifies and never crashes nor throws on bad
//! input: it returns a Result whose message names the field or the check that failed
//! (fuzzed by tests/fuzz/fuzz_bundle.cpp). Python writes bundles (a2l.skills.save_bundle) and
//! reads them through this loader (a2l._core.Skill.from_bytes), so there is one validator.
//! The host must be little-endian (as the format).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "a2l/diffeo.hpp"
#include "a2l/skill.hpp"
#include "a2l/status.hpp"

namespace a2l {

//! Schema version this build reads.
constexpr std::uint32_t kBundleSchemaVersion = 4;
//! Size of the fixed header (magic, version, manifest length, manifest CRC, reserved).
constexpr std::size_t kBundleHeaderSize = 24;
//! The 8 magic bytes "A2LBNDL\0".
extern const char kBundleMagic[8];

//! zlib's CRC-32 of `size` bytes.
std::uint32_t bundle_crc32(const void* data, std::size_t size) noexcept;

//! Load and validate a skill bundle file (kind "skill") into `out` (left untouched on
//! failure). A DS section, if present, is validated too.
//! \return `file_error` (missing or unreadable file), `version_mismatch` (schema version of
//!         the header or manifest is not kBundleSchemaVersion), `checksum_mismatch` (manifest
//!         or array CRC), `parse_error` (anything else: magic, JSON, a missing or mistyped
//!         key, shapes, offsets, probabilities...), each with a message naming the file and
//!         the field or check; `ok` on success.
Result load_bundle(const std::string& path, Skill& out);

//! Same as load_bundle() for bundle bytes held in memory; `source` names them in messages.
Result load_bundle_from_memory(const std::uint8_t* data, std::size_t size, Skill& out,
                               const std::string& source = "<memory>");

//! Load and validate the DS section of a bundle file (kind "ds", or kind "skill" with a DS)
//! into `out` (left untouched on failure); every other section present is validated too.
//! \return the statuses of load_bundle(); `parse_error` when the bundle holds no DS or a map
//!         breaks validate_diffeo_maps() (the message names the map's index, e.g.
//!         "ds: ... map 7: rho * ||v|| = 1.3 >= sqrt(e/2)").
Result load_ds_bundle(const std::string& path, DiffeoMaps& out);

//! Same as load_ds_bundle() for bundle bytes held in memory; `source` names them in messages.
Result load_ds_bundle_from_memory(const std::uint8_t* data, std::size_t size, DiffeoMaps& out,
                                  const std::string& source = "<memory>");

}  // namespace a2l
