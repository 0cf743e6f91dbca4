// compile(): specialised-size check, cache lookup, codegen, optimisation, object emission
// and loading into ORC LLJIT (one JITDylib per compiled module, removed on unload).
#include "compiler/jit.h"

#include <llvm/ExecutionEngine/Orc/ExecutionUtils.h>
#include <llvm/ExecutionEngine/Orc/JITTargetMachineBuilder.h>
#include <llvm/ExecutionEngine/Orc/LLJIT.h>
#include <llvm/IR/LegacyPassManager.h>
#include <llvm/Passes/PassBuilder.h>
#include <llvm/Transforms/Scalar/InstSimplifyPass.h>
#include <llvm/Transforms/IPO/AlwaysInliner.h>
#include <llvm/Transforms/Scalar/EarlyCSE.h>
#include <llvm/Transforms/Scalar/GVN.h>
#include <llvm/Transforms/Scalar/SROA.h>
#include <llvm/Transforms/Scalar/SimplifyCFG.h>
#include <llvm/Support/CommandLine.h>
#include <llvm/Support/MemoryBuffer.h>
#include <llvm/Support/TargetSelect.h>
#include <llvm/Target/TargetMachine.h>

#include <atomic>
#include <chrono>
#include <map>
#include <mutex>

#include "compiler/canonical_ir.h"
#include "compiler/codegen.h"
#include "compiler/object_cache.h"
#include "compiler/isel_barriers.h"
#include "compiler/small_domain_tables.h"
#include "compiler/parallel_emit.h"
#include "compiler/select_lowering.h"

namespace tex::compiler {

namespace {

// Bump on every change to code generation: it is part of every cache key.
constexpr const char* kCompilerVersion = "tex-compiler-20";  // 20: anisotropic roughness (closure flag bit 1)

std::string errorText(llvm::Error error) { return llvm::toString(std::move(error)); }

// The process-wide JIT: created on first use, shared by every compiled module.
struct Engine {
  std::unique_ptr<llvm::orc::LLJIT> jit;
  std::string error;
  std::string cpu, features, triple;
  std::atomic<uint64_t> counter{0};
  std::mutex mutex;  // serialises JITDylib creation and removal

  // Never destroyed: compiled modules may outlive static destruction (a static holding one
  // would otherwise unload into a destroyed JIT at exit).
  static Engine& get() {
    static Engine* engine = new Engine();
    return *engine;
  }

