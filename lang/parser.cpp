#include "lang/parser.h"

#include "lang/lexer.h"

#include <algorithm>
#include <utility>
#include <vector>

namespace tex::lang {

const char* binaryOpText(BinaryOp op) {
  static const char* names[] = {"||", "&&", "==", "!=", "<", "<=", ">", ">=", "|", "^",
                                "&",  "<<", ">>", "+",  "-", "*",  "/", "%"};
  return names[int(op)];
}
const char* unaryOpText(UnaryOp op) {
  static const char* names[] = {"-", "!", "~"};
  return names[int(op)];
}

namespace {

struct ParseAbort {};  // unwinds to the enclosing item after an error was reported

struct BinaryInfo {
  int precedence;
  BinaryOp op;
};

bool binaryInfo(Tok t, BinaryInfo& info) {
  switch (t) {
    case Tok::OrOr: info = {1, BinaryOp::Or}; return true;
    case Tok::AndAnd: info = {2, BinaryOp::And}; return true;
    case Tok::EqEq: info = {3, BinaryOp::Eq}; return true;
    case Tok::NotEq: info = {3, BinaryOp::Ne}; return true;
    case Tok::Lt: info = {4, BinaryOp::Lt}; return true;
    case Tok::Le: info = {4, BinaryOp::Le}; return true;
    case Tok::Gt: info = {4, BinaryOp::Gt}; return true;
    case Tok::Ge: info = {4, BinaryOp::Ge}; return true;
    case Tok::Pipe: info = {5, BinaryOp::BitOr}; return true;
    case Tok::Caret: info = {6, BinaryOp::BitXor}; return true;
    case Tok::Amp: info = {7, BinaryOp::BitAnd}; return true;
    case Tok::Shl: info = {8, BinaryOp::Shl}; return true;
    case Tok::Shr: info = {8, BinaryOp::Shr}; return true;
    case Tok::Plus: info = {9, BinaryOp::Add}; return true;
    case Tok::Minus: info = {9, BinaryOp::Sub}; return true;
    case Tok::Star: info = {10, BinaryOp::Mul}; return true;
    case Tok::Slash: info = {10, BinaryOp::Div}; return true;
    case Tok::Percent: info = {10, BinaryOp::Rem}; return true;
    default: return false;
  }
}

class Parser {
 public:
  Parser(std::shared_ptr<SourceFile> file, Diagnostics& diags)
      : file_(file), diags_(diags), module_(std::make_unique<Module>()) {
    module_->file = file;
    tokens_ = lex(*file, diags);
  }

  std::unique_ptr<Module> parseModule() {
    while (!at(Tok::End)) parseTopLevel();
    return std::move(module_);
  }

  std::unique_ptr<Module> parseRepl(Expr*& expr) {
    expr = nullptr;
    if (at(Tok::KwImport) || at(Tok::KwFn) || at(Tok::KwExport) || at(Tok::KwType) ||
        (at(Tok::KwLet) && !letIsExpression())) {
      while (!at(Tok::End)) parseTopLevel();
    } else {
      try {
        expr = parseExpr();
        if (!at(Tok::End)) errorHere("expected end of input");
        checkTreeDepth(expr);
      } catch (const ParseAbort&) {
        expr = nullptr;
      }
    }
    return std::move(module_);
  }

 private:
  // ---- token helpers -------------------------------------------------------------------
  const Token& cur() const { return tokens_[pos_]; }
  const Token& peekTok(size_t n) const { return tokens_[std::min(pos_ + n, tokens_.size() - 1)]; }
  bool at(Tok k) const { return cur().kind == k; }
  Span spanOf(const Token& t) const { return Span{file_.get(), t.begin, t.end}; }
  Span join(Span a, Span b) const { return Span{file_.get(), a.begin, std::max(a.end, b.end)}; }
  Span prevEnd() const {
    uint32_t e = pos_ > 0 ? tokens_[pos_ - 1].end : 0;
    return Span{file_.get(), e, e};
  }
  const Token& advance() {
    const Token& t = tokens_[pos_];
    if (pos_ + 1 < tokens_.size()) ++pos_;
    return t;
  }
  bool accept(Tok k) {
    if (!at(k)) return false;
    advance();
    return true;
  }

