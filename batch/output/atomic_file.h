// Result files written whole or not at all: the text goes to PATH.partial, which is renamed to
// PATH once written and flushed, so a reader never sees a half-written file under its real name
// and an interrupted run leaves the previous version (or nothing) in place. Neither name is
// followed when it is a symbolic link: one planted in tavis's folder is replaced, never written
// through, so nothing outside the folder is truncated or filled.
#pragma once

#include <filesystem>
#include <string>

namespace tavis::batch::output {

// Throws std::runtime_error naming the file and the system's reason when it cannot be written.
void WriteFileAtomically(const std::filesystem::path& path, const std::string& text);

// PATH.partial, with whatever was there (an interrupted write's file, or a link, which is removed
// and not followed) gone: a writer that creates the file by name then cannot write through a
// planted link. Throws std::runtime_error naming it when it cannot be removed.
std::filesystem::path FreshPartialPath(const std::filesystem::path& path);

// Renames PATH.partial to PATH (a link at PATH is replaced, not followed). Throws
// std::runtime_error naming both and the system's reason.
void RenamePartialIntoPlace(const std::filesystem::path& path);

}  // namespace tavis::batch::output
