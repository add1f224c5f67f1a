#include "tests/batch/dataset/parquet_fixtures.h"

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <stdexcept>

namespace tavis::batch::dataset::testing {
namespace {

using nlohmann::json;

json ToJson(std::int64_t value) { return std::to_string(value); }
json ToJson(std::int32_t value) { return value; }
json ToJson(float value) { return static_cast<double>(value); }
json ToJson(double value) { return value; }
json ToJson(bool value) { return value; }
json ToJson(const std::string& value) { return value; }

// The items [first, first + product(shape)) of `values` as arrays nested like `shape`.
template <typename T>
json Nested(const std::vector<T>& values, std::size_t first, const std::vector<std::size_t>& shape, std::size_t axis) {
  json array = json::array();
  std::size_t stride = 1;
  for (std::size_t inner = axis + 1; inner < shape.size(); ++inner) stride *= shape[inner];
  for (std::size_t i = 0; i < shape[axis]; ++i) {
    if (axis + 1 == shape.size()) {
      array.push_back(ToJson(static_cast<T>(values[first + i])));
    } else {
      array.push_back(Nested(values, first + i * stride, shape, axis + 1));
    }
  }
  return array;
}

// Per-row JSON of a column's values: scalars, fixed-shape lists, or lists of `row_lengths`.
template <typename T>
std::vector<json> RowsAsJson(const parquet::ColumnSpec& spec, std::size_t num_rows, const std::vector<T>& values,
                             const std::vector<std::size_t>& row_lengths) {
  std::vector<json> rows;
  std::size_t next = 0;
  for (std::size_t row = 0; row < num_rows; ++row) {
    if (!spec.is_list) {
      rows.push_back(ToJson(static_cast<T>(values[row])));
    } else if (!spec.shape.empty()) {
      rows.push_back(Nested(values, next, spec.shape, 0));
      next += spec.items_per_row();
    } else {
      rows.push_back(Nested(values, next, {row_lengths[row]}, 0));
      next += row_lengths[row];
    }
  }
  return rows;
}

// Writes a row group column by column and records the rows it holds.
class RecordedRowGroup {
 public:
  RecordedRowGroup(parquet::ParquetWriter& writer, WrittenTable& table, std::size_t num_rows)
      : writer_(writer), table_(table), rows_(writer.NewRowGroup(num_rows)), first_row_(table.rows.size()) {
    for (std::size_t row = 0; row < num_rows; ++row) table_.rows.push_back(json::object());
  }

  template <typename T>
  void Add(const std::string& name, const std::vector<T>& values) {
    rows_.Add(name, values);
    Record(name, values, {});
  }

  template <typename T>
  void AddList(const std::string& name, const std::vector<T>& values,
               const std::vector<std::size_t>& row_lengths = {}) {
    rows_.AddList(name, values, row_lengths);
    Record(name, values, row_lengths);
  }

  void Write() {
    writer_.WriteRowGroup(rows_);
    ++table_.row_groups;
  }

 private:
  template <typename T>
  void Record(const std::string& name, const std::vector<T>& values, const std::vector<std::size_t>& row_lengths) {
    const parquet::ColumnSpec* spec = nullptr;
    for (const parquet::ColumnSpec& column : table_.columns) {
      if (column.name == name) spec = &column;
    }
    if (spec == nullptr) throw std::logic_error("fixture column " + name + " not declared");
    const std::vector<json> rows = RowsAsJson(*spec, rows_.num_rows(), values, row_lengths);
    for (std::size_t row = 0; row < rows.size(); ++row) table_.rows[first_row_ + row][name] = rows[row];
  }