  std::string tokenDescription(const Token& t) const {
    if (t.kind == Tok::Ident || t.kind == Tok::Int || t.kind == Tok::Float)
      return std::string(tokenName(t.kind)) + " '" +
             std::string(file_->text.substr(t.begin, std::min<uint32_t>(t.end - t.begin, 40))) + "'";
    return tokenName(t.kind);
  }

  [[noreturn]] void errorHere(const std::string& expected, std::string help = {}) {
    if (at(Tok::End) && !openers_.empty()) {
      auto [span, kind] = openers_.back();
      diags_.error("E0203", span, std::string("unclosed ") + tokenName(kind),
                   std::string("the file ends before this ") + tokenName(kind) + " is closed");
    } else {
      diags_.error("E0201", spanOf(cur()), expected + ", found " + tokenDescription(cur()),
                   std::move(help));
    }
    throw ParseAbort{};
  }

  const Token& expect(Tok k, const char* context = nullptr) {
    if (!at(k)) {
      std::string message = std::string("expected ") + tokenName(k);
      if (context) message += std::string(" ") + context;
      errorHere(message);
    }
    return advance();
  }

  std::string expectIdent(Span& span, const char* what) {
    if (!at(Tok::Ident)) errorHere(std::string("expected ") + what);
    const Token& t = advance();
    span = spanOf(t);
    return std::string(file_->text.substr(t.begin, t.end - t.begin));
  }

  // Tracks open delimiters so an error at end of file can point at the unclosed one.
  struct Opener {
    Parser& p;
    Opener(Parser& parser, Tok kind) : p(parser) { p.openers_.push_back({p.spanOf(p.cur()), kind}); }
    ~Opener() { p.openers_.pop_back(); }
  };

  // Bounds recursion: every nested expression level passes through here.
  struct DepthGuard {
    Parser& p;
    explicit DepthGuard(Parser& parser) : p(parser) {
      if (++p.depth_ > kMaxNestingDepth) {
        p.depth_ = 0;  // the abort unwinds every level; reset so the next item starts clean
        p.diags_.error("E0202", p.spanOf(p.cur()),
                       "expression nested too deeply (more than " + std::to_string(kMaxNestingDepth) + " levels)",
                       "split it into smaller definitions with let bindings or functions");
        p.tooDeep_ = true;
        throw ParseAbort{};
      }
    }
    ~DepthGuard() {
      if (p.depth_ > 0) --p.depth_;
    }
  };

  // ---- items ---------------------------------------------------------------------------
  bool letIsExpression() const {
    // `let x = e in body` at REPL level is an expression; `let x = e` alone defines.
    int depth = 0;
    for (size_t i = pos_; i < tokens_.size(); ++i) {
      Tok k = tokens_[i].kind;
      if (k == Tok::LParen || k == Tok::LBrace) ++depth;
      if (k == Tok::RParen || k == Tok::RBrace) --depth;
      if (k == Tok::KwIn && depth == 0) return true;
    }
    return false;
  }

  void parseTopLevel() {
    size_t start = pos_;
    try {
      if (at(Tok::KwImport)) {
        parseImport();
        return;
      }
      bool exported = accept(Tok::KwExport);
      if (at(Tok::KwFn)) parseFunction(exported);
      else if (at(Tok::KwLet)) parseLetItem(exported);
      else if (at(Tok::KwType)) parseTypeItem(exported);
      else errorHere("expected 'fn', 'let', 'type' or 'import' at the top level");
    } catch (const ParseAbort&) {
      openers_.clear();
      depth_ = 0;
      synchronize(start);
    }
  }

  // Skips to the next token that can start an item: fn/export/import/type anywhere, or a
  // `let` in column 1. Always makes progress.
  void synchronize(size_t start) {
    if (pos_ == start) advance();
    while (!at(Tok::End)) {
      Tok k = cur().kind;
      if (k == Tok::KwFn || k == Tok::KwExport || k == Tok::KwImport || k == Tok::KwType) return;
      if (k == Tok::KwLet && file_->lineCol(cur().begin).col == 1) return;
      advance();
    }
  }

