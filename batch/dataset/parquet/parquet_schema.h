// Parquet schemas: the columns a writer declares (ColumnSpec) and how they are flattened into
// SchemaElements, and the leaf columns a reader derives from the SchemaElements of a footer.
//
// Every written column is OPTIONAL. A list column is the 3-level LIST of the Parquet spec,
// `optional group <name> (LIST) { repeated group list { optional <type> element; } }`, nested
// once per axis of its shape: shape {34} is list<float>, shape {3,1,1} list<list<list<double>>>.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "batch/dataset/parquet/parquet_format.h"
#include "batch/dataset/parquet/thrift_compact.h"

namespace tavis::batch::dataset::parquet {

// The value types a writer stores; kString is BYTE_ARRAY with the STRING logical type.
enum class ValueType { kBool, kInt32, kInt64, kFloat, kDouble, kString };

std::string ValueTypeName(ValueType type);
PhysicalType PhysicalTypeOf(ValueType type);

// The C++ type that holds each ValueType: ValueTypeOf<float>::kType is ValueType::kFloat.
template <typename T>
struct ValueTypeOf;
template <>
struct ValueTypeOf<bool> {
  static constexpr ValueType kType = ValueType::kBool;
};
template <>
struct ValueTypeOf<std::int32_t> {
  static constexpr ValueType kType = ValueType::kInt32;
};
template <>
struct ValueTypeOf<std::int64_t> {
  static constexpr ValueType kType = ValueType::kInt64;
};
template <>
struct ValueTypeOf<float> {
  static constexpr ValueType kType = ValueType::kFloat;
};
template <>
struct ValueTypeOf<double> {
  static constexpr ValueType kType = ValueType::kDouble;
};
template <>
struct ValueTypeOf<std::string> {
  static constexpr ValueType kType = ValueType::kString;
};

// Applies the macro X to each of those C++ types (for explicit template instantiations).
#define TAVIS_PARQUET_FOR_EACH_VALUE_TYPE(X) X(bool) X(std::int32_t) X(std::int64_t) X(float) X(double) X(std::string)

struct ColumnSpec {
  std::string name;  // any non-empty name, '/' and '.' included (e.g. "stats/action/mean")
  ValueType type = ValueType::kInt64;
  bool is_list = false;
  // For a list: the items of every row, one entry per nesting level; empty for a list whose
  // length varies per row (one level only). Empty for a scalar.
  std::vector<std::size_t> shape;

  static ColumnSpec Scalar(std::string name, ValueType type);
  static ColumnSpec List(std::string name, ValueType type, std::vector<std::size_t> shape = {});

  int list_depth() const;  // 0 for a scalar
  int max_definition_level() const { return 2 * list_depth() + 1; }
  int max_repetition_level() const { return list_depth(); }
  std::size_t items_per_row() const;           // the product of `shape` (1 for a scalar)
  std::vector<std::string> leaf_path() const;  // name, then "list", "element" per level
};

// Throws std::invalid_argument naming the column: empty or duplicate names, names with control
// characters or an empty '/'-separated part ("a//b", "/a", "a/"), shapes with a 0, nested
// lists without a fixed shape, an empty schema.
void ValidateColumns(const std::vector<ColumnSpec>& columns);

// Appends FileMetaData field 2 (the depth-first flattened schema, root first).
void AppendSchemaField(const std::vector<ColumnSpec>& columns, ThriftCompactWriter& thrift);

// One SchemaElement of a footer, as read.
struct SchemaElement {
  std::optional<PhysicalType> type;  // leaves only
  Repetition repetition = Repetition::kRequired;
  std::string name;
  std::int32_t num_children = 0;
  std::optional<std::int32_t> converted_type;
  bool logical_string = false;  // logicalType STRING (field 1 of the union)
};

SchemaElement ReadSchemaElement(ThriftCompactReader& thrift);

// A primitive column of a file, with the levels its values carry.
struct LeafColumn {
  std::vector<std::string> path;  // path[0] is the top-level column name
  PhysicalType type = PhysicalType::kInt64;
  bool is_string = false;  // UTF8 converted type or STRING logical type
  int max_definition_level = 0;
  int max_repetition_level = 0;
};

// The leaves of a flattened schema, in file order. Throws std::runtime_error starting with
// `context` for an inconsistent tree (children counts that do not add up, a leaf without a type).
std::vector<LeafColumn> LeafColumnsOf(const std::vector<SchemaElement>& elements, const std::string& context);

}  // namespace tavis::batch::dataset::parquet
