// `tex check FILE...`: type-checks modules and prints every diagnostic with its location.
#include <cstdio>

#include "cli/command.h"
#include "cli/options.h"
#include "lang/session.h"

namespace tex::cli {
namespace {

const char* kHelp =
    "usage: tex check [-I DIR]... FILE...\n\n"
    "Parses, resolves and type-checks each .tex file and the modules it imports, and prints\n"
    "every diagnostic as `file:line:col: error[CODE]: message` with the source line and a\n"
    "caret. Exits 1 if any error was found, 0 otherwise.\n\n"
    "  -I DIR    add DIR to the module search path (also $TEX_PATH, colon-separated)\n";

int runCheck(const Args& args) {
  if (wantsHelp(args)) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  lang::SessionOptions options;
  std::vector<std::string> files;
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "-I") {
      if (i + 1 >= args.size()) return usageError("check", "-I needs a directory");
      options.searchPath.push_back(args[++i]);
    } else if (!args[i].empty() && args[i][0] == '-') {
      return usageError("check", "unknown option '" + args[i] + "'");
    } else {
      files.push_back(args[i]);
    }
  }
  if (files.empty()) return usageError("check", "no input files");
  bool anyError = false;
  for (const std::string& file : files) {
    lang::Session session(options);
    session.loadFile(file);
    for (const lang::Diagnostic& d : session.diags().items()) {
      std::string text = lang::renderDiagnostic(d);
      if (!d.span.file && text.rfind("error", 0) == 0) text = file + ": " + text;
      std::fputs(text.c_str(), stderr);
    }
    size_t errors = 0;
    for (const auto& d : session.diags().items()) errors += d.severity == lang::Severity::Error;
    if (errors) {
      anyError = true;
      std::fprintf(stderr, "%s: %zu error%s\n", file.c_str(), errors, errors == 1 ? "" : "s");
    }
  }
  return anyError ? 1 : 0;
}

}  // namespace

TEX_COMMAND("check", "type-check .tex files and print located diagnostics", &runCheck);

}  // namespace tex::cli
