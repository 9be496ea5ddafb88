// Local commands: run the core in-process on a mesh file.
#include "client/commands.h"

namespace tessera::cli {

void registerLocalCommands(CLI::App& app, CommandContext& context) {
  (void)app;
  (void)context;
}

}  // namespace tessera::cli
