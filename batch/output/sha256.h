// SHA-256 (FIPS 180-4) of bytes, as the provenance of a result folder names the files it was made
// from: the same digest `sha256sum FILE` prints, so anyone can check a recorded hash by hand.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

namespace tavis::batch::output {

// The digest as 64 lowercase hex digits.
std::string Sha256Hex(std::string_view bytes);

// "sha256:" and the digest of the file's bytes. Throws std::invalid_argument naming the file when
// it cannot be read.
std::string FileSha256(const std::filesystem::path& path);

}  // namespace tavis::batch::output
