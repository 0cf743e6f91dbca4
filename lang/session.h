// A front-end session: loads modules (imports, search path, cycles), resolves names, checks
// types by instantiating definitions, and accumulates the typed core IR of everything it
// instantiated. This is the narrow public interface of lang/ for the CLI, REPL and compiler.
#pragma once
#include <deque>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "lang/ast.h"
#include "lang/core_ir.h"
#include "lang/types.h"
#include "lang/value.h"

namespace tex::lang {

struct ModuleInfo;

// A module-level `fn` or `let` (a `let` is a function of no parameters).
struct FunctionDecl {
  const Item* item = nullptr;
  ModuleInfo* module = nullptr;
  std::string qualifiedName() const;
};

struct Symbol {
  enum class Kind { Decl, TypeAlias, Module } kind = Kind::Decl;
  const FunctionDecl* decl = nullptr;  // Decl
  const Item* typeItem = nullptr;      // TypeAlias
  ModuleInfo* owner = nullptr;         // TypeAlias: the defining module
  ModuleInfo* module = nullptr;        // Module
  Span span;                           // where it was bound (item name or import)
  bool imported = false;
};

struct ModuleInfo {
  std::string name;  // dotted ("std.noise"); the root file's name is its stem
  std::string path;  // file path ("" for REPL input)
  std::vector<std::unique_ptr<Module>> asts;  // one file, or a REPL's successive inputs
  std::deque<FunctionDecl> decls;
  std::map<std::string, Symbol> scope;  // items and imports
  bool checked = false;
  bool syntaxErrors = false;  // its file did not parse: names missing from it are not reported again
};

struct SessionOptions {
  std::vector<std::string> searchPath;  // -I directories, then $TEX_PATH
  std::string stdlibDir;                // empty: $TEX_STDLIB, then the build's source stdlib
  int maxInstances = 20000;             // specialisation limit (E0413)
};

class Session {
 public:
  explicit Session(SessionOptions options = {});
  ~Session();

  Diagnostics& diags() { return diags_; }
  ir::Program& program() { return program_; }

  // Loads a file as a root module with its imports, and checks it: names, recursion,
  // annotations, and every definition that can be typed without a call (exported and fully
  // annotated functions, constants). Returns null only if the file cannot be read.
  ModuleInfo* loadFile(const std::string& path);
  // Same for text in memory (tests, REPL). `path` is used for messages and relative imports.
  ModuleInfo* loadSource(const std::string& path, std::string text);

  // The REPL's module: definitions accumulate; a later definition replaces an earlier one.
  ModuleInfo* replModule();
  // Parses one REPL input. Definitions are added to the REPL module; an expression is
  // returned (owned by the session) for compileExpression. Returns false on syntax errors.
  bool addReplInput(const std::string& text, Expr*& expression, int inputNumber);
  // Imports every exported name of `module` into the REPL scope (`:load`).
  void importIntoRepl(ModuleInfo* module);
  // The REPL undoes a request that failed (an input, `:load`, one step of `:reload`), so that it
  // leaves no trace: the names it bound in the REPL scope, the modules it loaded and the IR it
  // built are dropped again, and retrying it reports the same errors again (diagnostics are
  // deduplicated within one request only, not across requests).
  struct ReplMark {
    size_t functions = 0, nodes = 0;
    std::map<std::string, Symbol> scope;
    std::set<std::string> modules;  // canonical paths of the modules loaded before the mark
  };
  ReplMark replMark();
  void replRollback(const ReplMark& mark);

  // Instantiates a module-level function for the given argument types (positional, all
  // parameters). Returns the IR function index, or -1 after reporting diagnostics.
  int instantiate(ModuleInfo* module, const std::string& name, const std::vector<const Type*>& args, Span at);
  // Compiles an expression in a module's scope as a function of the given parameters.
  int compileExpression(ModuleInfo* scope, const Expr* expr,
                        const std::vector<std::pair<std::string, const Type*>>& params);
  // Specialises IR function `function` on constant arguments (material parameters): returns a
  // new function of the parameters whose entry in `constants` is null, which calls `function`
  // with the given constants in place of the others (Bool, Int and Float-based values only).
  // The compiler inlines the call and folds the constants. Returns -1 if a constant's type
  // is not supported.
  int specialise(int function, const std::vector<const Value*>& constants);
  // Everything compiled after a mark can be dropped again: the REPL evaluates each expression
  // and rolls back, so a long session does not accumulate IR.
  struct Mark {
    size_t functions = 0, nodes = 0;
  };
  Mark mark() const { return {program_.functions.size(), program_.nodes.size()}; }
  void rollback(const Mark& mark);
  // Looks up an exported or local definition by name.
  const FunctionDecl* findFunction(ModuleInfo* module, const std::string& name) const;
  // The declared parameter and result types of a fully annotated function (null if not).
  bool signature(const FunctionDecl* decl, std::vector<const Type*>& params, const Type*& result);

  const std::string& stdlibDir() const { return stdlibDir_; }

  struct Impl;

 private:
  // `function`, or -1 with E0413 when its inlined depth exceeds ir::kMaxInlinedDepth.
  int withinInlinedDepth(int function, Span at);

  SessionOptions options_;
  std::string stdlibDir_;
  Diagnostics diags_;
  ir::Program program_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tex::lang