 private:
  Engine() {
    // Three code-generation passes that cost compile time without speeding up texture code
    // (measured with bench/bench_jit.cpp: together about 1.5 ms less per O1 compile, the same
    // evaluation speed within noise): AVX-512 domain reassignment, the machine instruction
    // scheduler, which out-of-order x86 cores make nearly redundant, and machine loop-invariant
    // code motion (texture loops are short folds over octaves or cells). LLVM options are
    // process-wide; the compiler is the process's only LLVM user.
    static const char* argv[] = {"tex", "-disable-x86-domain-reassignment", "-enable-misched=false",
                                 "-disable-machine-licm"};
    llvm::cl::ParseCommandLineOptions(4, argv);
    llvm::InitializeNativeTarget();
    llvm::InitializeNativeTargetAsmPrinter();
    auto jtmb = llvm::orc::JITTargetMachineBuilder::detectHost();
    if (!jtmb) {
      error = errorText(jtmb.takeError());
      return;
    }
    cpu = jtmb->getCPU();
    features = jtmb->getFeatures().getString();
    triple = jtmb->getTargetTriple().str();
    auto created = llvm::orc::LLJITBuilder().setJITTargetMachineBuilder(*jtmb).create();
    if (!created) {
      error = errorText(created.takeError());
      return;
    }
    jit = std::move(*created);
    llvm::orc::JITDylib& main = jit->getMainJITDylib();
    // The C library (sinf, powf, ...) as the interpreter uses it, and our runtime functions.
    auto process = llvm::orc::DynamicLibrarySearchGenerator::GetForCurrentProcess(jit->getDataLayout().getGlobalPrefix());
    if (!process) {
      error = errorText(process.takeError());
      return;
    }
    main.addGenerator(std::move(*process));
    llvm::orc::SymbolMap runtime;
    auto& es = jit->getExecutionSession();
    auto bind = [&](const char* name, auto* fn) {
      runtime[es.intern(name)] = {llvm::orc::ExecutorAddr::fromPtr(fn), llvm::JITSymbolFlags::Exported | llvm::JITSymbolFlags::Callable};
    };
    bind("tex_rt_image_handle", &tex_rt_image_handle);
    bind("tex_rt_image_lookup", &tex_rt_image_lookup);
    bind("tex_rt_image_size", &tex_rt_image_size);
    bind("tex_rt_rgb_spectrum", &tex_rt_rgb_spectrum);
    if (auto err = main.define(llvm::orc::absoluteSymbols(std::move(runtime)))) error = errorText(std::move(err));
  }
};

// One target machine per thread and optimisation level: they are not shared across threads.
llvm::TargetMachine* targetMachine(OptLevel opt, std::string& error) {
  thread_local std::map<int, std::unique_ptr<llvm::TargetMachine>> machines;
  auto& slot = machines[int(opt)];
  if (!slot) {
    auto jtmb = llvm::orc::JITTargetMachineBuilder::detectHost();
    if (!jtmb) {
      error = errorText(jtmb.takeError());
      return nullptr;
    }
    jtmb->setCodeGenOptLevel(opt == OptLevel::Quick ? llvm::CodeGenOptLevel::None : llvm::CodeGenOptLevel::Less);
    auto tm = jtmb->createTargetMachine();
    if (!tm) {
      error = errorText(tm.takeError());
      return nullptr;
    }
    slot = std::move(*tm);
  }
  return slot.get();
}

void optimise(llvm::Module& module, llvm::TargetMachine* tm, OptLevel opt) {
  llvm::LoopAnalysisManager lam;
  llvm::FunctionAnalysisManager fam;
  llvm::CGSCCAnalysisManager cgam;
  llvm::ModuleAnalysisManager mam;
  llvm::PassBuilder pb(tm);
  pb.registerModuleAnalyses(mam);
  pb.registerCGSCCAnalyses(cgam);
  pb.registerFunctionAnalyses(fam);
  pb.registerLoopAnalyses(lam);
  pb.crossRegisterProxies(lam, fam, cgam, mam);
  if (opt == OptLevel::Quick) {
    llvm::ModulePassManager mpm = pb.buildO0DefaultPipeline(llvm::OptimizationLevel::O0);
    mpm.run(module, mam);
    return;
  }
  // A lean pipeline instead of the default O1: everything is already specialised and calls
  // are expanded in place by the code generator (only the entry wrappers' calls are left to
  // the always-inliner), so the work left is scalar clean-up and redundancy elimination.
  // Measured against O1 on the benchmark textures: the same speed of generated code, about
  // half the optimisation time (bench/bench_jit.cpp, docs/abi.md). InstSimplify rather than
  // InstCombine: InstCombine spent most of its time on known-bits queries through integer
  // hashes, and instruction selection does the combining that matters here (same speed).
  llvm::ModulePassManager mpm;
  mpm.addPass(llvm::AlwaysInlinerPass());
  llvm::FunctionPassManager fpm;
  fpm.addPass(llvm::SROAPass(llvm::SROAOptions::ModifyCFG));
  fpm.addPass(llvm::EarlyCSEPass());
  fpm.addPass(llvm::InstSimplifyPass());
  fpm.addPass(llvm::SimplifyCFGPass());
  fpm.addPass(llvm::GVNPass());
  mpm.addPass(llvm::createModuleToFunctionPassAdaptor(std::move(fpm)));
  mpm.run(module, mam);
}

bool emitObject(llvm::Module& module, llvm::TargetMachine* tm, std::string& object, std::string& error) {
  llvm::SmallVector<char, 0> buffer;
  llvm::raw_svector_ostream out(buffer);
  llvm::legacy::PassManager pm;
  if (tm->addPassesToEmitFile(pm, out, nullptr, llvm::CodeGenFileType::ObjectFile)) {
    error = "the target cannot emit object files";
    return false;
  }
  pm.run(module);
  object.assign(buffer.begin(), buffer.end());
  return true;
}

lang::Span spanOf(const lang::ir::Program& program, const std::vector<int>& entries) {
  return entries.empty() ? lang::Span{} : program.functions[size_t(entries[0])].span;
}

}  // namespace

struct CompiledModule::Impl {
  llvm::orc::JITDylib* dylib = nullptr;
  std::map<int, EntryFn> entries;
};

CompiledModule::CompiledModule(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

CompiledModule::~CompiledModule() {
  if (!impl_ || !impl_->dylib) return;
  Engine& engine = Engine::get();
  std::lock_guard<std::mutex> lock(engine.mutex);
  if (auto err = engine.jit->getExecutionSession().removeJITDylib(*impl_->dylib)) llvm::consumeError(std::move(err));
}

EntryFn CompiledModule::entry(int function) const {
  auto it = impl_->entries.find(function);
  return it == impl_->entries.end() ? nullptr : it->second;
}

std::string hostCpuDescription() {
  Engine& engine = Engine::get();
  return engine.triple + " " + engine.cpu + " " + engine.features;
}

std::string cacheKey(const lang::ir::Program& program, const std::vector<int>& entries, const CompileOptions& options) {
  std::string key = std::string(kCompilerVersion) + "\nllvm " + TEX_LLVM_VERSION + "\n" + hostCpuDescription() +
                    "\nopt " + std::to_string(int(options.opt)) + " lanes " + std::to_string(options.wavelengths) + "\n";
  return key + canonicalText(program, entries);
}

size_t wordCount(const lang::Type* type, int wavelengths) {
  switch (type->kind) {
    case lang::TypeKind::Bool:
    case lang::TypeKind::Int:
    case lang::TypeKind::Material:
    case lang::TypeKind::Image:
    case lang::TypeKind::Float: return 1;
    case lang::TypeKind::Spectrum: return size_t(wavelengths);
    case lang::TypeKind::Record:
    case lang::TypeKind::Lambda: {
      size_t n = 0;
      for (auto& f : type->fields) n += wordCount(f.second, wavelengths);
      return n;
    }
    default: return size_t(type->fixedLanes());
  }
}

std::unique_ptr<CompiledModule> compile(const lang::ir::Program& program, const std::vector<int>& entries,
                                        const CompileOptions& options, lang::Diagnostics& diags) {
  auto start = std::chrono::steady_clock::now();
  lang::Span at = spanOf(program, entries);
  auto fail = [&](const std::string& code, const std::string& message, const std::string& help = {}) {
    diags.error(code, at, message, help);
    return std::unique_ptr<CompiledModule>();
  };
  if (options.wavelengths != 1 && options.wavelengths != 4 && options.wavelengths != 8)
    return fail("E0501", "the compiler supports 1, 4 or 8 wavelengths, not " + std::to_string(options.wavelengths));
  for (int e : entries) {
    if (e < 0 || size_t(e) >= program.functions.size() || !program.functions[size_t(e)].body)
      return fail("E0501", "internal compiler error: no such function to compile");
    if (program.functions[size_t(e)].resultType->isError())
      return fail("E0501", "internal compiler error: cannot compile a function with type errors");
    // A value too large to hold (records sharing structure double per level) is refused
    // before LLVM is asked to lay out its type.
    const LargestValue largest = largestValue(program, e, options.wavelengths);
    if (largest.words > options.maxValueWords)
      return fail("E0413",
                  "a value of '" + program.functions[size_t(e)].name + "' would take " + std::to_string(largest.words) +
                      " words; the limit is " + std::to_string(options.maxValueWords),
                  "records that contain the same record twice double in size with each level");
    uint64_t size = inlinedSize(program, e);
    if (size > options.maxInlinedNodes)
      return fail("E0413",
                  "specialised code for '" + program.functions[size_t(e)].name + "' would have " + std::to_string(size) +
                      " operations after inlining; the limit is " + std::to_string(options.maxInlinedNodes),
                  "nested calls multiply: share intermediate results with let, or use fold instead of repeating calls");
  }
  Engine& engine = Engine::get();
  if (!engine.jit) return fail("E0501", "the LLVM JIT could not start: " + engine.error);

  CompileStats stats;
  std::string key = options.useCache ? cacheKey(program, entries, options) : std::string();
  std::string directory = options.useCache ? cacheDirectory(options.cacheDir) : std::string();
  std::vector<std::string> objects;
  if (options.useCache && options.readCache) {
    CacheLookup lookup = loadCachedObjects(directory, key, objects);
    stats.cacheHit = lookup == CacheLookup::Hit;
    stats.cacheRejected = lookup == CacheLookup::Rejected;
  }
  if (!stats.cacheHit) {
    std::string error;
    llvm::TargetMachine* tm = targetMachine(options.opt, error);
    if (!tm) return fail("E0501", "LLVM target machine: " + error);
    llvm::LLVMContext context;  // one per compile job: compiles may run in parallel threads
    CodegenOptions codegen;
    codegen.wavelengths = options.wavelengths;
    codegen.inlineEverything = options.opt != OptLevel::Quick;
    auto phase = std::chrono::steady_clock::now();
    auto lap = [&phase]() {
      auto now = std::chrono::steady_clock::now();
      double ms = std::chrono::duration<double, std::milli>(now - phase).count();
      phase = now;
      return ms;
    };
    std::unique_ptr<llvm::Module> module = generateModule(context, program, entries, codegen, error);
    if (!module) return fail("E0501", error);
    module->setDataLayout(tm->createDataLayout());
    module->setTargetTriple(tm->getTargetTriple().str());
    stats.codegenMs = lap();
    OptLevel opt = options.opt;
    std::atomic<size_t> tables{0};  // summed over the parts, which may run on two threads
    auto optimiseFn = [opt, &tables](llvm::Module& part) {
      std::string partError;
      llvm::TargetMachine* partTm = targetMachine(opt, partError);  // the calling thread's
      if (!partTm) return;  // emitFn reports the same error
      optimise(part, partTm, opt);
      if (opt != OptLevel::Quick) {
        tables += tabulateSmallDomainFunctions(part);  // before the select lowering: it reads the selects
        lowerFloatSelectsToIntegerSelects(part);
        insertIntegerMultiplyBarriers(part);
      }
      if (const char* dump = getenv("TEX_DUMP_IR"); dump && *dump) {  // debugging: each part appended
        static std::mutex dumpMutex;  // the two halves of a split compile dump one after the other
        std::lock_guard<std::mutex> lock(dumpMutex);
        std::error_code ec;
        llvm::raw_fd_ostream out(dump, ec, llvm::sys::fs::OF_Append);
        if (!ec) part.print(out, nullptr);
      }
    };
    auto emitFn = [opt](llvm::Module& part, std::string& object, std::string& partError) {
      llvm::TargetMachine* partTm = targetMachine(opt, partError);
      return partTm && emitObject(part, partTm, object, partError);
    };
    PartTimes times;
    if (!optimiseAndEmitInParts(*module, optimiseFn, emitFn, objects, times, error))
      return fail("E0501", "LLVM code generation: " + error);
    stats.optimiseMs = times.optimiseMs;
    stats.emitMs = times.emitMs;
    stats.tables = tables;
    if (options.useCache) storeCachedObjects(directory, key, objects);
  }
  for (const std::string& object : objects) stats.objectBytes += object.size();
  stats.objectCount = objects.size();

  auto linkStart = std::chrono::steady_clock::now();
  auto impl = std::make_unique<CompiledModule::Impl>();
  {
    std::lock_guard<std::mutex> lock(engine.mutex);
    auto dylib = engine.jit->createJITDylib("tex" + std::to_string(engine.counter++));
    if (!dylib) return fail("E0501", "LLVM JIT: " + errorText(dylib.takeError()));
    impl->dylib = &*dylib;
    impl->dylib->addToLinkOrder(engine.jit->getMainJITDylib());
  }
  auto result = std::unique_ptr<CompiledModule>(new CompiledModule(std::move(impl)));
  // A cached entry that passed its checksum but does not link (written by a broken build, or
  // one that changed without a new kCompilerVersion) is compiled afresh and replaced: it had
  // been a permanent E0501 until the entry was deleted by hand.
  const auto rebuildAfterBadEntry = [&]() {
    CompileOptions fresh = options;
    fresh.readCache = false;
    std::unique_ptr<CompiledModule> rebuilt = compile(program, entries, fresh, diags);
    if (rebuilt) rebuilt->stats_.cacheRejected = true;
    return rebuilt;
  };
  for (const std::string& object : objects) {
    auto buffer = llvm::MemoryBuffer::getMemBufferCopy(object, "tex-object");
    if (auto err = engine.jit->addObjectFile(*result->impl_->dylib, std::move(buffer))) {
      if (stats.cacheHit) {
        llvm::consumeError(std::move(err));
        return rebuildAfterBadEntry();
      }
      return fail("E0501", "LLVM JIT: " + errorText(std::move(err)));
    }
  }
  for (size_t k = 0; k < entries.size(); ++k) {
    auto address = engine.jit->lookup(*result->impl_->dylib, entrySymbol(k));
    if (!address) {
      if (stats.cacheHit) {
        llvm::consumeError(address.takeError());
        return rebuildAfterBadEntry();
      }
      return fail("E0501", "LLVM JIT: " + errorText(address.takeError()));
    }
    result->impl_->entries[entries[k]] = address->toPtr<EntryFn>();
  }
  auto end = std::chrono::steady_clock::now();
  stats.linkMs = std::chrono::duration<double, std::milli>(end - linkStart).count();
  stats.milliseconds = std::chrono::duration<double, std::milli>(end - start).count();
  result->stats_ = stats;
  return result;
}

}  // namespace tex::compiler
