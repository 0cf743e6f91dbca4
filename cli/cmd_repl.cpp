// `tex repl`: an interactive evaluator. Line editing and history through libedit when stdin
// is a terminal; plain line reading (no prompts) when it is piped.
#include <editline/readline.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <functional>
#include <memory>
#include <set>
#include <sstream>

#include "cli/command.h"
#include "cli/options.h"
#include "compiler/jit.h"
#include "compiler/value_layout.h"
#include "lang/interpreter.h"
#include "lang/parser.h"
#include "lang/session.h"

namespace tex::cli {
namespace {

const char* kHelp =
    "usage: tex repl [-I DIR]... [--interp]\n\n"
    "Reads definitions (fn, let, type, import) and expressions; prints each expression's value\n"
    "and type. Input continues on the next line while brackets are open or an expression is\n"
    "unfinished. Works with piped input: `echo '1 + 2' | tex repl` prints `3 : Int`.\n"
    "Expressions are compiled by the LLVM JIT in quick mode; --interp uses the interpreter.\n\n"
    "Commands:\n"
    "  :type EXPR       show the type of EXPR without evaluating it\n"
    "  :ir EXPR         show the typed core IR of EXPR\n"
    "  :load FILE       load a .tex module; its definitions become available\n"
    "  :reload          reload every loaded file and replay the session's definitions\n"
    "  :hit [uv=U,V] [p=X,Y,Z] [n=X,Y,Z] [lambda=L1,L2,...]\n"
    "                   set the shading context; `hit` in expressions is that Hit and\n"
    "                   Spectrum values are evaluated at the lambda list (1 to 8 nm values)\n"
    "  :help            this text\n"
    "  :quit            leave (also Ctrl-D)\n";

struct HitContext {
  float p[3] = {0.5f, 0.5f, 0};
  float n[3] = {0, 0, 1};
  float uv[2] = {0.5f, 0.5f};
  lang::WavelengthGroup group;
};

class Repl {
 public:
  Repl(lang::SessionOptions options, bool interactive, bool interpret)
      : options_(std::move(options)), interactive_(interactive), interpret_(interpret) {
    reset();
  }

  int run() {
    std::string pending;
    while (true) {
      std::string line;
      if (!readLine(pending.empty() ? "tex> " : "...> ", line)) break;
      if (pending.empty() && line.empty()) continue;
      if (pending.empty() && line[0] == ':') {
        if (!command(line)) break;
        continue;
      }
      pending += pending.empty() ? line : "\n" + line;
      if (!line.empty() && incomplete(pending)) continue;  // an empty line forces evaluation
      input(pending);
      pending.clear();
    }
    if (!pending.empty()) input(pending);
    return sawError_ && !interactive_ ? 1 : 0;
  }

 private:
  void reset() {
    session_ = std::make_unique<lang::Session>(options_);
    session_->replModule();
  }

  bool readLine(const char* prompt, std::string& line) {
    if (interactive_) {
      char* raw = readline(prompt);
      if (!raw) {
        std::printf("\n");
        return false;
      }
      line = raw;
      std::free(raw);
      if (!line.empty()) add_history(line.c_str());
      return true;
    }
    return static_cast<bool>(std::getline(std::cin, line));
  }

  // True when the input ends inside brackets or an unfinished expression.
  bool incomplete(const std::string& text) {
    lang::Diagnostics scratch;
    auto file = std::make_shared<lang::SourceFile>("<repl>", text);
    lang::Expr* expr = nullptr;
    lang::parseReplInput(file, scratch, expr);
    for (const lang::Diagnostic& d : scratch.items()) {
      if (d.code == "E0203") return true;
      if (d.code == "E0201" && d.span.begin >= text.size()) return true;
      if (d.code == "E0103") return true;
    }
    return false;
  }

  void printNewDiagnostics() {
    for (const lang::Diagnostic& d : session_->diags().items()) {
      std::fputs(lang::renderDiagnostic(d).c_str(), stderr);
      if (d.severity == lang::Severity::Error) sawError_ = true;
    }
    std::fflush(stderr);
    session_->diags().clear();
  }

  lang::Value hitValue() const { return lang::makeHit(hit_.p, hit_.n, hit_.uv, 0, 0); }

  // Compiles an expression input; returns the IR function index or -1.
  int compile(const std::string& text, bool recordDefinitions) {
    lang::Expr* expr = nullptr;
    bool ok = session_->addReplInput(text, expr, ++inputs_);
    if (ok && !expr && recordDefinitions) history_.push_back(text);
    if (!ok || !expr) {
      printNewDiagnostics();
      return -1;
    }
    int fn = session_->compileExpression(session_->replModule(), expr, {{"hit", lang::TypeTable::global().hit()}});
    printNewDiagnostics();
    return fn;
  }