  void parseImport() {
    Import imp;
    Span kw = spanOf(advance());
    Span segSpan;
    imp.path.push_back(expectIdent(segSpan, "a module name after 'import'"));
    imp.pathSpan = segSpan;
    while (at(Tok::Dot)) {
      advance();
      if (at(Tok::LBrace)) {
        Opener open(*this, Tok::LBrace);
        advance();
        imp.hasItemList = true;
        while (!at(Tok::RBrace)) {
          Import::Item item;
          item.name = expectIdent(item.span, "a name to import");
          if (accept(Tok::KwAs)) {
            Span aliasSpan;
            item.alias = expectIdent(aliasSpan, "a name after 'as'");
          } else {
            item.alias = item.name;
          }
          imp.items.push_back(item);
          if (!accept(Tok::Comma)) break;
        }
        expect(Tok::RBrace, "to close the import list");
        break;
      }
      imp.path.push_back(expectIdent(segSpan, "a module name after '.'"));
      imp.pathSpan = join(imp.pathSpan, segSpan);
    }
    if (!imp.hasItemList) {
      imp.alias = imp.path.back();
      imp.aliasSpan = segSpan;
      if (accept(Tok::KwAs)) imp.alias = expectIdent(imp.aliasSpan, "a name after 'as'");
    }
    imp.span = join(kw, prevEnd());
    module_->imports.push_back(std::move(imp));
  }

  // Starts an item at its keyword: kind, export flag and name.
  Item beginItem(Item::Kind kind, bool exported, const char* nameWhat, Span& keyword) {
    Item item;
    item.kind = kind;
    item.exported = exported;
    keyword = spanOf(advance());
    item.name = expectIdent(item.nameSpan, nameWhat);
    return item;
  }

  // The depth of a syntax tree (a leaf is 1), walked with an explicit stack.
  static int treeDepth(const Expr* root) {
    int deepest = 0;
    std::vector<std::pair<const Expr*, int>> stack;
    if (root) stack.push_back({root, 1});
    while (!stack.empty()) {
      auto [e, depth] = stack.back();
      stack.pop_back();
      deepest = std::max(deepest, depth);
      for (const Expr* child : {e->a, e->b, e->c})
        if (child) stack.push_back({child, depth + 1});
      for (const Argument& arg : e->args)
        if (arg.value) stack.push_back({arg.value, depth + 1});
      for (const FieldInit& field : e->fields)
        if (field.value) stack.push_back({field.value, depth + 1});
    }
    return deepest;
  }

  // E0202 for a tree deeper than kMaxTreeDepth: each limit of the grammar holds (256 levels,
  // 4096-long chains), but chains nested in chains multiply (256 x 4096 levels overflowed the
  // interpreter's and the compiler's stacks).
  void checkTreeDepth(const Expr* e) {
    if (!e) return;
    const int depth = treeDepth(e);
    if (depth <= kMaxTreeDepth) return;
    diags_.error("E0202", Span{file_.get(), e->span.begin, e->span.begin},
                 "expression nested too deeply: its tree is " + std::to_string(depth) + " levels deep (at most " +
                     std::to_string(kMaxTreeDepth) + ", each operator of a chain counting as a level)",
                 "split it into smaller definitions with let bindings or functions");
    throw ParseAbort{};
  }

  void finishItem(Item& item, Span keyword) {
    checkTreeDepth(item.body);
    for (const Param& param : item.params) checkTreeDepth(param.defaultValue);
    item.span = join(keyword, prevEnd());
    module_->items.push_back(std::move(item));
  }

