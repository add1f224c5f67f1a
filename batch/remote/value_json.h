// A decoded msgpack value as JSON, for the records: a server's metadata in summary.json. JSON
// has no bytes, arrays or non-finite numbers, so those are described instead of copied.
#pragma once

#include <nlohmann/json.hpp>

#include "batch/remote/msgpack_value.h"

namespace tavis::batch::remote {

// nil, bool, numbers, str, list and dict as themselves (dict keys that are not str are written as
// their JSON text); bytes as {"bytes": size}; an ndarray as {"ndarray": {"dtype", "shape"}}; a
// non-finite float as "nan", "inf" or "-inf".
nlohmann::json ToJson(const Value& value);

}  // namespace tavis::batch::remote
