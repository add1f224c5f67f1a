// The `tavis` program: one subcommand per job.
#include <exception>
#include <iostream>
#include <new>
#include <string>

#include "tools/build_version.h"
#include "tools/commands.h"
#include "tools/exit_status.h"
#include "tools/interrupt_notice.h"

namespace {

bool IsSubcommand(const CLI::App& app, const std::string& name) {
  return !app.get_subcommands([&name](const CLI::App* command) { return command->check_name(name); }).empty();
}

// "eval, demos, ..." in registration order.
std::string SubcommandNames(const CLI::App& app) {
  std::string names;
  for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; })) {
    names += (names.empty() ? "" : ", ") + command->get_name();
  }
  return names;
}

}  // namespace

int main(int argc, char** argv) {
  // First: every thread started later inherits the blocked signals, which only the watcher takes.
  tavis::tools::WatchForInterrupts(argc, argv);
  CLI::App app{"tavis: batched CPU simulator and evaluation harness for the TAVIS benchmark"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("tavis ") + tavis::tools::BuildVersion());
  tavis::tools::RegisterEvalCommand(app);
  tavis::tools::RegisterDemosCommand(app);
  tavis::tools::RegisterGaltCommand(app);
  tavis::tools::RegisterRenderCommand(app);
  tavis::tools::RegisterTableCommand(app);
  tavis::tools::RegisterAuditCommand(app);
  tavis::tools::RegisterSweepCommand(app);
  tavis::tools::RegisterCompareCommand(app);
  tavis::tools::RegisterVerifyCommand(app);
  // CLI11 reports a misspelt subcommand as a missing one ("A subcommand is required").
  if (argc > 1 && argv[1][0] != '-' && !IsSubcommand(app, argv[1])) {
    std::cerr << "tavis: error: unknown command '" << argv[1] << "' (known: " << SubcommandNames(app) << ")\n";
    return 1;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help exits 0; a usage error exits 1, like the errors below, unless its command says otherwise.
    return app.exit(e) == 0 ? 0 : tavis::tools::UsageErrorStatus();
  } catch (const tavis::tools::ExitStatus& e) {
    if (*e.what() != '\0') std::cerr << "tavis: error: " << e.what() << "\n";
    return e.status();
  } catch (const std::bad_alloc&) {
    std::cerr << "tavis: error: out of memory (try fewer --envs or a smaller --image-size)\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "tavis: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