  void parseFunction(bool exported) {
    Span kw;
    Item item = beginItem(Item::Kind::Function, exported, "a function name after 'fn'", kw);
    {
      Opener open(*this, Tok::LParen);
      expect(Tok::LParen, "to start the parameter list");
      bool sawDefault = false;
      while (!at(Tok::RParen)) {
        Param p;
        p.name = expectIdent(p.span, "a parameter name");
        for (const Param& q : item.params)
          if (q.name == p.name)
            diags_.error("E0204", p.span, "duplicate parameter '" + p.name + "'");
        if (accept(Tok::Colon)) p.type = parseType();
        if (accept(Tok::Assign)) {
          p.defaultValue = parseExpr();
          sawDefault = true;
        } else if (sawDefault) {
          diags_.error("E0207", p.span, "parameter '" + p.name + "' has no default but follows one that has",
                       "give it a default value or move it before the parameters with defaults");
        }
        item.params.push_back(std::move(p));
        if (!accept(Tok::Comma)) break;
      }
      expect(Tok::RParen, "to close the parameter list");
    }
    if (accept(Tok::Arrow)) item.resultType = parseType();
    if (accept(Tok::Assign)) {
      item.body = parseExpr();
    } else if (at(Tok::LBrace)) {
      item.body = parseBraced();
    } else {
      errorHere("expected '=' or '{' to start the function body");
    }
    finishItem(item, kw);
  }

  void parseLetItem(bool exported) {
    Span kw;
    Item item = beginItem(Item::Kind::Let, exported, "a name after 'let'", kw);
    if (accept(Tok::Colon)) item.resultType = parseType();
    expect(Tok::Assign, "after the name");
    item.body = parseExpr();
    if (at(Tok::KwIn)) errorHere("expected a top-level definition", "a top-level 'let' defines a constant; 'let ... in' is an expression and belongs inside a function");
    finishItem(item, kw);
  }

  void parseTypeItem(bool exported) {
    Span kw;
    Item item = beginItem(Item::Kind::Type, exported, "a type name after 'type'", kw);
    expect(Tok::Assign, "after the type name");
    item.resultType = parseType();
    finishItem(item, kw);
  }

  // ---- types ---------------------------------------------------------------------------
  TypeExpr* parseType() {
    DepthGuard guard(*this);
    Span start = spanOf(cur());
    if (at(Tok::Ident)) {
      TypeExpr* t = module_->newType(TypeExpr::Kind::Name, start);
      Span s;
      t->name = expectIdent(s, "a type");
      return t;
    }
    if (at(Tok::LBrace)) {
      Opener open(*this, Tok::LBrace);
      advance();
      TypeExpr* t = module_->newType(TypeExpr::Kind::Record, start);
      while (!at(Tok::RBrace)) {
        Span fs;
        std::string name = expectIdent(fs, "a field name");
        for (auto& f : t->fields)
          if (f.first == name) diags_.error("E0205", fs, "duplicate field '" + name + "'");
        expect(Tok::Colon, "after the field name");
        t->fields.push_back({name, parseType()});
        t->fieldSpans.push_back(fs);
        if (!accept(Tok::Comma)) break;
      }
      expect(Tok::RBrace, "to close the record type");
      t->span = join(start, prevEnd());
      return t;
    }
    if (at(Tok::LParen)) {
      TypeExpr* t = module_->newType(TypeExpr::Kind::Function, start);
      {
        Opener open(*this, Tok::LParen);
        advance();
        while (!at(Tok::RParen)) {
          t->params.push_back(parseType());
          if (!accept(Tok::Comma)) break;
        }
        expect(Tok::RParen, "to close the parameter types");
      }
      expect(Tok::Arrow, "in a function type");
      t->result = parseType();
      t->span = join(start, prevEnd());
      return t;
    }
    errorHere("expected a type");
  }

  // ---- expressions ---------------------------------------------------------------------
  Expr* parseExpr() {
    if (at(Tok::KwLet)) return parseLetExpr();
    if (at(Tok::Pipe) || at(Tok::OrOr)) return parseLambda();
    return parseBinary(1);
  }

  Expr* parseLetExpr() {
    DepthGuard guard(*this);
    Span kw = spanOf(advance());
    Expr* e = module_->newExpr(Expr::Kind::Let, kw);
    e->name = expectIdent(e->nameSpan, "a name after 'let'");
    if (accept(Tok::Colon)) e->annotation = parseType();
    expect(Tok::Assign, "after the name");
    e->a = parseExpr();
    expect(Tok::KwIn, "after the value of 'let'");
    e->b = parseExpr();
    e->span = join(kw, prevEnd());
    return e;
  }

