// Option values shared by the subcommands, parsed and listed the same way everywhere.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "batch/output/setting_error.h"

namespace tavis::tools {

// "224x224" -> (224, 224); throws std::invalid_argument naming the value.
std::pair<int, int> ParseImageSize(const std::string& text);

// A seed: a decimal integer from 0 to 2^64 - 1. Anything else (negative, 2^64 or more, not an
// integer) throws std::invalid_argument naming the value; nothing is clamped.
uint64_t ParseSeed(const std::string& text);

// Adds --seed, parsed by ParseSeed into `seed` (which must outlive the parse).
CLI::Option* AddSeedOption(CLI::App& command, uint64_t& seed, const std::string& help);

// A finite number within [low, high]; throws std::invalid_argument naming `option`, the range
// and the value, saying "out of range" for a literal beyond the range of a double (1e400).
double ParseNumberInRange(const std::string& option, const std::string& text, double low, double high);

// Checks an integer option's text before CLI11 converts it, so a bad value reads "must be an
// integer from LOW to HIGH, got 'TEXT'" rather than CLI11's conversion error or a 309-digit bound.
CLI::Validator IntegerIn(int64_t low, int64_t high);
// The same for a number (seconds, rates): finite, within [low, high].
CLI::Validator NumberIn(double low, double high);
// For an integer that must be one of `choices`: text that is no integer at all reads "must be 60
// or 20, got 'sixty'" rather than CLI11's "Could not convert: --fps = sixty", which names no value
// allowed. Which integer is allowed stays the setting's own check, which names it the same way.
CLI::Validator IntegerNamingChoices(const std::vector<double>& choices);

// The library names a bad setting by its key; a command names the flag the user typed:
// std::invalid_argument("FLAG PROBLEM").
[[noreturn]] void ThrowNamingFlag(const batch::output::SettingError& error, const std::string& flag);

// Throws std::invalid_argument unless `dir` is a folder holding robots/*.yaml, so that a wrong
// --config-dir is reported as such rather than as an unknown robot.
void RequireConfigDir(const std::string& dir);

// Adds --config-dir, checked by RequireConfigDir, into `dir` (set to DefaultConfigDir() until given).
CLI::Option* AddConfigDirOption(CLI::App& command, std::string& dir);

// The default --config-dir: share/tavis/configs next to an installed binary (bin/../share), else
// the source tree's configs of the build that made it.
std::string DefaultConfigDir();

}  // namespace tavis::tools
