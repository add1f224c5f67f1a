// SHA-256 against the FIPS 180-4 examples and `sha256sum`, a reader we did not write.
#include "batch/output/sha256.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace tavis::batch::output {
namespace {

TEST(Sha256, MatchesTheStandardsExamples) {
  EXPECT_EQ(Sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(Sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  // 56 bytes: the padding spills into a second block.
  EXPECT_EQ(Sha256Hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(Sha256Hex(std::string(1000000, 'a')), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

// Every length around the block boundaries, checked against sha256sum.
TEST(Sha256, FileHashIsWhatSha256sumPrints) {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("tavis_sha256_test_" + std::to_string(getpid()));
  for (const std::size_t size : {0, 1, 55, 56, 63, 64, 65, 119, 120, 128, 1000}) {
    std::string bytes;
    for (std::size_t i = 0; i < size; ++i) bytes += static_cast<char>((i * 131 + 7) % 256);
    std::ofstream(path, std::ios::binary) << bytes;
    FILE* pipe = popen(("sha256sum '" + path.string() + "'").c_str(), "r");
    ASSERT_NE(pipe, nullptr);
    char digest[65] = {};
    ASSERT_EQ(std::fread(digest, 1, 64, pipe), 64u);
    pclose(pipe);
    EXPECT_EQ(FileSha256(path), std::string("sha256:") + digest) << size << " bytes";
  }
  std::filesystem::remove(path);
  EXPECT_THROW(FileSha256(path), std::invalid_argument);
}

}  // namespace
}  // namespace tavis::batch::output