  Expr* parseLambda() {
    DepthGuard guard(*this);
    Span start = spanOf(cur());
    Expr* e = module_->newExpr(Expr::Kind::Lambda, start);
    if (!accept(Tok::OrOr)) {
      Opener open(*this, Tok::Pipe);
      advance();
      while (!at(Tok::Pipe)) {
        LambdaParam p;
        p.name = expectIdent(p.span, "a lambda parameter name");
        for (const LambdaParam& q : e->params)
          if (q.name == p.name) diags_.error("E0204", p.span, "duplicate parameter '" + p.name + "'");
        if (accept(Tok::Colon)) p.type = parseType();
        e->params.push_back(std::move(p));
        if (!accept(Tok::Comma)) break;
      }
      expect(Tok::Pipe, "to close the lambda's parameters");
    }
    e->a = parseExpr();
    e->span = join(start, prevEnd());
    return e;
  }

  Expr* parseBinary(int minPrecedence) {
    Expr* lhs = parseUnary();
    int chain = 0;
    BinaryInfo info;
    while (binaryInfo(cur().kind, info) && info.precedence >= minPrecedence) {
      Span opSpan = spanOf(advance());
      Expr* rhs = parseBinaryRhs(info.precedence + 1);
      Expr* e = module_->newExpr(Expr::Kind::Binary, join(lhs->span, rhs->span));
      e->binaryOp = info.op;
      e->opSpan = opSpan;
      e->a = lhs;
      e->b = rhs;
      lhs = e;
      // A left-deep chain deepens the tree by one per operator: count it like nesting.
      if (++chain > kMaxChainLength) {
        diags_.error("E0202", opSpan,
                     "operator chain too long (more than " + std::to_string(kMaxChainLength) + " operators)",
                     "split the long operator chain with let bindings");
        throw ParseAbort{};
      }
    }
    return lhs;
  }

  Expr* parseBinaryRhs(int minPrecedence) {
    // A lambda or let may close an operator chain: `x + let y = 1 in y` is allowed.
    if (at(Tok::KwLet)) return parseLetExpr();
    if (at(Tok::Pipe) || at(Tok::OrOr)) return parseLambda();
    return parseBinary(minPrecedence);
  }

  Expr* parseUnary() {
    if (at(Tok::Minus) || at(Tok::Bang) || at(Tok::Tilde)) {
      DepthGuard guard(*this);
      Span opSpan = spanOf(cur());
      Tok k = advance().kind;
      if (k == Tok::Minus && at(Tok::Int) && cur().intValue == 2147483648LL) {
        Expr* lit = module_->newExpr(Expr::Kind::IntLit, join(opSpan, spanOf(cur())));
        lit->intValue = -2147483648LL;
        advance();
        return parsePostfix(lit);
      }
      Expr* operand = parseUnary();
      Expr* e = module_->newExpr(Expr::Kind::Unary, join(opSpan, operand->span));
      e->unaryOp = k == Tok::Minus ? UnaryOp::Neg : k == Tok::Bang ? UnaryOp::Not : UnaryOp::BitNot;
      e->opSpan = opSpan;
      e->a = operand;
      return e;
    }
    return parsePostfix(parsePrimary());
  }

  Expr* parsePostfix(Expr* e) {
    int chain = 0;
    while (true) {
      if (at(Tok::LParen)) {
        DepthGuard guard(*this);
        Expr* call = module_->newExpr(Expr::Kind::Call, e->span);
        call->a = e;
        {
          Opener open(*this, Tok::LParen);
          advance();
          bool sawNamed = false;
          while (!at(Tok::RParen)) {
            Argument arg;
            if (at(Tok::Ident) && peekTok(1).kind == Tok::Colon) {
              arg.name = expectIdent(arg.nameSpan, "an argument name");
              advance();
              sawNamed = true;
            } else if (sawNamed) {
              diags_.error("E0206", spanOf(cur()), "positional argument after a named argument",
                           "pass positional arguments first, then named ones");
            }
            arg.value = parseExpr();
            call->args.push_back(arg);
            if (!accept(Tok::Comma)) break;
          }
          call->closeSpan = spanOf(cur());
          expect(Tok::RParen, "to close the argument list");
        }
        call->span = join(e->span, prevEnd());
        e = call;
      } else if (at(Tok::Dot)) {
        advance();
        Expr* f = module_->newExpr(Expr::Kind::Field, e->span);
        f->a = e;
        f->name = expectIdent(f->nameSpan, "a field name after '.'");
        f->span = join(e->span, f->nameSpan);
        e = f;
      } else {
        return e;
      }
      if (++chain > kMaxChainLength) {
        diags_.error("E0202", e->span, "expression nested too deeply",
                     "split the long chain of calls with let bindings");
        throw ParseAbort{};
      }
    }
  }

