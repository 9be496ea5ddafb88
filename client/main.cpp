// `tessera`: the command-line front end. Local commands run the core in-process; remote
// commands talk to a tessera-server (chosen with --server HOST:PORT).
#include <iostream>

#include "client/commands.h"

int main(int argc, char** argv) {
  CLI::App app{"Tessera: error-bounded tessellation of Catmull-Clark subdivision surfaces"};
  app.require_subcommand(1);
  tessera::cli::CommandContext context;
  tessera::cli::registerLocalCommands(app, context);
#if TESSERA_WITH_REMOTE
  tessera::cli::registerRemoteCommands(app, context);
#endif
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int code = app.exit(e);
    return code == 0 ? 0 : tessera::cli::kExitUsage;
  }
  return context.exitCode;
}