  parquet::ParquetWriter& writer_;
  WrittenTable& table_;
  parquet::RowGroupBuilder rows_;
  std::size_t first_row_;
};

WrittenTable Declare(const std::string& path, std::vector<parquet::ColumnSpec> columns,
                     std::vector<std::pair<std::string, std::string>> key_value_metadata = {}) {
  WrittenTable table;
  table.path = path;
  table.columns = std::move(columns);
  table.key_value_metadata = std::move(key_value_metadata);
  return table;
}

parquet::ParquetWriterOptions OptionsOf(const WrittenTable& table, parquet::Codec codec) {
  parquet::ParquetWriterOptions options;
  options.codec = codec;
  options.key_value_metadata = table.key_value_metadata;
  return options;
}

// Awkward float32 values: exact halves, non-terminating binary fractions, extremes, a negative zero.
float StateValue(std::size_t row, std::size_t item) {
  switch ((row * 7 + item) % 6) {
    case 0: return static_cast<float>(row) * 0.1f - static_cast<float>(item);
    case 1: return std::numeric_limits<float>::max() / static_cast<float>(item + 1);
    case 2: return std::numeric_limits<float>::denorm_min() * static_cast<float>(row + 1);
    case 3: return -0.0f;
    case 4: return 1.0f / 3.0f + static_cast<float>(row);
    default: return std::ldexp(1.0f, -static_cast<int>(item)) - 0.5f;
  }
}

}  // namespace

WrittenTable WriteDataTable(const std::string& path, parquet::Codec codec) {
  constexpr std::size_t kStateSize = 34;
  constexpr std::size_t kActionSize = 19;
  WrittenTable table =
      Declare(path, {parquet::ColumnSpec::List("observation.state", parquet::ValueType::kFloat, {kStateSize}),
                     parquet::ColumnSpec::List("action", parquet::ValueType::kFloat, {kActionSize}),
                     parquet::ColumnSpec::Scalar("language_instruction", parquet::ValueType::kString),
                     parquet::ColumnSpec::Scalar("timestamp", parquet::ValueType::kFloat),
                     parquet::ColumnSpec::Scalar("frame_index", parquet::ValueType::kInt64),
                     parquet::ColumnSpec::Scalar("episode_index", parquet::ValueType::kInt64),
                     parquet::ColumnSpec::Scalar("index", parquet::ValueType::kInt64),
                     parquet::ColumnSpec::Scalar("task_index", parquet::ValueType::kInt64)});
  parquet::ParquetWriter writer(path, table.columns, OptionsOf(table, codec));
  const std::vector<std::size_t> episode_lengths{7, 12, 3};
  const std::vector<std::string> prompts{"Pick up the red cube.", "Öffne die Schublade — bitte", ""};
  std::int64_t index = 0;
  for (std::size_t episode = 0; episode < episode_lengths.size(); ++episode) {
    const std::size_t frames = episode_lengths[episode];
    std::vector<float> state, action, timestamps;
    std::vector<std::int64_t> frame_index, episode_index, global_index, task_index;
    for (std::size_t frame = 0; frame < frames; ++frame) {
      const std::size_t row = static_cast<std::size_t>(index);
      for (std::size_t i = 0; i < kStateSize; ++i) state.push_back(StateValue(row, i));
      for (std::size_t i = 0; i < kActionSize; ++i) action.push_back(StateValue(row + 1000, i) * 0.5f);
      timestamps.push_back(static_cast<float>(frame) / 60.0f);
      frame_index.push_back(static_cast<std::int64_t>(frame));
      episode_index.push_back(static_cast<std::int64_t>(episode));
      global_index.push_back(index++);
      task_index.push_back(static_cast<std::int64_t>(episode % 2));
    }
    RecordedRowGroup rows(writer, table, frames);
    rows.Add("task_index", task_index);  // any order: the file keeps the schema's
    rows.AddList("observation.state", state);
    rows.AddList("action", action);
    rows.Add("language_instruction", std::vector<std::string>(frames, prompts[episode]));
    rows.Add("timestamp", timestamps);
    rows.Add("frame_index", frame_index);
    rows.Add("episode_index", episode_index);
    rows.Add("index", global_index);
    rows.Write();
  }
  writer.Close();
  return table;
}

WrittenTable WriteTasksTable(const std::string& path, parquet::Codec codec) {
  const std::string pandas =
      R"({"index_columns": ["task"], "column_indexes": [{"name": null, "field_name": null, "pandas_type": "unicode", )"
      R"("numpy_type": "object", "metadata": {"encoding": "UTF-8"}}], "columns": [{"name": "task_index", )"
      R"("field_name": "task_index", "pandas_type": "int64", "numpy_type": "int64", "metadata": null}, )"
      R"({"name": "task", "field_name": "task", "pandas_type": "unicode", "numpy_type": "object", "metadata": null}]})";
  WrittenTable table = Declare(path,
                               {parquet::ColumnSpec::Scalar("task_index", parquet::ValueType::kInt64),
                                parquet::ColumnSpec::Scalar("task", parquet::ValueType::kString)},
                               {{"pandas", pandas}});
  parquet::ParquetWriter writer(path, table.columns, OptionsOf(table, codec));
  RecordedRowGroup rows(writer, table, 3);
  rows.Add("task_index", std::vector<std::int64_t>{0, 1, 2});
  rows.Add("task", std::vector<std::string>{"ConditionalPickTask", "OpenDrawerTask", "PeekingBoxTask"});
  rows.Write();
  writer.Close();
  return table;
}

WrittenTable WriteEpisodesTable(const std::string& path, parquet::Codec codec) {
  WrittenTable table = Declare(
      path, {parquet::ColumnSpec::Scalar("episode_index", parquet::ValueType::kInt64),
             parquet::ColumnSpec::List("tasks", parquet::ValueType::kString),
             parquet::ColumnSpec::Scalar("length", parquet::ValueType::kInt64),
             parquet::ColumnSpec::Scalar("data/chunk_index", parquet::ValueType::kInt64),
             parquet::ColumnSpec::Scalar("videos/observation.images.head/from_timestamp", parquet::ValueType::kDouble),
             parquet::ColumnSpec::List("stats/action/mean", parquet::ValueType::kDouble, {4}),
             parquet::ColumnSpec::List("stats/action/count", parquet::ValueType::kInt64, {1}),
             parquet::ColumnSpec::List("stats/observation.images.head/mean", parquet::ValueType::kDouble, {3, 1, 1}),
             parquet::ColumnSpec::List("stats/grid/max", parquet::ValueType::kDouble, {2, 3}),
             parquet::ColumnSpec::Scalar("success", parquet::ValueType::kBool),
             parquet::ColumnSpec::Scalar("seed", parquet::ValueType::kInt32),
             parquet::ColumnSpec::List("camera_ids", parquet::ValueType::kInt32, {2}),
             parquet::ColumnSpec::List("flags", parquet::ValueType::kBool)});
  parquet::ParquetWriter writer(path, table.columns, OptionsOf(table, codec));
  const auto write_group = [&](std::int64_t first_episode, std::vector<std::vector<std::string>> tasks) {
    const std::size_t episodes = tasks.size();
    std::vector<std::string> flat_tasks;
    std::vector<std::size_t> task_counts;
    std::vector<std::int64_t> episode_index, length, chunk, count;
    std::vector<double> from, mean, image_mean, grid;
    std::vector<bool> success, flags;
    std::vector<std::size_t> flag_counts;
    std::vector<std::int32_t> seed, camera_ids;
    for (std::size_t e = 0; e < episodes; ++e) {
      const std::int64_t episode = first_episode + static_cast<std::int64_t>(e);
      flat_tasks.insert(flat_tasks.end(), tasks[e].begin(), tasks[e].end());
      task_counts.push_back(tasks[e].size());
      episode_index.push_back(episode);
      length.push_back(100 + episode * 37);
      chunk.push_back(episode / 2);
      count.push_back(std::numeric_limits<std::int64_t>::max() - episode);  // beyond 2^53: INT64 must be exact
      from.push_back(static_cast<double>(episode) / 3.0);
      for (int i = 0; i < 4; ++i) mean.push_back(0.1 * i - static_cast<double>(episode) * 1e-300);
      for (int i = 0; i < 3; ++i) image_mean.push_back(1.0 / (7.0 + i + static_cast<double>(episode)));
      for (int i = 0; i < 6; ++i) grid.push_back(static_cast<double>(i * 10 + episode));
      success.push_back(episode % 3 != 1);
      seed.push_back(episode % 2 == 0 ? std::numeric_limits<std::int32_t>::min()
                                      : 12345 + static_cast<std::int32_t>(episode));
      camera_ids.push_back(static_cast<std::int32_t>(episode));
      camera_ids.push_back(-7);
      for (std::int64_t f = 0; f < episode % 3; ++f) flags.push_back((f + episode) % 2 == 0);
      flag_counts.push_back(static_cast<std::size_t>(episode % 3));
    }
    RecordedRowGroup rows(writer, table, episodes);
    rows.Add("episode_index", episode_index);
    rows.AddList("tasks", flat_tasks, task_counts);
    rows.Add("length", length);
    rows.Add("data/chunk_index", chunk);
    rows.Add("videos/observation.images.head/from_timestamp", from);
    rows.AddList("stats/action/mean", mean);
    rows.AddList("stats/action/count", count);
    rows.AddList("stats/observation.images.head/mean", image_mean);
    rows.AddList("stats/grid/max", grid);
    rows.Add("success", success);
    rows.Add("seed", seed);
    rows.AddList("camera_ids", camera_ids);
    rows.AddList("flags", flags, flag_counts);
    rows.Write();
  };
  write_group(0, {{"ConditionalPickTask"}, {"ConditionalPickTask", "OpenDrawerTask"}, {}});
  write_group(3, {{"PeekingBoxTask", "OpenDrawerTask", "ConditionalPickTask"}, {"a"}});
  writer.Close();
  return table;
}

namespace {

// Calls `visit` with a value of the C++ type that holds `type`.
template <typename Visit>
void WithValueType(parquet::ValueType type, const Visit& visit) {
  switch (type) {
    case parquet::ValueType::kBool: return visit(bool{});
    case parquet::ValueType::kInt32: return visit(std::int32_t{});
    case parquet::ValueType::kInt64: return visit(std::int64_t{});
    case parquet::ValueType::kFloat: return visit(float{});
    case parquet::ValueType::kDouble: return visit(double{});
    case parquet::ValueType::kString: return visit(std::string{});
  }
}

template <typename T>
void ReadColumnAsJson(const parquet::ParquetReader& reader, const parquet::ColumnSpec& spec, json& rows) {
  const parquet::ListColumn<T> column = reader.ReadListColumn<T>(spec.name);
  if (column.row_lengths.size() != rows.size()) {
    throw std::logic_error(spec.name + ": " + std::to_string(column.row_lengths.size()) + " rows read");
  }
  for (std::size_t row = 0; row < rows.size(); ++row) {
    if (!spec.shape.empty() || !spec.is_list) {
      if (column.row_lengths[row] != spec.items_per_row()) {
        throw std::logic_error(spec.name + ": " + std::to_string(column.row_lengths[row]) + " items in row " +
                               std::to_string(row) + " for " + std::to_string(spec.items_per_row()) + " written");
      }
    }
  }
  const std::vector<json> values = RowsAsJson(spec, rows.size(), column.values, column.row_lengths);
  for (std::size_t row = 0; row < rows.size(); ++row) rows[row][spec.name] = values[row];
}

}  // namespace

json ReadWithOurReader(const std::string& path, const std::vector<parquet::ColumnSpec>& columns) {
  const parquet::ParquetReader reader(path);
  json rows = json::array();
  for (std::int64_t row = 0; row < reader.num_rows(); ++row) rows.push_back(json::object());
  for (const parquet::ColumnSpec& spec : columns) {
    WithValueType(spec.type, [&](auto type) { ReadColumnAsJson<decltype(type)>(reader, spec, rows); });
  }
  return rows;
}

void ReadEveryColumn(const std::string& path, const std::vector<parquet::ColumnSpec>& columns) {
  const parquet::ParquetReader reader(path);
  for (const parquet::ColumnSpec& spec : columns) {
    WithValueType(spec.type, [&](auto type) { reader.ReadListColumn<decltype(type)>(spec.name); });
  }
}

ScratchDir::ScratchDir() {
  std::string pattern = (std::filesystem::temp_directory_path() / "tavis_parquet_XXXXXX").string();
  if (::mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed for " + pattern);
  path_ = pattern;
}

ScratchDir::~ScratchDir() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

}  // namespace tavis::batch::dataset::testing
