#include "a2l/file_hash.hpp"

#include <openssl/evp.h>

#include <array>
#include <fstream>
#include <memory>

namespace a2l {
namespace {

struct MdCtxDeleter {
  void operator()(EVP_MD_CTX* ctx) const noexcept { EVP_MD_CTX_free(ctx); }
};
using MdCtx = std::unique_ptr<EVP_MD_CTX, MdCtxDeleter>;

std::string to_hex(const unsigned char* digest, unsigned int n) {
  static const char kDigits[] = "0123456789abcdef";
  std::string hex(2 * static_cast<std::size_t>(n), '0');
  for (unsigned int i = 0; i < n; ++i) {
    hex[2 * i] = kDigits[digest[i] >> 4];
    hex[2 * i + 1] = kDigits[digest[i] & 0x0f];
  }
  return hex;
}

Result crypto_failure(const char* call) {
  return Result::failure(Status::internal_error,
                         std::string("OpenSSL libcrypto: ") + call + " failed (SHA-256)");
}

}  // namespace

Result sha256_hex(const void* data, std::size_t size, std::string& hex) {
  std::array<unsigned char, EVP_MAX_MD_SIZE> digest{};
  unsigned int n = 0;
  if (EVP_Digest(data, size, digest.data(), &n, EVP_sha256(), nullptr) != 1) {
    return crypto_failure("EVP_Digest");
  }
  hex = to_hex(digest.data(), n);
  return Result::success();
}

Result sha256_file(const std::string& path, std::string& hex) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Result::failure(Status::file_error, "cannot open '" + path + "'");
  MdCtx ctx(EVP_MD_CTX_new());
  if (!ctx) return crypto_failure("EVP_MD_CTX_new");
  if (EVP_DigestInit_ex(ctx.get(), EVP_sha256(), nullptr) != 1) {
    return crypto_failure("EVP_DigestInit_ex");
  }
  std::array<char, 1 << 16> buffer{};
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    const std::streamsize got = in.gcount();
    if (got > 0 && EVP_DigestUpdate(ctx.get(), buffer.data(), static_cast<std::size_t>(got)) != 1) {
      return crypto_failure("EVP_DigestUpdate");
    }
  }
  if (in.bad()) return Result::failure(Status::file_error, "error while reading '" + path + "'");
  std::array<unsigned char, EVP_MAX_MD_SIZE> digest{};
  unsigned int n = 0;
  if (EVP_DigestFinal_ex(ctx.get(), digest.data(), &n) != 1) {
    return crypto_failure("EVP_DigestFinal_ex");
  }
  hex = to_hex(digest.data(), n);
  return Result::success();
}

}  // namespace a2l
