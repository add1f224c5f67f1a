// Files a user names as input (a sweep spec, a robot file, an actions CSV) must be regular files:
// a device such as /dev/zero or a FIFO would be read without end, a directory not at all, and the
// libraries' own messages for them ("read error", "bad file") do not say what is wrong.
#pragma once

#include <filesystem>
#include <string>

namespace tavis::configs {

// "" when `path` is a regular file (or a link to one), else what is wrong with it: "no such
// file", "is a directory, not a file", "is a character device, not a regular file", ...
std::string WhyNotARegularFile(const std::filesystem::path& path);

}  // namespace tavis::configs
