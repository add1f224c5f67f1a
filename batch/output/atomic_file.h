// Result files written whole or not at all: the text goes to PATH.partial, which is renamed to
// PATH once written and flushed, so a reader never sees a half-written file under its real name
// and an interrupted run leaves the previous version (or nothing) in place.
#pragma once

#include <filesystem>
#include <string>

namespace tavis::batch::output {

// Throws std::runtime_error naming the file and the system's reason when it cannot be written.
void WriteFileAtomically(const std::filesystem::path& path, const std::string& text);

}  // namespace tavis::batch::output