  Expr* parsePrimary() {
    const Token& t = cur();
    Span s = spanOf(t);
    switch (t.kind) {
      case Tok::Int: {
        advance();
        if (t.intValue > 2147483647LL) {
          diags_.error("E0105", s, "integer literal out of range",
                       "2147483648 is only allowed after unary minus");
        }
        Expr* e = module_->newExpr(Expr::Kind::IntLit, s);
        e->intValue = t.intValue;
        return e;
      }
      case Tok::Float: {
        advance();
        Expr* e = module_->newExpr(Expr::Kind::FloatLit, s);
        e->floatValue = t.floatValue;
        return e;
      }
      case Tok::String: {
        advance();
        Expr* e = module_->newExpr(Expr::Kind::StringLit, s);
        e->intValue = t.intValue;  // 1: malformed, already reported
        e->name = s.end - s.begin >= 2 ? std::string(s.file->text.substr(s.begin + 1, s.end - s.begin - 2)) : std::string();
        return e;
      }
      case Tok::KwTrue:
      case Tok::KwFalse: {
        advance();
        Expr* e = module_->newExpr(Expr::Kind::BoolLit, s);
        e->boolValue = t.kind == Tok::KwTrue;
        return e;
      }
      case Tok::Ident: {
        Expr* e = module_->newExpr(Expr::Kind::Name, s);
        e->name = expectIdent(e->nameSpan, "a name");
        return e;
      }
      case Tok::LParen: {
        DepthGuard guard(*this);
        Opener open(*this, Tok::LParen);
        advance();
        bool saved = noRecordLiteral_;
        noRecordLiteral_ = false;
        Expr* inner = parseExpr();
        noRecordLiteral_ = saved;
        expect(Tok::RParen, "to close the parenthesis");
        return inner;
      }
      case Tok::LBrace: return parseBraced();
      case Tok::KwIf: return parseIf();
      case Tok::KwLet: return parseLetExpr();
      case Tok::Pipe:
      case Tok::OrOr: return parseLambda();
      default: errorHere("expected an expression");
    }
  }

  Expr* parseIf() {
    DepthGuard guard(*this);
    Span kw = spanOf(advance());
    Expr* e = module_->newExpr(Expr::Kind::If, kw);
    bool saved = noRecordLiteral_;
    noRecordLiteral_ = true;  // `if x {` : the brace opens the branch (as in Rust)
    e->a = parseExpr();
    noRecordLiteral_ = saved;
    if (!at(Tok::LBrace)) errorHere("expected '{' after the condition of 'if'");
    e->b = parseBraced();
    if (!at(Tok::KwElse))
      errorHere("expected 'else'", "'if' is an expression: it needs an 'else' branch");
    advance();
    if (at(Tok::KwIf)) e->c = parseIf();
    else if (at(Tok::LBrace)) e->c = parseBraced();
    else errorHere("expected '{' or 'if' after 'else'");
    e->span = join(kw, prevEnd());
    return e;
  }

