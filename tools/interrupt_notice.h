// Ctrl-C (SIGINT) or SIGTERM in the middle of `tavis eval`, `demos` or `sweep`: before the program
// ends, one line on stderr says how many episodes were kept in which folder and the exact command
// that finishes the run. The signals are taken by a watcher thread (sigwait), not by a handler, so
// the line is composed with ordinary code (it reads what is on disk, which every record reaches
// as it is written); the program then ends by the same signal, as if it had not been caught (a
// shell sees 130 for Ctrl-C, 143 for SIGTERM), and what it kept is what an uncaught signal keeps.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace tavis::tools {

// In main(), before any thread starts (each inherits the blocked signals): blocks SIGINT and
// SIGTERM in every thread and starts the watcher; `argv` is kept for the commands the line names.
void WatchForInterrupts(int argc, char** argv);

// The line's text, asked for on the watcher thread when a signal comes (empty: no line). Until
// one is set, a signal ends the program at once, as before.
void SetInterruptNotice(std::function<std::string()> describe);

// The command line this program was run with, each word shell-quoted where needed, without the
// options in `drop` (a flag, or an option and its value: "--out DIR" and "--out=DIR") and with
// `add` (already quoted words) at the end.
std::string CommandLineWith(const std::vector<std::string>& drop_flags, const std::vector<std::string>& drop_options,
                            const std::string& add);

// A word as the shell reads it: as it is when it has no special characters, else single-quoted.
std::string ShellWord(const std::string& word);

// "interrupted: 3 episodes kept in FOLDER; to finish WHAT: COMMAND".
std::string KeptLine(int64_t episodes, const std::filesystem::path& folder, const std::string& what,
                     const std::string& command);

// The complete (newline-ended) lines of FILE; 0 when it is absent.
int64_t CompleteLines(const std::filesystem::path& file);

}  // namespace tavis::tools
