// The `tavis` command-line program: one subcommand per job.
#include <exception>
#include <iostream>

#include "tools/commands.h"

int main(int argc, char** argv) {
  CLI::App app{"tavis: batched CPU simulator and evaluation harness for the TAVIS benchmark"};
  app.require_subcommand(1);
  tavis::tools::RegisterEvalCommand(app);
  tavis::tools::RegisterDemosCommand(app);
  tavis::tools::RegisterGaltCommand(app);
  tavis::tools::RegisterRenderCommand(app);
  tavis::tools::RegisterTableCommand(app);
  tavis::tools::RegisterAuditCommand(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help exits 0; every usage error exits 1, like the errors below.
    return app.exit(e) == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "tavis: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