  void input(const std::string& text) {
    // Expressions are compiled, evaluated and dropped again; definitions stay.
    lang::Session::Mark mark = session_->mark();
    int fn = compile(text, true);
    if (fn >= 0) {
      const lang::ir::Function& f = session_->program().functions[size_t(fn)];
      lang::Value v;
      if (run(fn, v))
        std::printf("%s : %s\n", lang::formatValue(v, f.resultType, hit_.group).c_str(), lang::typeName(f.resultType).c_str());
      std::fflush(stdout);
      session_->rollback(mark);
    }
  }

  bool command(const std::string& line) {
    std::string name = line.substr(0, line.find(' '));
    std::string rest = line.size() > name.size() ? line.substr(name.size() + 1) : "";
    if (name == ":quit" || name == ":q" || name == ":exit") return false;
    if (name == ":help" || name == ":h") {
      std::fputs(kHelp, stdout);
    } else if (name == ":type" || name == ":t") {
      lang::Session::Mark mark = session_->mark();
      int fn = compile(rest, false);
      if (fn >= 0) {
        std::printf("%s\n", lang::typeName(session_->program().functions[size_t(fn)].resultType).c_str());
        session_->rollback(mark);
      }
    } else if (name == ":ir") {
      lang::Session::Mark mark = session_->mark();
      int fn = compile(rest, false);
      if (fn >= 0) {
        std::set<int> shown;
        dumpWithCallees(fn, shown);
        session_->rollback(mark);
      }
    } else if (name == ":load" || name == ":l") {
      load(rest, true);
    } else if (name == ":reload" || name == ":r") {
      reset();
      auto files = loaded_;
      auto defs = history_;
      loaded_.clear();
      history_.clear();
      for (const std::string& f : files) load(f, true);
      for (const std::string& d : defs) compile(d, true);
      std::printf("reloaded %zu file(s) and %zu definition(s)\n", files.size(), defs.size());
    } else if (name == ":hit") {
      setHit(rest);
    } else {
      std::fprintf(stderr, "unknown command '%s' (try :help)\n", name.c_str());
      sawError_ = true;
    }
    std::fflush(stdout);
    return true;
  }

  // Evaluates a compiled REPL expression (a function of `hit`): JIT in quick mode, or the
  // interpreter. The compiled code is unloaded right after.
  bool run(int fn, lang::Value& out) {
    if (interpret_) {
      out = lang::evaluate(session_->program(), fn, {hitValue()}, hit_.group);
      return true;
    }
    compiler::CompileOptions options;
    options.opt = compiler::OptLevel::Quick;
    options.useCache = false;  // REPL lines are one-offs: keep them out of the cache
    options.wavelengths = hit_.group.count;
    if (options.wavelengths != 1 && options.wavelengths != 4 && options.wavelengths != 8) {
      out = lang::evaluate(session_->program(), fn, {hitValue()}, hit_.group);  // the JIT has 1, 4 or 8 lanes
      return true;
    }
    auto module = compiler::compile(session_->program(), {fn}, options, session_->diags());
    if (!module) {
      printNewDiagnostics();
      return false;
    }
    const lang::Type* hitType = lang::TypeTable::global().hit();
    std::vector<uint32_t> args;
    compiler::flatten(hitValue(), hitType, options.wavelengths, args);
    const lang::Type* resultType = session_->program().functions[size_t(fn)].resultType;
    std::vector<uint32_t> result(compiler::wordCount(resultType, options.wavelengths) + 1, 0);
    std::vector<compiler::ClosureNode> nodes(1024);
    compiler::ClosureArena arena{nodes.data(), int32_t(nodes.size()), 0, 0};
    compiler::ShadingContext ctx{};
    for (int i = 0; i < hit_.group.count; ++i) ctx.lambdaNm[i] = hit_.group.lambdaNm[i];
    ctx.wavelengthCount = hit_.group.count;
    ctx.arena = &arena;
    module->entry(fn)(args.data(), result.data(), &ctx);
    if (arena.overflow) {
      std::fprintf(stderr, "error: the material has more than %zu closure nodes\n", nodes.size());
      sawError_ = true;
      return false;
    }
    out = compiler::unflatten(result.data(), resultType, options.wavelengths, &arena);
    return true;
  }