  // `{` starts a record literal, a record update or a block (docs/language.md section 2).
  Expr* parseBraced() {
    DepthGuard guard(*this);
    Span open = spanOf(cur());
    Opener opener(*this, Tok::LBrace);
    advance();
    bool recordAllowed = !noRecordLiteral_;
    struct Restore {
      bool& flag;
      bool value;
      ~Restore() { flag = value; }
    } restore{noRecordLiteral_, noRecordLiteral_};
    noRecordLiteral_ = false;
    if (at(Tok::RBrace)) errorHere("expected an expression or a record field", "a block needs a final expression; a record needs at least one field");
    if (recordAllowed && at(Tok::Ident) && peekTok(1).kind == Tok::Colon) {
      Expr* e = module_->newExpr(Expr::Kind::Record, open);
      parseFieldInits(e);
      expect(Tok::RBrace, "to close the record");
      e->span = join(open, prevEnd());
      return e;
    }
    if (at(Tok::KwLet) && !letStatementIsExpression()) return parseBlockStatements(open);
    Expr* first = parseExpr();
    if (accept(Tok::KwWith)) {
      Expr* e = module_->newExpr(Expr::Kind::RecordUpdate, open);
      e->a = first;
      if (at(Tok::RBrace)) errorHere("expected a field name after 'with'");
      parseFieldInits(e);
      expect(Tok::RBrace, "to close the record update");
      e->span = join(open, prevEnd());
      return e;
    }
    expect(Tok::RBrace, "to close the block");
    return first;
  }

  // In a block, `let x = e;` is a statement; `let x = e in b` is an expression.
  bool letStatementIsExpression() const {
    int depth = 0;
    for (size_t i = pos_; i < tokens_.size(); ++i) {
      Tok k = tokens_[i].kind;
      if (k == Tok::LParen || k == Tok::LBrace) ++depth;
      else if (k == Tok::RParen || k == Tok::RBrace) {
        if (--depth < 0) return false;
      } else if (depth == 0 && k == Tok::Semi) return false;
      else if (depth == 0 && k == Tok::KwIn) return true;
    }
    return false;
  }

  Expr* parseBlockStatements(Span open) {
    // Desugars `{ let a = 1; let b = 2; e }` into nested Let expressions.
    std::vector<Expr*> lets;
    while (at(Tok::KwLet) && !letStatementIsExpression()) {
      Span kw = spanOf(advance());
      Expr* let = module_->newExpr(Expr::Kind::Let, kw);
      let->name = expectIdent(let->nameSpan, "a name after 'let'");
      if (accept(Tok::Colon)) let->annotation = parseType();
      expect(Tok::Assign, "after the name");
      let->a = parseExpr();
      expect(Tok::Semi, "after the 'let' statement");
      let->span = join(kw, prevEnd());
      lets.push_back(let);
      if (int(lets.size()) > kMaxChainLength) {
        diags_.error("E0202", kw, "block nested too deeply (too many 'let' statements)",
                     "split the block into functions");
        throw ParseAbort{};
      }
    }
    Expr* body = parseExpr();
    expect(Tok::RBrace, "to close the block");
    for (auto it = lets.rbegin(); it != lets.rend(); ++it) {
      (*it)->b = body;
      (*it)->span = join((*it)->span, body->span);
      body = *it;
    }
    (void)open;
    return body;
  }

  void parseFieldInits(Expr* e) {
    while (!at(Tok::RBrace)) {
      FieldInit f;
      f.name = expectIdent(f.nameSpan, "a field name");
      for (const FieldInit& g : e->fields)
        if (g.name == f.name) diags_.error("E0205", f.nameSpan, "duplicate field '" + f.name + "'");
      expect(Tok::Colon, "after the field name");
      f.value = parseExpr();
      e->fields.push_back(f);
      if (!accept(Tok::Comma)) break;
    }
  }

  std::shared_ptr<SourceFile> file_;
  Diagnostics& diags_;
  std::unique_ptr<Module> module_;
  std::vector<Token> tokens_;
  size_t pos_ = 0;
  int depth_ = 0;
  bool tooDeep_ = false;
  bool noRecordLiteral_ = false;  // inside an `if` condition, outside brackets
  std::vector<std::pair<Span, Tok>> openers_;
};

}  // namespace

std::unique_ptr<Module> parseModule(std::shared_ptr<SourceFile> file, Diagnostics& diags) {
  return Parser(file, diags).parseModule();
}

std::unique_ptr<Module> parseReplInput(std::shared_ptr<SourceFile> file, Diagnostics& diags, Expr*& expr) {
  return Parser(file, diags).parseRepl(expr);
}

}  // namespace tex::lang
