#include "batch/action_csv.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include <zlib.h>

#include "configs/input_file.h"

namespace tavis::batch {
namespace {

std::string_view Trim(std::string_view text) {
  const auto is_space = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (!text.empty() && is_space(text.front())) text.remove_prefix(1);
  while (!text.empty() && is_space(text.back())) text.remove_suffix(1);
  return text;
}

std::vector<std::string_view> SplitFields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t begin = 0;
  while (true) {
    const std::size_t comma = line.find(',', begin);
    fields.push_back(Trim(line.substr(begin, comma - begin)));
    if (comma == std::string_view::npos) return fields;
    begin = comma + 1;
  }
}

// The whole field as a double (correctly rounded, like Python's float()), or nullopt; a number
// beyond the double range reads as infinity so that it is reported as non-finite.
std::optional<double> ParseNumber(std::string_view field) {
  if (!field.empty() && field.front() == '+') field.remove_prefix(1);
  if (field.empty()) return std::nullopt;
  double value = 0.0;
  const char* const end = field.data() + field.size();
  const auto [parsed_end, error] = std::from_chars(field.data(), end, value);
  if (parsed_end != end) return std::nullopt;
  if (error == std::errc::result_out_of_range) return HUGE_VAL;
  if (error != std::errc()) return std::nullopt;
  return value;
}

[[noreturn]] void FailAt(const std::string& source, int line_number, const std::string& what) {
  throw std::runtime_error(source + ":" + std::to_string(line_number) + ": " + what);
}

void CheckColumnCount(const std::vector<std::string_view>& fields, int columns, const std::string& source,
                      int line_number) {
  if (static_cast<int>(fields.size()) != columns) {
    FailAt(source, line_number,
           "expected " + std::to_string(columns) + " comma-separated values, found " + std::to_string(fields.size()));
  }
}

bool IsHeader(const std::vector<std::string_view>& fields) {
  for (const std::string_view field : fields) {
    if (ParseNumber(field)) return false;
  }
  return true;
}

constexpr const char* kUtf8ByteOrderMark = "\xEF\xBB\xBF";

// The file's bytes, a gzip stream decompressed (zlib reads any other file as it is).
std::string ReadMaybeCompressed(const std::filesystem::path& path) {
  gzFile file = gzopen(path.c_str(), "rb");
  if (file == nullptr) throw std::runtime_error(path.string() + ": cannot open file");
  std::string text;
  char buffer[1 << 16];
  int read = 0;
  while ((read = gzread(file, buffer, sizeof(buffer))) > 0) text.append(buffer, static_cast<std::size_t>(read));
  // A stream cut short reads as its first part, then end of file with Z_BUF_ERROR: damaged too.
  int code = Z_OK;
  const std::string why = gzerror(file, &code);
  gzclose(file);
  if (read < 0 || (code != Z_OK && code != Z_STREAM_END))
    throw std::runtime_error(path.string() + ": damaged gzip data: " + why);
  return text;
}

void WriteGzip(const std::filesystem::path& path, const std::string& text) {
  // "wb9": the smallest files (actions compress 2.2x at any level; 9 costs little at this size).
  gzFile file = gzopen(path.c_str(), "wb9");
  bool ok = file != nullptr;
  if (ok && !text.empty())
    ok = gzwrite(file, text.data(), static_cast<unsigned>(text.size())) == static_cast<int>(text.size());
  if (file != nullptr) ok = gzclose(file) == Z_OK && ok;
  if (!ok) throw std::runtime_error(path.string() + ": cannot write");
}

}  // namespace

ActionTrajectory ParseActionCsv(std::istream& in, const std::string& source, int columns) {
  ActionTrajectory trajectory;
  trajectory.num_columns = columns;
  std::string line;
  int line_number = 0;
  bool first_line = true;
  while (std::getline(in, line)) {
    ++line_number;
    // Spreadsheet programs start a UTF-8 CSV with a byte order mark, invisible in an error message.
    if (line_number == 1 && line.rfind(kUtf8ByteOrderMark, 0) == 0)
      line.erase(0, std::string_view(kUtf8ByteOrderMark).size());
    if (Trim(line).empty()) continue;
    const std::vector<std::string_view> fields = SplitFields(line);
    CheckColumnCount(fields, columns, source, line_number);
    const bool header = first_line && IsHeader(fields);
    first_line = false;
    if (header) continue;
    for (std::size_t column = 0; column < fields.size(); ++column) {
      const std::optional<double> value = ParseNumber(fields[column]);
      if (!value || !std::isfinite(*value)) {
        FailAt(source, line_number,
               "column " + std::to_string(column + 1) + ": " +
                   (value ? "non-finite or out-of-range value '" : "not a number: '") + std::string(fields[column]) +
                   "'");
      }
      trajectory.values.push_back(*value);
    }
    ++trajectory.num_steps;
  }
  if (in.bad()) throw std::runtime_error(source + ": read error");
  if (trajectory.num_steps == 0) throw std::runtime_error(source + ": no data rows");
  return trajectory;
}

ActionTrajectory ReadActionCsv(const std::filesystem::path& path, int columns) {
  const std::string not_a_file = configs::WhyNotARegularFile(path);
  if (!not_a_file.empty()) throw std::runtime_error(path.string() + ": " + not_a_file);
  std::istringstream in(ReadMaybeCompressed(path));
  return ParseActionCsv(in, path.string(), columns);
}

std::string EpisodeActionsName(int64_t episode) { return "episode_" + std::to_string(episode) + ".csv.gz"; }

std::filesystem::path FindEpisodeActions(const std::filesystem::path& folder, int64_t episode) {
  const std::filesystem::path plain = folder / ("episode_" + std::to_string(episode) + ".csv");
  if (std::filesystem::exists(plain)) return plain;
  const std::filesystem::path compressed = folder / EpisodeActionsName(episode);
  return std::filesystem::exists(compressed) ? compressed : std::filesystem::path();
}

void WriteActionCsv(const std::filesystem::path& path, const std::vector<kinematics::Action>& rows,
                    ActionFileFormat format) {
  std::string text;
  char number[32];
  for (const kinematics::Action& action : rows) {
    for (std::size_t column = 0; column < action.size(); ++column) {
      const auto result = std::to_chars(number, number + sizeof(number), action[column]);
      if (column > 0) text += ',';
      text.append(number, result.ptr);
    }
    text += '\n';
  }
  if (format == ActionFileFormat::kGzip) return WriteGzip(path, text);
  std::ofstream out(path);
  if (!out || !(out << text) || !out.flush()) throw std::runtime_error(path.string() + ": cannot write");
}

}  // namespace tavis::batch
