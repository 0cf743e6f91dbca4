// The syntax tree. Every node carries its source span. Nodes live in the module's arena
// (no recursive destructors, so hostile inputs cannot overflow the stack on teardown).
#pragma once
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "lang/source.h"

namespace tex::lang {

struct TypeExpr {
  enum class Kind { Name, Record, Function } kind = Kind::Name;
  Span span;
  std::string name;                                       // Name
  std::vector<std::pair<std::string, TypeExpr*>> fields;  // Record
  std::vector<Span> fieldSpans;                           // Record
  std::vector<TypeExpr*> params;                          // Function
  TypeExpr* result = nullptr;                             // Function
};

enum class UnaryOp { Neg, Not, BitNot };
enum class BinaryOp {
  Or, And, Eq, Ne, Lt, Le, Gt, Ge, BitOr, BitXor, BitAnd, Shl, Shr, Add, Sub, Mul, Div, Rem
};
const char* binaryOpText(BinaryOp op);
const char* unaryOpText(UnaryOp op);

struct Expr;

struct Argument {
  std::string name;  // empty for positional
  Span nameSpan;
  Expr* value = nullptr;
};

struct LambdaParam {
  std::string name;
  Span span;
  TypeExpr* type = nullptr;  // optional
};

struct FieldInit {
  std::string name;
  Span nameSpan;
  Expr* value = nullptr;
};

struct Expr {
  enum class Kind {
    IntLit, FloatLit, BoolLit, StringLit, Name, Unary, Binary, Call, Field, Let, If, Lambda, Record,
    RecordUpdate
  } kind;
  Span span;
  // literals (StringLit: intValue 1 marks a malformed literal the lexer reported)
  int64_t intValue = 0;
  float floatValue = 0;
  bool boolValue = false;
  // Name / Field / Let: the identifier; StringLit: the text between the quotes
  std::string name;
  Span nameSpan;
  // operators
  UnaryOp unaryOp = UnaryOp::Neg;
  BinaryOp binaryOp = BinaryOp::Add;
  Span opSpan;
  // children: Unary {a}; Binary {a, b}; Call {callee=a}; Field {a}; Let {value=a, body=b};
  // If {cond=a, then=b, else=c}; Lambda {body=a}; RecordUpdate {base=a}
  Expr* a = nullptr;
  Expr* b = nullptr;
  Expr* c = nullptr;
  TypeExpr* annotation = nullptr;  // Let
  std::vector<Argument> args;      // Call
  std::vector<LambdaParam> params; // Lambda
  std::vector<FieldInit> fields;   // Record, RecordUpdate
  Span closeSpan;                  // Call: the ')' (for arity errors)
};

struct Param {
  std::string name;
  Span span;
  TypeExpr* type = nullptr;     // optional unless exported
  Expr* defaultValue = nullptr; // optional
};

struct Import {
  Span span;
  std::vector<std::string> path;  // ["std", "noise"]
  Span pathSpan;                  // from the first segment to the last
  struct Item {
    std::string name, alias;
    Span span;
  };
  bool hasItemList = false;
  std::vector<Item> items;  // import a.b.{x, y as z}
  std::string alias;        // import a.b as m (or the last segment)
  Span aliasSpan;
};

struct Item {
  enum class Kind { Function, Let, Type } kind = Kind::Function;
  bool exported = false;
  std::string name;
  Span nameSpan;
  Span span;
  std::vector<Param> params;      // Function
  TypeExpr* resultType = nullptr; // Function (optional), Let annotation, Type definition
  Expr* body = nullptr;           // Function body, Let value
};

// One parsed file. Owns every node of its tree.
struct Module {
  std::shared_ptr<SourceFile> file;
  std::vector<Import> imports;
  std::vector<Item> items;

  Expr* newExpr(Expr::Kind kind, Span span) {
    Expr& e = exprs_.emplace_back();
    e.kind = kind;
    e.span = span;
    return &e;
  }
  TypeExpr* newType(TypeExpr::Kind kind, Span span) {
    TypeExpr& t = types_.emplace_back();
    t.kind = kind;
    t.span = span;
    return &t;
  }

 private:
  std::deque<Expr> exprs_;
  std::deque<TypeExpr> types_;
};

}  // namespace tex::lang
