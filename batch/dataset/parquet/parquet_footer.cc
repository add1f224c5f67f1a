#include "batch/dataset/parquet/parquet_footer.h"

namespace tavis::batch::dataset::parquet {
namespace {

// Calls `read_element` once per element of the list field of `type`.
template <typename ReadElement>
void ReadList(ThriftCompactReader& thrift, ThriftType type, ThriftType expected_element,
              const ReadElement& read_element) {
  ThriftType element_type{};
  const std::size_t size = thrift.ReadListHeader(type, element_type);
  if (size > 0 && element_type != expected_element) {
    thrift.Fail("list of thrift type " + std::to_string(static_cast<int>(element_type)) + " where type " +
                std::to_string(static_cast<int>(expected_element)) + " was expected");
  }
  for (std::size_t i = 0; i < size; ++i) read_element(element_type);
}

ColumnChunkMetadata ReadColumnMetadata(ThriftCompactReader& thrift) {
  ColumnChunkMetadata column;
  thrift.ReadStruct([&](std::int16_t id, ThriftType type) {
    switch (id) {
      case 1: column.type = static_cast<PhysicalType>(thrift.ReadI32(type)); break;
      case 3:
        ReadList(thrift, type, ThriftType::kBinary,
                 [&](ThriftType element) { column.path.push_back(thrift.ReadBinary(element)); });
        break;
      case 4: column.codec = static_cast<Codec>(thrift.ReadI32(type)); break;
      case 5: column.num_values = thrift.ReadInt(type); break;
      case 7: column.total_compressed_size = thrift.ReadInt(type); break;
      case 9: column.data_page_offset = thrift.ReadInt(type); break;
      case 11: column.dictionary_page_offset = thrift.ReadInt(type); break;
      default: thrift.Skip(type);
    }
  });
  return column;
}

ColumnChunkMetadata ReadColumnChunk(ThriftCompactReader& thrift) {
  ColumnChunkMetadata column;
  bool has_metadata = false;
  bool in_other_file = false;
  thrift.ReadStruct([&](std::int16_t id, ThriftType type) {
    if (id == 1) {
      thrift.ReadBinary(type);
      in_other_file = true;
    } else if (id == 3 && type == ThriftType::kStruct) {
      column = ReadColumnMetadata(thrift);
      has_metadata = true;
    } else {
      thrift.Skip(type);
    }
  });
  if (!has_metadata) thrift.Fail("column chunk without metadata");
  column.in_other_file = in_other_file;
  return column;
}

RowGroupMetadata ReadRowGroup(ThriftCompactReader& thrift) {
  RowGroupMetadata group;
  thrift.ReadStruct([&](std::int16_t id, ThriftType type) {
    if (id == 1) {
      ReadList(thrift, type, ThriftType::kStruct,
               [&](ThriftType) { group.columns.push_back(ReadColumnChunk(thrift)); });
    } else if (id == 3) {
      group.num_rows = thrift.ReadInt(type);
    } else {
      thrift.Skip(type);
    }
  });
  return group;
}

std::pair<std::string, std::string> ReadKeyValue(ThriftCompactReader& thrift) {
  std::pair<std::string, std::string> entry;
  thrift.ReadStruct([&](std::int16_t id, ThriftType type) {
    if (id == 1) {
      entry.first = thrift.ReadBinary(type);
    } else if (id == 2) {
      entry.second = thrift.ReadBinary(type);
    } else {
      thrift.Skip(type);
    }
  });
  return entry;
}

}  // namespace

FileMetadata ReadFileMetadata(ThriftCompactReader& thrift) {
  FileMetadata file;
  thrift.ReadStruct([&](std::int16_t id, ThriftType type) {
    switch (id) {
      case 2:
        ReadList(thrift, type, ThriftType::kStruct,
                 [&](ThriftType) { file.schema.push_back(ReadSchemaElement(thrift)); });
        break;
      case 3: file.num_rows = thrift.ReadInt(type); break;
      case 4:
        ReadList(thrift, type, ThriftType::kStruct,
                 [&](ThriftType) { file.row_groups.push_back(ReadRowGroup(thrift)); });
        break;
      case 5:
        ReadList(thrift, type, ThriftType::kStruct,
                 [&](ThriftType) { file.key_value_metadata.push_back(ReadKeyValue(thrift)); });
        break;
      case 6: file.created_by = thrift.ReadBinary(type); break;
      default: thrift.Skip(type);
    }
  });
  return file;
}

PageHeader ReadPageHeader(ThriftCompactReader& thrift) {
  PageHeader page;
  const auto read_data_page_header = [&](ThriftType struct_type, bool v2) {
    thrift.ReadStruct(struct_type, [&](std::int16_t id, ThriftType type) {
      if (id == 1) {
        page.num_values = thrift.ReadI32(type);
      } else if (!v2 && id == 2) {
        page.encoding = static_cast<Encoding>(thrift.ReadI32(type));
      } else if (!v2 && id == 3) {
        page.definition_level_encoding = static_cast<Encoding>(thrift.ReadI32(type));
      } else if (!v2 && id == 4) {
        page.repetition_level_encoding = static_cast<Encoding>(thrift.ReadI32(type));
      } else if (v2 && id == 4) {
        page.encoding = static_cast<Encoding>(thrift.ReadI32(type));
      } else if (v2 && id == 5) {
        page.definition_levels_byte_length = thrift.ReadI32(type);
      } else if (v2 && id == 6) {
        page.repetition_levels_byte_length = thrift.ReadI32(type);
      } else if (v2 && id == 7) {
        page.is_compressed = thrift.ReadBool(type);
      } else {
        thrift.Skip(type);
      }
    });
  };
  thrift.ReadStruct([&](std::int16_t id, ThriftType type) {
    switch (id) {
      case 1: page.type = static_cast<PageType>(thrift.ReadI32(type)); break;
      case 2: page.uncompressed_page_size = thrift.ReadI32(type); break;
      case 3: page.compressed_page_size = thrift.ReadI32(type); break;
      case 5: read_data_page_header(type, false); break;
      case 7:
        thrift.ReadStruct(type, [&](std::int16_t field, ThriftType field_type) {
          if (field == 1) {
            page.num_values = thrift.ReadI32(field_type);
          } else if (field == 2) {
            page.encoding = static_cast<Encoding>(thrift.ReadI32(field_type));
          } else {
            thrift.Skip(field_type);
          }
        });
        break;
      case 8: read_data_page_header(type, true); break;
      default: thrift.Skip(type);
    }
  });
  return page;
}

}  // namespace tavis::batch::dataset::parquet
