#include "tools/option_parsing.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace tavis::tools {

namespace fs = std::filesystem;

std::pair<int, int> ParseImageSize(const std::string& text) {
  int width = 0;
  int height = 0;
  char trailing = 0;
  if (std::sscanf(text.c_str(), "%dx%d%c", &width, &height, &trailing) != 2 || width < 1 || height < 1) {
    throw std::invalid_argument("--image-size '" + text +
                                "' must be WIDTHxHEIGHT with positive integers, e.g. 224x224");
  }
  return {width, height};
}

uint64_t ParseSeed(const std::string& text) {
  const bool digits = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
  errno = 0;
  const unsigned long long value = digits ? std::strtoull(text.c_str(), nullptr, 10) : 0;
  if (!digits || errno == ERANGE) {
    throw std::invalid_argument("--seed must be an integer from 0 to " +
                                std::to_string(std::numeric_limits<uint64_t>::max()) + ", got " + text);
  }
  return value;
}

CLI::Option* AddSeedOption(CLI::App& command, uint64_t& seed, const std::string& help) {
  // A function option: CLI11's own unsigned conversion clamps 2^64 and more to 2^64 - 1.
  return command
      .add_option_function<std::string>(
          "--seed", [&seed](const std::string& text) { seed = ParseSeed(text); }, help)
      ->default_str(std::to_string(seed));
}

double ParseNumberInRange(const std::string& option, const std::string& text, double low, double high) {
  std::ostringstream range;
  range << "from " << low << " to " << high;
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(text.c_str(), &end);
  const bool number = !text.empty() && end != text.c_str() && *end == '\0';
  if (number && errno == ERANGE) {
    throw std::invalid_argument(option + " " + text + " is out of range: it must be " + range.str());
  }
  if (!number || !std::isfinite(value) || value < low || value > high) {
    throw std::invalid_argument(option + " must be a number " + range.str() + ", got " + text);
  }
  return value;
}

void ThrowNamingFlag(const batch::output::SettingError& error, const std::string& flag) {
  throw std::invalid_argument(flag + " " + error.problem());
}

void RequireConfigDir(const std::string& dir) {
  std::error_code error;
  if (!fs::is_directory(dir, error)) {
    throw std::invalid_argument("--config-dir '" + dir + "' does not exist or is not a folder");
  }
  const fs::path robots = fs::path(dir) / "robots";
  if (fs::is_directory(robots, error)) {
    for (const auto& entry : fs::directory_iterator(robots, error)) {
      if (entry.path().extension() == ".yaml") return;
    }
  }
  throw std::invalid_argument("--config-dir '" + dir + "' has no robots/*.yaml");
}

CLI::Option* AddConfigDirOption(CLI::App& command, std::string& dir) {
  dir = DefaultConfigDir();
  return command
      .add_option_function<std::string>(
          "--config-dir",
          [&dir](const std::string& text) {
            RequireConfigDir(text);
            dir = text;
          },
          "Directory holding robots/*.yaml")
      ->default_str(dir);
}

std::string DefaultConfigDir() {
  std::error_code error;
  const fs::path exe = fs::read_symlink("/proc/self/exe", error);
  if (!error) {
    const fs::path installed = exe.parent_path().parent_path() / "share" / "tavis" / "configs";
    if (fs::is_directory(installed / "robots", error)) return installed.string();
  }
  return TAVIS_DEFAULT_CONFIG_DIR;
}

namespace {

// `text` as a whole decimal integer (nothing after it), or nullopt.
std::optional<long long> WholeInteger(const std::string& text) {
  std::size_t used = 0;
  try {
    const long long value = std::stoll(text, &used);
    if (used == text.size()) return value;
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

}  // namespace

CLI::Validator IntegerIn(int64_t low, int64_t high) {
  const std::string range = "an integer from " + std::to_string(low) + " to " + std::to_string(high);
  return CLI::Validator(
      [low, high, range](std::string& text) -> std::string {
        const std::optional<long long> value = WholeInteger(text);
        if (!value || *value < low || *value > high) return "must be " + range + ", got '" + text + "'";
        return "";
      },
      range);
}

CLI::Validator NumberIn(double low, double high) {
  std::ostringstream text_of_range;
  text_of_range << "a number from " << low << " to " << high;
  const std::string range = text_of_range.str();
  return CLI::Validator(
      [low, high, range](std::string& text) -> std::string {
        std::size_t used = 0;
        double value = std::nan("");
        try {
          value = std::stod(text, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (used != text.size() || text.empty() || !(value >= low && value <= high))
          return "must be " + range + ", got '" + text + "'";
        return "";
      },
      range);
}

CLI::Validator IntegerNamingChoices(const std::vector<double>& choices) {
  std::string allowed;
  for (std::size_t i = 0; i < choices.size(); ++i) {
    allowed += (i == 0 ? "" : i + 1 == choices.size() ? " or " : ", ") + std::to_string(std::llround(choices[i]));
  }
  return CLI::Validator(
      [allowed](std::string& text) -> std::string {
        return WholeInteger(text) ? "" : "must be " + allowed + ", got '" + text + "'";
      },
      allowed);
}

}  // namespace tavis::tools
