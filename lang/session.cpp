#include "lang/session.h"

#include <cstdlib>
#include <unistd.h>

#include "lang/parser.h"
#include "lang/session_impl.h"

namespace fs = std::filesystem;

namespace tex::lang {

std::string FunctionDecl::qualifiedName() const {
  if (!module || module->name.empty()) return item->name;
  return module->name + "." + item->name;
}

const Symbol* lookupSymbol(const ModuleInfo* module, const std::string& name) {
  auto it = module->scope.find(name);
  return it == module->scope.end() ? nullptr : &it->second;
}

static std::string executableDir() {
  char buf[4096];
  ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n <= 0) return {};
  buf[n] = 0;
  return fs::path(buf).parent_path().string();
}

static std::string defaultStdlibDir() {
  if (const char* env = std::getenv("TEX_STDLIB"); env && *env) return env;
  // An installed layout (<prefix>/bin/tex, <prefix>/share/tex/stdlib) wins over the source tree.
  std::string exe = executableDir();
  if (!exe.empty()) {
    fs::path installed = fs::path(exe) / ".." / "share" / "tex" / "stdlib";
    std::error_code ec;
    if (fs::is_directory(installed, ec)) return installed.lexically_normal().string();
  }
#ifdef TEX_STDLIB_DIR
  return TEX_STDLIB_DIR;
#else
  return "stdlib";
#endif
}

Session::Session(SessionOptions options) : options_(std::move(options)), impl_(std::make_unique<Impl>(*this)) {
  stdlibDir_ = options_.stdlibDir.empty() ? defaultStdlibDir() : options_.stdlibDir;
  if (const char* env = std::getenv("TEX_PATH"); env && *env) {
    std::string all = env;
    size_t start = 0;
    while (start <= all.size()) {
      size_t colon = all.find(':', start);
      std::string dir = all.substr(start, colon == std::string::npos ? std::string::npos : colon - start);
      if (!dir.empty()) options_.searchPath.push_back(dir);
      if (colon == std::string::npos) break;
      start = colon + 1;
    }
  }
}

Session::~Session() = default;

Diagnostic* Session::Impl::error(const std::string& code, Span span, std::string message, std::string help) {
  auto key = std::make_tuple(code, span.file, span.begin);
  if (!reported.insert(key).second) return nullptr;
  return &session.diags_.error(code, span, std::move(message), std::move(help));
}

static std::string canonical(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
  return ec ? path : p.string();
}

ModuleInfo* Session::loadFile(const std::string& path) {
  std::string text, err;
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    diags_.error("E0303", Span{}, "'" + path + "' is a directory, not a .tex file");
    return nullptr;
  }
  if (!readFile(path, text, err)) {
    diags_.error("E0303", Span{}, err);
    return nullptr;
  }
  std::string canon = canonical(path);
  if (auto it = impl_->modulesByPath.find(canon); it != impl_->modulesByPath.end()) return it->second.get();
  return impl_->loadModule(canon, path, fs::path(path).stem().string(), std::move(text));
}

ModuleInfo* Session::loadSource(const std::string& path, std::string text) {
  std::string canon = canonical(path);
  impl_->modulesByPath.erase(canon);
  return impl_->loadModule(canon, path, fs::path(path).stem().string(), std::move(text));
}

ModuleInfo* Session::Impl::loadModule(const std::string& canonicalPath, const std::string& displayPath,
                                      const std::string& dottedName, std::string text) {
  auto owned = std::make_unique<ModuleInfo>();
  ModuleInfo* module = owned.get();
  module->name = dottedName;
  module->path = canonicalPath;
  modulesByPath[canonicalPath] = std::move(owned);

  auto file = std::make_shared<SourceFile>(displayPath, std::move(text));
  const size_t diagnosticsBefore = session.diags_.size();
  module->asts.push_back(parseModule(file, session.diags_));
  module->syntaxErrors = session.diags_.size() > diagnosticsBefore;
  Module& ast = *module->asts.back();

  loadingStack.push_back(canonicalPath);
  bindImports(module, ast);
  loadingStack.pop_back();
  bindItems(module, ast, false);
  resolveModule(module, ast);
  checkEagerly(module, ast);
  module->checked = true;
  return module;
}

