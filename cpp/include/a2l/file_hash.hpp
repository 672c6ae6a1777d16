//! \file file_hash.hpp
//! \brief SHA-256 of bytes and of files, computed by OpenSSL's libcrypto (EVP interface).
//!
//! A skill bundle records the SHA-256 of the URDF it was learned on (docs/bundle_format.md);
//! `a2l-run` compares it with the URDF it loads. Set-up code: these functions allocate.
#pragma once

#include <cstddef>
#include <string>

#include "a2l/status.hpp"

namespace a2l {

//! SHA-256 of `size` bytes as 64 lowercase hexadecimal characters.
//! \return `ok`, or `internal_error` if libcrypto fails (message says which call).
Result sha256_hex(const void* data, std::size_t size, std::string& hex);

//! SHA-256 of the bytes of the file at `path`, as 64 lowercase hexadecimal characters.
//! \return `file_error` naming the file when it cannot be opened or read, `internal_error` if
//!         libcrypto fails, `ok` otherwise (`hex` is left untouched on failure).
Result sha256_file(const std::string& path, std::string& hex);

}  // namespace a2l