  void dumpWithCallees(int fn, std::set<int>& shown) {
    if (!shown.insert(fn).second) return;
    const lang::ir::Program& program = session_->program();
    std::fputs(lang::ir::dump(program, fn).c_str(), stdout);
    std::function<void(const lang::ir::Node*)> visit = [&](const lang::ir::Node* n) {
      if (n->kind == lang::ir::Node::Kind::Call || n->kind == lang::ir::Node::Kind::Fold) dumpWithCallees(n->callee, shown);
      for (const lang::ir::Node* a : n->args) visit(a);
    };
    if (program.functions[size_t(fn)].body) visit(program.functions[size_t(fn)].body);
  }

  void load(const std::string& path, bool remember) {
    if (path.empty()) {
      std::fprintf(stderr, ":load needs a file name\n");
      sawError_ = true;
      return;
    }
    lang::ModuleInfo* module = session_->loadFile(path);
    bool failed = !module || session_->diags().hasErrors();
    printNewDiagnostics();
    if (failed) return;
    session_->importIntoRepl(module);
    if (remember) loaded_.push_back(path);
    std::printf("loaded %s\n", path.c_str());
  }

  static bool parseFloats(const std::string& text, float* out, int maxCount, int& count) {
    std::stringstream in(text);
    std::string item;
    count = 0;
    while (std::getline(in, item, ',')) {
      if (count >= maxCount || !parseFloat(item, out[count])) return false;
      ++count;
    }
    return count > 0;
  }

  void setHit(const std::string& spec) {
    std::stringstream in(spec);
    std::string token;
    HitContext next = hit_;
    while (in >> token) {
      size_t eq = token.find('=');
      std::string key = token.substr(0, eq), value = eq == std::string::npos ? "" : token.substr(eq + 1);
      int count = 0;
      bool ok = false;
      if (key == "uv") ok = parseFloats(value, next.uv, 2, count) && count == 2;
      else if (key == "p") ok = parseFloats(value, next.p, 3, count) && count == 3;
      else if (key == "n") {
        // A normal must have a direction (a zero vector is no normal).
        ok = parseFloats(value, next.n, 3, count) && count == 3 &&
             next.n[0] * next.n[0] + next.n[1] * next.n[1] + next.n[2] * next.n[2] > 0.0f;
      } else if (key == "lambda") {
        ok = parseFloats(value, next.group.lambdaNm, lang::kMaxLanes, count);
        next.group.count = count;
        for (int i = 0; i < count && ok; ++i) ok = next.group.lambdaNm[i] > 0.0f;  // wavelengths in nm are positive
      }
      if (!ok) {
        std::fprintf(stderr, ":hit: cannot read '%s' (see :help)\n", token.c_str());
        sawError_ = true;
        return;
      }
    }
    hit_ = next;
    std::printf("hit: uv=%g,%g p=%g,%g,%g n=%g,%g,%g lambda=", hit_.uv[0], hit_.uv[1], hit_.p[0], hit_.p[1], hit_.p[2],
                hit_.n[0], hit_.n[1], hit_.n[2]);
    for (int i = 0; i < hit_.group.count; ++i) std::printf("%s%g", i ? "," : "", hit_.group.lambdaNm[i]);
    std::printf("\n");
  }

  lang::SessionOptions options_;
  bool interactive_;
  bool interpret_;
  std::unique_ptr<lang::Session> session_;
  HitContext hit_;
  int inputs_ = 0;
  bool sawError_ = false;
  std::vector<std::string> loaded_, history_;
};

int runRepl(const Args& args) {
  if (wantsHelp(args)) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  lang::SessionOptions options;
  bool interpret = false;
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "-I" && i + 1 < args.size()) options.searchPath.push_back(args[++i]);
    else if (args[i] == "--interp") interpret = true;
    else return usageError("repl", "unknown option '" + args[i] + "'");
  }
  bool interactive = isatty(STDIN_FILENO) && isatty(STDOUT_FILENO);
  // History persists across sessions in ~/.tex_history (interactive use only).
  std::string historyFile;
  if (const char* home = std::getenv("HOME"); interactive && home && *home) {
    historyFile = std::string(home) + "/.tex_history";
    read_history(historyFile.c_str());
  }
  if (interactive) std::printf("tex repl — :help for commands, :quit or Ctrl-D to leave\n");
  int status = Repl(options, interactive, interpret).run();
  if (!historyFile.empty()) {
    stifle_history(1000);
    write_history(historyFile.c_str());
  }
  return status;
}

}  // namespace

TEX_COMMAND("repl", "interactive evaluation of .tex expressions and definitions", &runRepl);

}  // namespace tex::cli
