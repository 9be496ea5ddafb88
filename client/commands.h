// Command groups of the `tessera` CLI. Each group registers its subcommands on the app; a
// subcommand's callback returns the process exit code through the shared ExitCode.
#pragma once

#include <CLI/CLI.hpp>

namespace tessera::cli {

// Exit codes a script can rely on.
enum ExitCode : int {
  kExitOk = 0,
  kExitUsage = 2,        // bad flags or values
  kExitInvalidInput = 3, // the mesh or request is malformed
  kExitUnsupported = 4,  // the mesh uses a feature Tessera refuses
  kExitLimit = 5,        // a size or work budget was exceeded
  kExitIo = 6,           // a file could not be read or written
  kExitRemote = 7,       // the server answered with an error or could not be reached
};

struct CommandContext {
  int exitCode = kExitOk;
};

void registerLocalCommands(CLI::App& app, CommandContext& context);
#if TESSERA_WITH_REMOTE
void registerRemoteCommands(CLI::App& app, CommandContext& context);
#endif

}  // namespace tessera::cli
