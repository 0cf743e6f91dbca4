// Internal to lang/: the session's state shared by the loader, resolver and checker.
#pragma once
#include <filesystem>
#include <map>
#include <set>
#include <tuple>

#include "lang/session.h"

namespace tex::lang {

// Builtin names of the prelude (docs/language.md section 6).
bool isBuiltinFunction(const std::string& name);
bool isBuiltinConstant(const std::string& name);

struct Session::Impl {
  Session& session;
  explicit Impl(Session& s) : session(s) {}

  std::map<std::string, std::unique_ptr<ModuleInfo>> modulesByPath;  // canonical path -> module
  // Modules a failed REPL request loaded: no longer found by path (a retry loads the file
  // afresh), but kept alive because instances and reported spans may still point into them.
  std::vector<std::unique_ptr<ModuleInfo>> discardedModules;
  std::vector<std::string> loadingStack;                             // canonical paths
  std::unique_ptr<ModuleInfo> repl;
  std::vector<std::unique_ptr<Module>> replExpressions;  // keeps REPL expression ASTs alive
  // Inputs that failed to parse: their diagnostics point into them until they are printed.
  std::vector<std::shared_ptr<SourceFile>> replRejectedSources;

  // Instances: (what, argument types) -> IR function index (-2 while being built).
  std::map<std::pair<const void*, std::vector<const Type*>>, int> instances;
  std::map<const Expr*, ModuleInfo*> lambdaModule;  // the module a lambda's names resolve in
  std::set<std::tuple<std::string, const SourceFile*, uint32_t>> reported;  // dedupe
  int instanceDepth = 0;
  int genericInstances = 0;  // instances of unannotated definitions and lambdas (E0413)
  std::map<std::pair<const Expr*, std::string>, const Type*> captureAnnotations;
  int maxInstances() const { return session.options_.maxInstances; }

  // Loader (session.cpp)
  ModuleInfo* loadModule(const std::string& canonicalPath, const std::string& displayPath,
                         const std::string& dottedName, std::string text);
  void bindImports(ModuleInfo* module, Module& ast);
  void bindItems(ModuleInfo* module, Module& ast, bool replace);
  std::string findModuleFile(const std::vector<std::string>& path, const std::string& fromDir);

  // Resolver (resolver.cpp): unknown names and types, recursion, export annotations.
  void resolveModule(ModuleInfo* module, Module& ast);
  void resolveExpression(ModuleInfo* module, const Expr* expr, const std::vector<std::string>& params);

  // Checker (checker.cpp)
  void checkEagerly(ModuleInfo* module, Module& ast);
  int instantiateDecl(const FunctionDecl* decl, const std::vector<const Type*>& args, Span at);
  int compileExpression(ModuleInfo* scope, const Expr* expr,
                        const std::vector<std::pair<std::string, const Type*>>& params);
  const Type* resolveType(const TypeExpr* t, ModuleInfo* module, int depth = 0);
  // Type aliases being resolved (outermost first): one met again refers to itself.
  std::vector<const void*> resolvingAliases;

  // Reports once per (code, place).
  Diagnostic* error(const std::string& code, Span span, std::string message, std::string help = {});
};

const Symbol* lookupSymbol(const ModuleInfo* module, const std::string& name);

}  // namespace tex::lang