std::string Session::Impl::findModuleFile(const std::vector<std::string>& path, const std::string& fromDir) {
  fs::path relative;
  for (const std::string& segment : path) relative /= segment;
  relative += ".tex";
  std::vector<std::string> roots;
  if (path.size() > 1 && path[0] == "std") {
    roots.push_back(session.stdlibDir_);
  } else {
    roots.push_back(fromDir);
    for (const std::string& dir : session.options_.searchPath) roots.push_back(dir);
  }
  for (const std::string& root : roots) {
    fs::path candidate = fs::path(root) / relative;
    std::error_code ec;
    if (fs::is_regular_file(candidate, ec)) return candidate.string();
  }
  return {};
}

static std::string joinPath(const std::vector<std::string>& path) {
  std::string s;
  for (size_t i = 0; i < path.size(); ++i) s += (i ? "." : "") + path[i];
  return s;
}

void Session::Impl::bindImports(ModuleInfo* module, Module& ast) {
  std::string fromDir = module->path.empty() ? fs::current_path().string() : fs::path(module->path).parent_path().string();
  for (const Import& imp : ast.imports) {
    std::string dotted = joinPath(imp.path);
    std::string file = findModuleFile(imp.path, fromDir);
    ModuleInfo* target = nullptr;
    if (file.empty()) {
      std::string where = imp.path.size() > 1 && imp.path[0] == "std" ? "in the standard library (" + session.stdlibDir_ + ")"
                                                                       : "next to the importing file or on the search path (-I, $TEX_PATH)";
      error("E0303", imp.pathSpan, "module '" + dotted + "' not found",
            "looked for " + fs::path(joinPath(imp.path)).string() + " as a .tex file " + where);
    } else {
      std::string canon = canonical(file);
      bool cyclic = false;
      for (const std::string& p : loadingStack) cyclic |= p == canon;
      if (cyclic) {
        Diagnostic* d = error("E0304", imp.pathSpan, "import cycle: '" + dotted + "' is already being loaded",
                              "modules may not import each other in a cycle; move shared definitions into a third module");
        if (d) {
          std::string chain;
          for (const std::string& p : loadingStack) chain += fs::path(p).filename().string() + " -> ";
          d->notes.push_back({Span{}, "cycle: " + chain + fs::path(canon).filename().string()});
        }
      } else if (auto it = modulesByPath.find(canon); it != modulesByPath.end()) {
        target = it->second.get();
      } else {
        std::string text, err;
        if (!readFile(file, text, err)) {
          error("E0303", imp.pathSpan, "module '" + dotted + "' cannot be read: " + err);
        } else {
          std::string display = file;
          target = loadModule(canon, display, dotted, std::move(text));
        }
      }
    }
    auto bind = [&](const std::string& name, Symbol sym, Span span) {
      sym.span = span;
      sym.imported = true;
      auto [it, inserted] = module->scope.emplace(name, sym);
      if (!inserted) {
        Diagnostic* d = error("E0302", span, "'" + name + "' is imported twice");
        if (d && it->second.span.file) d->notes.push_back({it->second.span, "first bound here"});
      }
    };
    if (imp.hasItemList) {
      for (const Import::Item& item : imp.items) {
        Symbol sym;
        sym.kind = Symbol::Kind::Decl;  // decl stays null when the module is missing: no cascade
        if (target) {
          const Symbol* found = lookupSymbol(target, item.name);
          bool exported = false;
          if (found && !found->imported) {
            if (found->kind == Symbol::Kind::Decl && found->decl) exported = found->decl->item->exported;
            if (found->kind == Symbol::Kind::TypeAlias) exported = found->typeItem->exported;
          }
          // A name missing from a module that did not parse was most likely lost to its syntax
          // error, reported already: a second "does not export" would only mislead.
          if (exported) {
            sym = *found;
          } else if (!(target->syntaxErrors && !found)) {
            error("E0305", item.span, "module '" + dotted + "' does not export '" + item.name + "'",
                  found && !found->imported ? "mark its definition with 'export'" : "");
          }
        }
        bind(item.alias, sym, item.span);
      }
    } else {
      Symbol sym;
      sym.kind = Symbol::Kind::Module;
      sym.module = target;  // null if missing: uses are silently errors
      bind(imp.alias, sym, imp.aliasSpan.file ? imp.aliasSpan : imp.pathSpan);
    }
  }
}

