// The compiler's public interface: typed core IR (lang/core_ir.h) to native code with LLVM 19
// and ORC LLJIT. All LLVM use in the project lives behind this header (docs/abi.md).
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "compiler/abi.h"
#include "lang/core_ir.h"
#include "lang/source.h"

namespace tex::compiler {

enum class OptLevel {
  Quick,  // no IR optimisation, fast instruction selection: REPL latency
  O1,     // the new pass manager's O1 pipeline: the default
};

struct CompileOptions {
  OptLevel opt = OptLevel::O1;
  int wavelengths = 4;           // Spectrum lanes: 4 or 8 (1 for measurements)
  bool useCache = true;          // the on-disk object cache (docs/abi.md, "Cache")
  bool readCache = true;         // with useCache: false compiles afresh and replaces the entry
  std::string cacheDir;          // empty: $TEX_CACHE_DIR, else $XDG_CACHE_HOME/tex, else ~/.cache/tex
  uint64_t maxInlinedNodes = 4'000'000;  // specialised-code size limit (E0413)
  uint64_t maxValueWords = 65536;         // largest value, in 32-bit words (E0413)
};

// What a compile did, for benchmarks and tests.
struct CompileStats {
  bool cacheHit = false;
  bool cacheRejected = false;  // a cache entry existed but failed verification and was rebuilt
  double milliseconds = 0;    // the whole compile() call
  double codegenMs = 0, optimiseMs = 0, emitMs = 0, linkMs = 0;  // its phases
  size_t objectBytes = 0;
  size_t objectCount = 0;  // object files: 2 when code generation was split across threads
  size_t tables = 0;       // computations read from constant tables (small_domain_tables.h); 0 on a cache hit
};

// Compiled code for some entry functions of one program. Destroying it unloads the code.
class CompiledModule {
 public:
  ~CompiledModule();
  CompiledModule(const CompiledModule&) = delete;
  CompiledModule& operator=(const CompiledModule&) = delete;

  // The entry point for program function `function` (one of those compiled).
  EntryFn entry(int function) const;
  const CompileStats& stats() const { return stats_; }

  struct Impl;
  explicit CompiledModule(std::unique_ptr<Impl> impl);

 private:
  std::unique_ptr<Impl> impl_;
  CompileStats stats_;
  friend std::unique_ptr<CompiledModule> compile(const lang::ir::Program&, const std::vector<int>&,
                                                 const CompileOptions&, lang::Diagnostics&);
};

// Compiles the entry functions (and everything they call) to native code. On failure
// returns null and reports diagnostics (never aborts). Thread-safe: compiles may run in
// parallel threads, each with its own LLVM context.
std::unique_ptr<CompiledModule> compile(const lang::ir::Program& program, const std::vector<int>& entries,
                                        const CompileOptions& options, lang::Diagnostics& diags);

// Argument and result buffers in the ABI's word layout.
size_t wordCount(const lang::Type* type, int wavelengths);

// The hash key of a compile (canonical IR text + versions + CPU + options), for the cache.
std::string cacheKey(const lang::ir::Program& program, const std::vector<int>& entries, const CompileOptions& options);

// Host CPU name and features, as LLVM sees them.
std::string hostCpuDescription();

}  // namespace tex::compiler
