#include "tools/cell_options.h"

#include <cstdint>
#include <stdexcept>
#include <type_traits>
#include <variant>
#include <vector>

#include "tools/option_parsing.h"

namespace tavis::tools {
namespace {

using batch::cell::CellSetting;
using batch::cell::EvalOption;

// The option for one setting, of the setting's type: its range checked before CLI11 converts
// it, an enum read from its text.
CLI::Option* AddCellOption(CLI::App& command, const CellSetting& setting, batch::cell::EvaluationCellConfig& cell) {
  return std::visit(
      [&](auto member) -> CLI::Option* {
        using T = std::decay_t<decltype(cell.*member)>;
        T& value = cell.*member;
        if constexpr (std::is_same_v<T, bool>) {
          return command.add_flag(setting.flag, value, setting.help);
        } else if constexpr (std::is_same_v<T, uint64_t>) {
          return AddSeedOption(command, value, setting.help);  // the one 64-bit setting: the seed
        } else if constexpr (std::is_enum_v<T>) {
          return command
              .add_option_function<std::string>(
                  setting.flag, [&value](const std::string& text) { value = batch::cell::SettingText<T>::Read(text); },
                  setting.help)
              ->default_str(batch::cell::SettingText<T>::Write(value));
        } else {
          CLI::Option* option = command.add_option(setting.flag, value, setting.help);
          const bool ranged = setting.range && setting.range->choices.empty();
          const bool chosen = setting.range && !setting.range->choices.empty();
          if constexpr (std::is_integral_v<T>) {
            if (ranged)
              option->check(
                  IntegerIn(static_cast<int64_t>(setting.range->low), static_cast<int64_t>(setting.range->high)));
            if (chosen) option->check(IntegerNamingChoices(setting.range->choices));
          } else if constexpr (std::is_floating_point_v<T>) {
            if (ranged) option->check(NumberIn(setting.range->low, setting.range->high));
          }
          if (setting.option == EvalOption::kShowingDefault) option->capture_default_str();
          return option;
        }
      },
      setting.member);
}

}  // namespace

void AddCellOptions(CLI::App& command, batch::cell::EvaluationCellConfig& cell) {
  for (const CellSetting& setting : batch::cell::CellSettings()) {
    if (setting.option == EvalOption::kShowingDefault || setting.option == EvalOption::kHidingDefault)
      AddCellOption(command, setting, cell);
  }
}

void RefuseOptionsOfOtherPolicies(const CLI::App& command, const std::string& policy) {
  for (const CellSetting& setting : batch::cell::CellSettings()) {
    if (setting.option == EvalOption::kNone || batch::cell::SettingApplies(setting.scope, policy)) continue;
    if (command.count(setting.flag) > 0) {
      throw std::invalid_argument(std::string(setting.flag) + " applies to --policy " +
                                  batch::cell::ScopePolicyName(setting.scope) + " only, got --policy " + policy);
    }
  }
}

batch::cell::CellPlan PlanCellNamingFlags(const batch::cell::EvaluationCellConfig& cell) {
  try {
    return batch::cell::PlanCell(cell);
  } catch (const batch::output::SettingError& error) {
    const CellSetting* setting = batch::cell::FindCellSetting(error.key());
    if (setting == nullptr || setting->flag == nullptr) throw;
    ThrowNamingFlag(error, setting->flag);
  }
}

}  // namespace tavis::tools
