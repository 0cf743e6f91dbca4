// Subcommand registry: each cmd_*.cpp registers itself with TEX_COMMAND, so adding a
// subcommand never touches main.cpp.
#pragma once
#include <string>
#include <vector>

namespace tex::cli {

using Args = std::vector<std::string>;  // arguments after the subcommand name
using CommandFn = int (*)(const Args& args);

struct Command {
  const char* name;
  const char* summary;  // one line for `tex --help`
  CommandFn run;
};

// Registers at static-initialisation time; returns a dummy for the static initialiser.
bool registerCommand(const Command& command);
const std::vector<Command>& commands();

// True if args contain -h or --help.
bool wantsHelp(const Args& args);

}  // namespace tex::cli

#define TEX_CLI_CONCAT2(a, b) a##b
#define TEX_CLI_CONCAT(a, b) TEX_CLI_CONCAT2(a, b)
#define TEX_COMMAND(name, summary, fn)                                          \
  static const bool TEX_CLI_CONCAT(texCommandRegistered_, __LINE__) =          \
      ::tex::cli::registerCommand(::tex::cli::Command{name, summary, fn})
