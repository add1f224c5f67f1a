#include "tools/error_text.h"

#include <algorithm>

#include "batch/cell/cell_settings.h"
#include "batch/output/setting_error.h"

namespace tavis::tools {

std::string FlagOfSetting(const std::string& key) {
  const batch::cell::CellSetting* setting = batch::cell::FindCellSetting(key);
  if (setting != nullptr && setting->flag != nullptr) return setting->flag;
  std::string flag = "--" + key;
  std::replace(flag.begin(), flag.end(), '_', '-');
  return flag;
}

std::string ErrorText(const std::exception& error) {
  if (const auto* named = dynamic_cast<const batch::output::NamesSettings*>(&error)) {
    return named->MessageNaming(FlagOfSetting);
  }
  return error.what();
}

}  // namespace tavis::tools
