// Subcommands of the `tavis` program. Each registers its options and its callback on the root
// application; the callback throws std::exception on bad input and main() reports it.
#pragma once

#include <CLI/CLI.hpp>

namespace tavis::tools {

void RegisterAuditCommand(CLI::App& app);
void RegisterCompareCommand(CLI::App& app);
void RegisterDemosCommand(CLI::App& app);
void RegisterEvalCommand(CLI::App& app);
void RegisterGaltCommand(CLI::App& app);
void RegisterRenderCommand(CLI::App& app);
void RegisterSweepCommand(CLI::App& app);
void RegisterTableCommand(CLI::App& app);
void RegisterVerifyCommand(CLI::App& app);

}  // namespace tavis::tools