void Session::Impl::bindItems(ModuleInfo* module, Module& ast, bool replace) {
  for (const Item& item : ast.items) {
    Symbol sym;
    sym.span = item.nameSpan;
    if (item.kind == Item::Kind::Type) {
      sym.kind = Symbol::Kind::TypeAlias;
      sym.typeItem = &item;
      sym.owner = module;
    } else {
      module->decls.push_back(FunctionDecl{&item, module});
      sym.kind = Symbol::Kind::Decl;
      sym.decl = &module->decls.back();
    }
    auto it = module->scope.find(item.name);
    if (it != module->scope.end() && !replace) {
      Diagnostic* d = error("E0302", item.nameSpan,
                            "'" + item.name + "' is already " + (it->second.imported ? "imported" : "defined") + " in this module");
      if (d && it->second.span.file) d->notes.push_back({it->second.span, "previous binding here"});
      continue;
    }
    module->scope[item.name] = sym;
  }
}

ModuleInfo* Session::replModule() {
  if (!impl_->repl) {
    impl_->repl = std::make_unique<ModuleInfo>();
    impl_->repl->name = "";
    impl_->repl->path = "";
  }
  return impl_->repl.get();
}

bool Session::addReplInput(const std::string& text, Expr*& expression, int inputNumber) {
  ModuleInfo* repl = replModule();
  impl_->reported.clear();  // each input is its own request: an error met before is reported again
  auto file = std::make_shared<SourceFile>("<repl:" + std::to_string(inputNumber) + ">", text);
  size_t errorsBefore = diags_.items().size();
  auto ast = parseReplInput(file, diags_, expression);
  if (diags_.items().size() != errorsBefore) {
    impl_->replRejectedSources.push_back(file);
    expression = nullptr;
    return false;
  }
  Module& m = *ast;
  if (expression) {
    impl_->replExpressions.push_back(std::move(ast));
    impl_->resolveExpression(repl, expression, {"hit"});
    return diags_.items().size() == errorsBefore;
  }
  repl->asts.push_back(std::move(ast));
  // A REPL may rebind names: drop earlier bindings of names this input defines or imports.
  for (const Item& item : m.items) repl->scope.erase(item.name);
  for (const Import& imp : m.imports) {
    if (imp.hasItemList)
      for (auto& item : imp.items) repl->scope.erase(item.alias);
    else
      repl->scope.erase(imp.alias);
  }
  impl_->bindImports(repl, m);
  impl_->bindItems(repl, m, true);
  impl_->resolveModule(repl, m);
  impl_->checkEagerly(repl, m);
  return diags_.items().size() == errorsBefore;
}

void Session::importIntoRepl(ModuleInfo* module) {
  ModuleInfo* repl = replModule();
  for (auto& [name, sym] : module->scope) {
    if (sym.imported) continue;
    bool exported = (sym.kind == Symbol::Kind::Decl && sym.decl && sym.decl->item->exported) ||
                    (sym.kind == Symbol::Kind::TypeAlias && sym.typeItem->exported);
    // :load makes the file's own definitions available, exported or not, for exploring.
    (void)exported;
    Symbol copy = sym;
    copy.imported = true;
    repl->scope[name] = copy;
  }
}

Session::ReplMark Session::replMark() {
  ReplMark mark;
  mark.functions = program_.functions.size();
  mark.nodes = program_.nodes.size();
  mark.scope = replModule()->scope;
  for (const auto& [path, module] : impl_->modulesByPath) mark.modules.insert(path);
  return mark;
}

void Session::replRollback(const ReplMark& mark) {
  replModule()->scope = mark.scope;
  for (auto it = impl_->modulesByPath.begin(); it != impl_->modulesByPath.end();) {
    if (mark.modules.count(it->first)) {
      ++it;
      continue;
    }
    impl_->discardedModules.push_back(std::move(it->second));
    it = impl_->modulesByPath.erase(it);
  }
  rollback(Mark{mark.functions, mark.nodes});
  impl_->reported.clear();
}

