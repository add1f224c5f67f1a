#include "batch/dataset/parquet/parquet_schema.h"

#include <functional>
#include <stdexcept>
#include <unordered_set>

namespace tavis::batch::dataset::parquet {
namespace {

// SchemaElement field ids.
constexpr std::int16_t kTypeField = 1;
constexpr std::int16_t kRepetitionField = 3;
constexpr std::int16_t kNameField = 4;
constexpr std::int16_t kNumChildrenField = 5;
constexpr std::int16_t kConvertedTypeField = 6;
constexpr std::int16_t kLogicalTypeField = 10;
// LogicalType union members.
constexpr std::int16_t kLogicalString = 1;
constexpr std::int16_t kLogicalList = 3;

void AppendElement(ThriftCompactWriter& thrift, std::optional<PhysicalType> type, Repetition repetition,
                   const std::string& name, std::optional<std::int32_t> num_children,
                   std::optional<std::int32_t> converted_type, std::optional<std::int16_t> logical_type) {
  thrift.BeginStruct();
  if (type) thrift.I32Field(kTypeField, static_cast<std::int32_t>(*type));
  thrift.I32Field(kRepetitionField, static_cast<std::int32_t>(repetition));
  thrift.BinaryField(kNameField, name);
  if (num_children) thrift.I32Field(kNumChildrenField, *num_children);
  if (converted_type) thrift.I32Field(kConvertedTypeField, *converted_type);
  if (logical_type) {
    thrift.BeginStructField(kLogicalTypeField);
    thrift.BeginStructField(*logical_type);  // the member is an empty struct
    thrift.EndStruct();
    thrift.EndStruct();
  }
  thrift.EndStruct();
}

void CheckName(const std::string& name) {
  if (name.empty()) throw std::invalid_argument("Parquet column with an empty name");
  for (const char c : name) {
    if (static_cast<unsigned char>(c) < 0x20) {
      throw std::invalid_argument("Parquet column \"" + name + "\": control character in the name");
    }
  }
  if (name.front() == '/' || name.back() == '/' || name.find("//") != std::string::npos) {
    throw std::invalid_argument("Parquet column \"" + name + "\": empty part between '/' separators");
  }
}

}  // namespace

std::string ValueTypeName(ValueType type) {
  switch (type) {
    case ValueType::kBool: return "bool";
    case ValueType::kInt32: return "int32";
    case ValueType::kInt64: return "int64";
    case ValueType::kFloat: return "float";
    case ValueType::kDouble: return "double";
    case ValueType::kString: return "string";
  }
  return "value type " + std::to_string(static_cast<int>(type));
}

PhysicalType PhysicalTypeOf(ValueType type) {
  switch (type) {
    case ValueType::kBool: return PhysicalType::kBoolean;
    case ValueType::kInt32: return PhysicalType::kInt32;
    case ValueType::kInt64: return PhysicalType::kInt64;
    case ValueType::kFloat: return PhysicalType::kFloat;
    case ValueType::kDouble: return PhysicalType::kDouble;
    case ValueType::kString: return PhysicalType::kByteArray;
  }
  throw std::invalid_argument("unknown value type " + std::to_string(static_cast<int>(type)));
}

ColumnSpec ColumnSpec::Scalar(std::string name, ValueType type) { return ColumnSpec{std::move(name), type, false, {}}; }

ColumnSpec ColumnSpec::List(std::string name, ValueType type, std::vector<std::size_t> shape) {
  return ColumnSpec{std::move(name), type, true, std::move(shape)};
}

int ColumnSpec::list_depth() const {
  if (!is_list) return 0;
  return shape.empty() ? 1 : static_cast<int>(shape.size());
}

std::size_t ColumnSpec::items_per_row() const {
  std::size_t items = 1;
  for (const std::size_t axis : shape) items *= axis;
  return items;
}

std::vector<std::string> ColumnSpec::leaf_path() const {
  std::vector<std::string> path{name};
  for (int level = 0; level < list_depth(); ++level) {
    path.emplace_back("list");
    if (level + 1 < list_depth()) path.emplace_back("element");
  }
  if (is_list) path.emplace_back("element");
  return path;
}

void ValidateColumns(const std::vector<ColumnSpec>& columns) {
  if (columns.empty()) throw std::invalid_argument("a Parquet schema needs at least one column");
  std::unordered_set<std::string> names;
  for (const ColumnSpec& column : columns) {
    CheckName(column.name);
    if (!names.insert(column.name).second) {
      throw std::invalid_argument("Parquet column \"" + column.name + "\" declared twice");
    }
    if (!column.is_list && !column.shape.empty()) {
      throw std::invalid_argument("Parquet column \"" + column.name + "\": a scalar column has no shape");
    }
    for (const std::size_t axis : column.shape) {
      if (axis == 0) throw std::invalid_argument("Parquet column \"" + column.name + "\": shape with a 0 axis");
    }
    PhysicalTypeOf(column.type);
  }
}

void AppendSchemaField(const std::vector<ColumnSpec>& columns, ThriftCompactWriter& thrift) {
  std::size_t elements = 1;
  for (const ColumnSpec& column : columns) elements += 1 + 2 * static_cast<std::size_t>(column.list_depth());
  thrift.ListField(2, ThriftType::kStruct, elements);
  AppendElement(thrift, std::nullopt, Repetition::kRequired, "schema", static_cast<std::int32_t>(columns.size()),
                std::nullopt, std::nullopt);
  for (const ColumnSpec& column : columns) {
    // Each level of a list is an optional LIST group holding a repeated group "list"; the inner
    // levels' groups are named "element", as the elements of their parent list.
    for (int level = 0; level < column.list_depth(); ++level) {
      AppendElement(thrift, std::nullopt, Repetition::kOptional, level == 0 ? column.name : "element", 1,
                    kConvertedList, kLogicalList);
      AppendElement(thrift, std::nullopt, Repetition::kRepeated, "list", 1, std::nullopt, std::nullopt);
    }
    const bool is_string = column.type == ValueType::kString;
    AppendElement(thrift, PhysicalTypeOf(column.type), Repetition::kOptional, column.is_list ? "element" : column.name,
                  std::nullopt, is_string ? std::optional<std::int32_t>(kConvertedUtf8) : std::nullopt,
                  is_string ? std::optional<std::int16_t>(kLogicalString) : std::nullopt);
  }
}

SchemaElement ReadSchemaElement(ThriftCompactReader& thrift) {
  SchemaElement element;
  thrift.ReadStruct([&](std::int16_t id, ThriftType type) {
    switch (id) {
      case kTypeField: element.type = static_cast<PhysicalType>(thrift.ReadI32(type)); break;
      case kRepetitionField: element.repetition = static_cast<Repetition>(thrift.ReadI32(type)); break;
      case kNameField: element.name = thrift.ReadBinary(type); break;
      case kNumChildrenField: element.num_children = thrift.ReadI32(type); break;
      case kConvertedTypeField: element.converted_type = thrift.ReadI32(type); break;
      case kLogicalTypeField:
        thrift.ReadStruct(type, [&](std::int16_t member, ThriftType member_type) {
          if (member == kLogicalString) element.logical_string = true;
          thrift.Skip(member_type);
        });
        break;
      default: thrift.Skip(type);
    }
  });
  return element;
}

std::vector<LeafColumn> LeafColumnsOf(const std::vector<SchemaElement>& elements, const std::string& context) {
  if (elements.empty()) throw std::runtime_error(context + ": empty schema");
  std::vector<LeafColumn> leaves;
  std::size_t next = 1;
  std::vector<std::string> path;
  // Depth-first over the flattened tree, with the nesting bounded so a hostile footer cannot
  // exhaust the stack.
  constexpr std::size_t kMaxNesting = 64;
  const std::function<void(int, int)> visit = [&](int definition, int repetition) {
    if (next >= elements.size())
      throw std::runtime_error(context + ": schema has fewer elements than its children counts");
    if (path.size() >= kMaxNesting) throw std::runtime_error(context + ": schema nested deeper than 64 levels");
    const SchemaElement& element = elements[next++];
    if (element.repetition != Repetition::kRequired) ++definition;
    if (element.repetition == Repetition::kRepeated) ++repetition;
    path.push_back(element.name);
    if (element.num_children > 0) {
      if (static_cast<std::size_t>(element.num_children) > elements.size() - next) {
        throw std::runtime_error(context + ": schema group \"" + element.name + "\" claims " +
                                 std::to_string(element.num_children) + " children");
      }
      for (std::int32_t child = 0; child < element.num_children; ++child) visit(definition, repetition);
    } else {
      if (!element.type) throw std::runtime_error(context + ": schema leaf \"" + element.name + "\" has no type");
      const bool is_string = element.logical_string || element.converted_type == kConvertedUtf8;
      leaves.push_back(LeafColumn{path, *element.type, is_string, definition, repetition});
    }
    path.pop_back();
  };
  const std::int32_t top_level = elements[0].num_children;
  if (top_level < 0 || static_cast<std::size_t>(top_level) >= elements.size() + 1) {
    throw std::runtime_error(context + ": schema root claims " + std::to_string(top_level) + " columns");
  }
  for (std::int32_t column = 0; column < top_level; ++column) visit(0, 0);
  if (next != elements.size()) throw std::runtime_error(context + ": schema has elements outside the root's tree");
  return leaves;
}

}  // namespace tavis::batch::dataset::parquet
