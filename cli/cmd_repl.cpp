// `tex repl`: an interactive evaluator. Line editing and history through libedit when stdin
// is a terminal; plain line reading (no prompts) when it is piped.
#include <editline/readline.h>
#include <fcntl.h>
#include <langinfo.h>
#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <clocale>
#include <csignal>
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
#include "lang/lexer.h"
#include "lang/parser.h"
#include "lang/session.h"

namespace tex::cli {
namespace {

const char* kHelp =
    "usage: tex repl [-I DIR]... [--interp]\n\n"
    "Reads definitions (fn, let, type, import) and expressions; prints each expression's value\n"
    "and type. Input continues on the next line while brackets are open, a block comment is\n"
    "open or an expression is unfinished; an empty line, or a lexical error such as a stray\n"
    "character, ends it. Ctrl-C abandons an unfinished input. Works with piped input:\n"
    "`echo '1 + 2' | tex repl` prints `3 : Int`.\n"
    "Expressions are compiled by the LLVM JIT in quick mode; --interp uses the interpreter.\n"
    "An input, :load or import with an error is undone: it defines and loads nothing, and\n"
    "trying it again reports the same errors.\n\n"
    "Commands:\n"
    "  :type EXPR       show the type of EXPR without evaluating it\n"
    "  :ir EXPR         show the typed core IR of EXPR\n"
    "  :load FILE       load a .tex module; its definitions become available\n"
    "  :reload          reload every loaded file and replay the session's definitions; a file\n"
    "                   or definition that fails stays on the list for the next :reload\n"
    "  :hit [uv=U,V] [p=X,Y,Z] [n=X,Y,Z] [lambda=L1,L2,...]\n"
    "                   set the shading context; `hit` in expressions is that Hit and\n"
    "                   Spectrum values are evaluated at the lambda list (1 to 8 nm values).\n"
    "                   `hit` exists in expressions only, not in definitions: give a\n"
    "                   definition a Hit parameter (fn u(h: Hit) = h.uv.x) and call u(hit)\n"
    "  :help            this text\n"
    "  :quit            leave (also Ctrl-D)\n";

// Ctrl-C while a line is read (interactive only): the handler sets a flag and writes a byte to
// a pipe; the getc function below waits on the terminal and that pipe, so it wakes whichever
// thread the signal went to (commands run on a thread of their own), reports end of input,
// readline returns, and the REPL abandons the unfinished input instead of dying. Outside
// readline, SIGINT keeps its default action, so Ctrl-C still stops a long evaluation.
volatile sig_atomic_t gInterrupted = 0;
int gWake[2] = {-1, -1};  // the self-pipe: read end, write end (both non-blocking)

void onInterrupt(int) {
  int saved = errno;
  gInterrupted = 1;
  char byte = 0;
  if (gWake[1] >= 0 && ::write(gWake[1], &byte, 1) < 0) {
    // full or closed: the flag alone is enough then
  }
  errno = saved;
}

void drainWakePipe() {
  char bytes[64];
  while (gWake[0] >= 0 && ::read(gWake[0], bytes, sizeof bytes) > 0) {
  }
}

int readByte(FILE* in) {
  int fd = fileno(in);
  while (true) {
    if (gInterrupted) return EOF;
    pollfd fds[2] = {{fd, POLLIN, 0}, {gWake[0], POLLIN, 0}};
    int ready = ::poll(fds, gWake[0] >= 0 ? 2 : 1, -1);
    if (ready < 0) {
      if (errno == EINTR) continue;  // a signal: Ctrl-C set the flag, others (resize) retry
      return EOF;
    }
    if (ready > 0 && gWake[0] >= 0 && fds[1].revents) {
      drainWakePipe();
      continue;
    }
    unsigned char c;
    ssize_t n = ::read(fd, &c, 1);
    if (n == 1) return c;
    if (n < 0 && errno == EINTR) continue;
    return EOF;
  }
}

// libedit's getc hook returns characters, not bytes (it decodes nothing itself when the hook is
// set): a UTF-8 sequence is read whole and returned as its code point (U+FFFD if malformed), so
// `é` arrives as one character instead of two Latin-1 ones.
int readChar(FILE* in) {
  const int lead = readByte(in);
  if (lead == EOF || lead < 0x80) return lead;
  const int length = lead >= 0xF0 ? 4 : lead >= 0xE0 ? 3 : lead >= 0xC0 ? 2 : 0;
  if (length == 0 || lead >= 0xF8) return 0xFFFD;  // a stray continuation byte or an invalid lead
  int codePoint = lead & (0x3F >> (length - 1));
  for (int i = 1; i < length; ++i) {
    const int next = readByte(in);
    if (next == EOF) return EOF;
    if ((next & 0xC0) != 0x80) return 0xFFFD;
    codePoint = (codePoint << 6) | (next & 0x3F);
  }
  return codePoint;
}

std::string trim(const std::string& s) {
  size_t b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  size_t e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

struct HitContext {
  float p[3] = {0.5f, 0.5f, 0};
  float n[3] = {0, 0, 1};
  float uv[2] = {0.5f, 0.5f};
  lang::WavelengthGroup group;
};

// Closure nodes one REPL evaluation may build, compiled or interpreted.
constexpr size_t kClosureNodes = 1024;

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
      bool interrupted = false;
      if (!readLine(pending.empty() ? "tex> " : "...> ", line, interrupted)) {
        if (!interrupted) break;
        pending.clear();  // Ctrl-C: drop the unfinished input and start again
        continue;
      }
      if (pending.empty() && trim(line).empty()) continue;
      if (pending.empty() && trim(line)[0] == ':') {  // no expression starts with ':'
        if (!command(line)) break;
        continue;
      }
      pending += pending.empty() ? line : "\n" + line;
      if (!trim(line).empty() && incomplete(pending)) continue;  // an empty line forces evaluation
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

  bool readLine(const char* prompt, std::string& line, bool& interrupted) {
    interrupted = false;
    if (interactive_) {
      struct sigaction handler {}, previous {};
      handler.sa_handler = onInterrupt;
      sigemptyset(&handler.sa_mask);
      handler.sa_flags = 0;  // no SA_RESTART: a blocked read returns EINTR
      drainWakePipe();
      gInterrupted = 0;
      sigaction(SIGINT, &handler, &previous);
      char* raw = readline(prompt);
      sigaction(SIGINT, &previous, nullptr);
      if (gInterrupted) {
        gInterrupted = 0;
        std::free(raw);
        std::printf("\n");
        std::fflush(stdout);
        interrupted = true;
        return false;
      }
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
    // A lexical error (a stray character, invalid UTF-8, a malformed literal) ends the input at
    // once: no further line can repair it. Only an unterminated block comment continues.
    for (const lang::Diagnostic& d : scratch.items())
      if (d.code.compare(0, 3, "E01") == 0 && d.code != "E0103") return false;
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

  // A definition that uses `hit` gets a hint: `hit` is the :hit context of expressions only.
  void explainHitInDefinitions(size_t from) {
    for (size_t i = from; i < session_->diags().size(); ++i) {
      lang::Diagnostic& d = session_->diags().at(i);
      if (d.code != "E0301" || !d.span.file || !d.help.empty()) continue;
      if (d.span.file->text.compare(d.span.begin, d.span.end - d.span.begin, "hit") != 0) continue;
      d.help = "`hit` (the :hit context) exists in REPL expressions only; a definition takes a Hit parameter, "
               "e.g. `fn u(h: Hit) = h.uv.x`, and the expression `u(hit)` passes the context";
    }
  }

  // An input that holds nothing but a lexical error (`@`, or a comment with invalid UTF-8) also
  // gets "expected an expression, found end of file", which only repeats it: drop that. (With
  // any valid token in the input, a syntax error at its end is an error of its own.)
  void dropCascadeAfterLexicalError(size_t from, const std::string& text) {
    lang::Diagnostics& diags = session_->diags();
    lang::Diagnostics scratch;
    lang::SourceFile file("<repl>", text);
    if (lang::lex(file, scratch).size() != 1 || !scratch.hasErrors()) return;  // only End: no valid token
    std::vector<lang::Diagnostic> kept(diags.items().begin(), diags.items().end());
    kept.erase(std::remove_if(kept.begin() + long(from), kept.end(),
                              [&](const lang::Diagnostic& d) { return d.code == "E0201" && d.span.begin >= text.size(); }),
               kept.end());
    diags.clear();
    for (lang::Diagnostic& d : kept) diags.add(std::move(d));
  }

  // Adds one input to the session: a definition (or import) stays, fn is -1; an expression is
  // compiled to IR function fn, which the caller drops again after use. An input with an error
  // is undone at once: it leaves no trace, so later uses of the names it tried to define are
  // unknown names, and a module it failed to import is loaded (and reported) afresh next time.
  // `wantExpression`: a definition is refused (:type, :ir). Returns false after an error.
  bool compile(const std::string& text, int& fn, bool wantExpression) {
    fn = -1;
    lang::Session::ReplMark mark = session_->replMark();
    lang::Expr* expr = nullptr;
    size_t before = session_->diags().size();
    bool ok = session_->addReplInput(text, expr, ++inputs_);
    if (!ok && !expr) {
      explainHitInDefinitions(before);
      dropCascadeAfterLexicalError(before, text);
    }
    if (ok && expr) {
      fn = session_->compileExpression(session_->replModule(), expr, {{"hit", lang::TypeTable::global().hit()}});
      ok = fn >= 0;
    }
    bool refused = ok && !expr && wantExpression;
    printNewDiagnostics();
    if (refused) {
      std::fprintf(stderr, "error: this command takes an expression, not a definition (nothing was defined)\n");
      sawError_ = true;
      ok = false;
    }
    if (!ok) {
      fn = -1;
      session_->replRollback(mark);
    }
    return ok;
  }

  void input(const std::string& text) {
    // Expressions are compiled, evaluated and dropped again; definitions stay.
    lang::Session::Mark mark = session_->mark();
    int fn = -1;
    if (!compile(text, fn, false)) return;
    if (fn < 0) {
      history_.push_back(text);  // a definition: :reload replays it
      return;
    }
    const lang::ir::Function& f = session_->program().functions[size_t(fn)];
    lang::Value v;
    if (run(fn, v))
      std::printf("%s : %s\n", lang::formatValue(v, f.resultType, hit_.group).c_str(), lang::typeName(f.resultType).c_str());
    std::fflush(stdout);
    session_->rollback(mark);
  }

  bool command(const std::string& line) {
    std::string text = trim(line);
    size_t space = text.find_first_of(" \t");
    std::string name = text.substr(0, space);
    std::string rest = space == std::string::npos ? "" : trim(text.substr(space));
    if (name == ":quit" || name == ":q" || name == ":exit") return false;
    if (name == ":help" || name == ":h") {
      std::fputs(kHelp, stdout);
    } else if (name == ":type" || name == ":t") {
      lang::Session::Mark mark = session_->mark();
      int fn = -1;
      if (compile(rest, fn, true)) {
        std::printf("%s\n", lang::typeName(session_->program().functions[size_t(fn)].resultType).c_str());
        session_->rollback(mark);
      }
    } else if (name == ":ir") {
      lang::Session::Mark mark = session_->mark();
      int fn = -1;
      if (compile(rest, fn, true)) {
        std::set<int> shown;
        dumpWithCallees(fn, shown);
        session_->rollback(mark);
      }
    } else if (name == ":load" || name == ":l") {
      if (load(rest) && std::find(loaded_.begin(), loaded_.end(), rest) == loaded_.end()) loaded_.push_back(rest);
    } else if (name == ":reload" || name == ":r") {
      // Everything is loaded and replayed afresh. A file or definition that fails now stays
      // on the lists, so that fixing it and reloading again brings it back.
      reset();
      size_t failedFiles = 0, failedDefinitions = 0;
      for (const std::string& f : loaded_) failedFiles += !load(f);
      for (const std::string& d : history_) {
        int fn = -1;
        failedDefinitions += !compile(d, fn, false);
      }
      if (failedFiles + failedDefinitions == 0) {
        std::printf("reloaded %zu file(s) and %zu definition(s)\n", loaded_.size(), history_.size());
      } else {
        std::fprintf(stderr,
                     "reload incomplete: %zu of %zu file(s) and %zu of %zu definition(s) failed; they stay listed "
                     "for the next :reload\n",
                     failedFiles, loaded_.size(), failedDefinitions, history_.size());
        sawError_ = true;
      }
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
    if (interpret_) return interpret(fn, out);
    compiler::CompileOptions options;
    options.opt = compiler::OptLevel::Quick;
    options.useCache = false;  // REPL lines are one-offs: keep them out of the cache
    options.wavelengths = hit_.group.count;
    if (options.wavelengths != 1 && options.wavelengths != 4 && options.wavelengths != 8)
      return interpret(fn, out);  // the JIT has 1, 4 or 8 lanes
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
    std::vector<compiler::ClosureNode> nodes(kClosureNodes);
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

  // The interpreter, with the closure-node limit the JIT's arena has here (the same error).
  bool interpret(int fn, lang::Value& out) {
    lang::ClosureBudget budget{kClosureNodes};
    out = lang::evaluate(session_->program(), fn, {hitValue()}, hit_.group, &budget);
    if (budget.overflowed) {
      std::fprintf(stderr, "error: the material has more than %zu closure nodes\n", kClosureNodes);
      sawError_ = true;
      return false;
    }
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

  // Loads a file into the REPL. A file with an error is undone (nothing of it, nor of the
  // modules it imported, stays loaded), so loading it again reports the same errors.
  bool load(const std::string& path) {
    if (path.empty()) {
      std::fprintf(stderr, ":load needs a file name\n");
      sawError_ = true;
      return false;
    }
    lang::Session::ReplMark mark = session_->replMark();
    lang::ModuleInfo* module = session_->loadFile(path);
    bool failed = !module || session_->diags().hasErrors();
    printNewDiagnostics();
    if (failed) {
      session_->replRollback(mark);
      return false;
    }
    session_->importIntoRepl(module);
    std::printf("loaded %s\n", path.c_str());
    return true;
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
  // Set before libedit initialises (read_history or the first readline do that).
  if (interactive) {
    // libedit decodes the typed bytes with the locale's character set, and in the C locale it
    // dropped every non-ASCII character (`:load é.tex` read `:load .tex`). Source text is UTF-8
    // (docs/language.md): use the environment's locale if it is UTF-8, else C.UTF-8.
    const char* locale = std::setlocale(LC_CTYPE, "");
    if (!locale || std::string(nl_langinfo(CODESET)) != "UTF-8") std::setlocale(LC_CTYPE, "C.UTF-8");
    rl_getc_function = readChar;
    if (pipe2(gWake, O_NONBLOCK | O_CLOEXEC) != 0) gWake[0] = gWake[1] = -1;
  }
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
