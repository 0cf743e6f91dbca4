// `tex`: the command-line program. Dispatches to the registered subcommands.
#include <pthread.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <new>
#include <cstdio>
#include <cstring>

#include "cli/command.h"
#include "renderer/spectra/rgb_spectrum.h"

namespace tex::cli {

namespace {
std::vector<Command>& registry() {
  static std::vector<Command> all;
  return all;
}

void printUsage(FILE* out) {
  std::fprintf(out, "tex: a functional texture language and a spectral renderer\n\n"
                    "usage: tex <command> [options]\n\ncommands:\n");
  std::vector<Command> sorted = registry();
  std::sort(sorted.begin(), sorted.end(),
            [](const Command& a, const Command& b) { return std::strcmp(a.name, b.name) < 0; });
  for (const Command& c : sorted) std::fprintf(out, "  %-10s %s\n", c.name, c.summary);
  std::fprintf(out, "\nRun `tex <command> --help` for a command's options; `tex --version` prints the version.\n");
}

struct MainJob {
  int argc;
  char** argv;
  int exitCode = 0;
};

int dispatch(int argc, char** argv) {
  if (argc < 2) {
    printUsage(stderr);
    return 2;
  }
  std::string name = argv[1];
  if (name == "--help" || name == "-h" || name == "help") {
    printUsage(stdout);
    return 0;
  }
  if (name == "--version") {
    std::printf("tex 0.1.0\n");
    return 0;
  }
  for (const Command& c : registry()) {
    if (name != c.name) continue;
    try {
      return c.run(Args(argv + 2, argv + argc));
    } catch (const std::bad_alloc&) {
      // A film, image or scene too large for this machine (a resolution within the flags'
      // limits can still need more memory than there is): an error, not an abort.
      std::fprintf(stderr, "tex %s: error: out of memory (the image, scene or sample data is too large for this machine)\n",
                   c.name);
      return 1;
    }
  }
  std::fprintf(stderr, "tex: error: unknown command '%s'\n", name.c_str());
  printUsage(stderr);
  return 2;
}

void* runMainJob(void* raw) {
  auto* job = static_cast<MainJob*>(raw);
  job->exitCode = dispatch(job->argc, job->argv);
  return nullptr;
}
}  // namespace

bool registerCommand(const Command& command) {
  registry().push_back(command);
  return true;
}

const std::vector<Command>& commands() { return registry(); }

bool wantsHelp(const Args& args) {
  return std::any_of(args.begin(), args.end(),
                     [](const std::string& a) { return a == "-h" || a == "--help"; });
}

}  // namespace tex::cli

int main(int argc, char** argv) {
  // The language's RGB-to-spectrum builtins use the renderer's fitted table.
  tex::render::installRgbUpsampling();
  // The front end and interpreter recurse over syntax trees; their depth is bounded by the
  // parser's limits (8192 levels per definition), and a large stack keeps that bound far from
  // an overflow. The same for TBB's workers, which run the interpreter in `tex eval --interp`
  // (their default 2-4 MB overflowed at 4600 levels; calls nest up to ir::kMaxInlinedDepth,
  // about 450 bytes a level); only touched pages are committed.
  tbb::global_control workerStack(tbb::global_control::thread_stack_size, size_t(256) << 20);
  tex::cli::MainJob job{argc, argv};
  pthread_attr_t attr;
  pthread_attr_init(&attr);
  pthread_attr_setstacksize(&attr, size_t(512) << 20);
  pthread_t thread;
  if (pthread_create(&thread, &attr, tex::cli::runMainJob, &job) != 0) {
    tex::cli::runMainJob(&job);
  } else {
    pthread_join(thread, nullptr);
  }
  pthread_attr_destroy(&attr);
  return job.exitCode;
}
