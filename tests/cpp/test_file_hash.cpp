// SHA-256 through OpenSSL's libcrypto: FIPS 180-2 test vectors, files, errors.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "a2l/file_hash.hpp"

namespace test_file_hash {

std::string temp_file(const std::string& name, const std::string& bytes) {
  const auto path = std::filesystem::temp_directory_path() / name;
  std::ofstream(path, std::ios::binary) << bytes;
  return path.string();
}

TEST(FileHash, KnownVectors) {
  std::string hex;
  ASSERT_TRUE(a2l::sha256_hex("", 0, hex).ok());
  EXPECT_EQ(hex, "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  ASSERT_TRUE(a2l::sha256_hex("abc", 3, hex).ok());
  EXPECT_EQ(hex, "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  const std::string two_blocks = "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq";
  ASSERT_TRUE(a2l::sha256_hex(two_blocks.data(), two_blocks.size(), hex).ok());
  EXPECT_EQ(hex, "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

TEST(FileHash, FileEqualsBytes) {
  // Larger than the 64 KiB read buffer, so the file is hashed in several updates.
  std::string bytes(200000, '\0');
  for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<char>((i * 131) % 251);
  const std::string path = temp_file("a2l_test_file_hash.bin", bytes);
  std::string from_file, from_bytes;
  ASSERT_TRUE(a2l::sha256_file(path, from_file).ok());
  ASSERT_TRUE(a2l::sha256_hex(bytes.data(), bytes.size(), from_bytes).ok());
  EXPECT_EQ(from_file, from_bytes);
  bytes[123456] ^= 1;  // one bit changed: another hash
  ASSERT_TRUE(a2l::sha256_file(temp_file("a2l_test_file_hash.bin", bytes), from_file).ok());
  EXPECT_NE(from_file, from_bytes);
  std::remove(path.c_str());
}

TEST(FileHash, MissingFileIsAFileError) {
  std::string hex = "unchanged";
  const a2l::Result r = a2l::sha256_file("/nonexistent/a2l/robot.urdf", hex);
  EXPECT_EQ(r.status, a2l::Status::file_error);
  EXPECT_NE(r.message.find("/nonexistent/a2l/robot.urdf"), std::string::npos);
  EXPECT_EQ(hex, "unchanged");
}

}  // namespace test_file_hash