int Session::instantiate(ModuleInfo* module, const std::string& name, const std::vector<const Type*>& args, Span at) {
  const FunctionDecl* decl = findFunction(module, name);
  if (!decl) {
    diags_.error("E0301", at, "no definition named '" + name + "' in " + (module->path.empty() ? "the REPL" : module->path));
    return -1;
  }
  return withinInlinedDepth(impl_->instantiateDecl(decl, args, at), at);
}

int Session::compileExpression(ModuleInfo* scope, const Expr* expr,
                               const std::vector<std::pair<std::string, const Type*>>& params) {
  return withinInlinedDepth(impl_->compileExpression(scope, expr, params), expr->span);
}

// Each definition's tree is at most 8192 levels deep (the parser), but calls stack the bodies
// of their callees under them: 60 functions of 4000-operator chains calling each other nest
// 240,000 deep, and the interpreter and the compiler recurse that deep. E0413 beyond
// ir::kMaxInlinedDepth, before anything evaluates or compiles the entry.
int Session::withinInlinedDepth(int function, Span at) {
  if (function < 0) return function;
  std::map<int, uint64_t> memo;
  const uint64_t depth = ir::inlinedDepth(program_, function, memo);
  if (depth <= ir::kMaxInlinedDepth) return function;
  diags_.error("E0413", at,
               "specialisation limit exceeded: with its calls expanded this nests " + std::to_string(depth) +
                   " levels deep (at most " + std::to_string(ir::kMaxInlinedDepth) + ")",
               "long chains of calls to long expressions multiply: share intermediate results with let");
  return -1;
}

void Session::rollback(const Mark& mark) {
  for (auto it = impl_->instances.begin(); it != impl_->instances.end();) {
    if (it->second >= int(mark.functions)) it = impl_->instances.erase(it);
    else ++it;
  }
  if (program_.functions.size() > mark.functions) program_.functions.resize(mark.functions);
  if (program_.nodes.size() > mark.nodes) program_.nodes.resize(mark.nodes);
}

int Session::specialise(int function, const std::vector<const Value*>& constants) {
  const ir::Function& target = program_.functions[size_t(function)];
  if (constants.size() != target.paramTypes.size()) return -1;
  ir::Function fn;
  fn.name = target.name + "<specialised>";
  fn.span = target.span;
  fn.resultType = target.resultType;
  ir::Node* call = program_.node(ir::Node::Kind::Call, target.resultType, target.span);
  call->callee = function;
  for (size_t i = 0; i < constants.size(); ++i) {
    const Type* t = target.paramTypes[i];
    if (!constants[i]) {
      ir::Node* local = program_.node(ir::Node::Kind::Local, t, target.span);
      local->slot = int(fn.paramTypes.size());
      fn.paramTypes.push_back(t);
      call->args.push_back(local);
      continue;
    }
    if (t->kind != TypeKind::Bool && t->kind != TypeKind::Int && !t->isFloatBased()) return -1;
    ir::Node* c = program_.node(ir::Node::Kind::Const, t, target.span);
    for (int k = 0; k < kMaxLanes; ++k) c->floatValue[k] = constants[i]->f[t->kind == TypeKind::Spectrum ? 0 : k];
    c->intValue = constants[i]->i;
    c->boolValue = constants[i]->i != 0;
    call->args.push_back(c);
  }
  fn.numSlots = int(fn.paramTypes.size());
  fn.body = call;
  program_.functions.push_back(std::move(fn));
  return int(program_.functions.size()) - 1;
}

const FunctionDecl* Session::findFunction(ModuleInfo* module, const std::string& name) const {
  const Symbol* sym = lookupSymbol(module, name);
  if (!sym || sym->kind != Symbol::Kind::Decl) return nullptr;
  return sym->decl;
}

bool Session::signature(const FunctionDecl* decl, std::vector<const Type*>& params, const Type*& result) {
  params.clear();
  result = nullptr;
  if (decl->item->kind != Item::Kind::Function) return false;
  for (const Param& p : decl->item->params) {
    if (!p.type) return false;
    params.push_back(impl_->resolveType(p.type, decl->module));
  }
  if (decl->item->resultType) result = impl_->resolveType(decl->item->resultType, decl->module);
  return true;
}

}  // namespace tex::lang
