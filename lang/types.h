// Types of the language (docs/language.md section 4). Types are interned: compare pointers.
#pragma once
#include <deque>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace tex::lang {

struct Expr;
struct FunctionDecl;

enum class TypeKind {
  Error,  // after a reported error; suppresses follow-on errors
  Bool, Int, Float, Vec2, Vec3, Vec4, Color, Spectrum, Material,
  Image,       // an image texture: an int32 handle into lang::ImageTable (lang/image_table.h)
  Record,      // fields sorted by name
  Function,    // an annotation `(A, B) -> R`; values of it are callables checked at application
  FuncRef,     // a named module-level function as a value (no runtime data)
  BuiltinRef,  // a builtin function as a value (no runtime data)
  Lambda,      // a lambda value: its runtime data are the captured values (`fields`)
};

struct Type {
  TypeKind kind = TypeKind::Error;
  std::vector<std::pair<std::string, const Type*>> fields;  // Record (sorted), Lambda (captures)
  std::vector<const Type*> params;                          // Function
  const Type* result = nullptr;                             // Function
  const FunctionDecl* function = nullptr;                   // FuncRef
  const Expr* lambda = nullptr;                             // Lambda
  std::string builtin;                                      // BuiltinRef

  bool isError() const { return kind == TypeKind::Error; }
  // Float-based values are vectors of float lanes: Float, Vec2-4, Color, Spectrum.
  bool isFloatBased() const {
    return kind == TypeKind::Float || kind == TypeKind::Vec2 || kind == TypeKind::Vec3 ||
           kind == TypeKind::Vec4 || kind == TypeKind::Color || kind == TypeKind::Spectrum;
  }
  bool isVector() const { return kind == TypeKind::Vec2 || kind == TypeKind::Vec3 || kind == TypeKind::Vec4; }
  bool isCallable() const {
    return kind == TypeKind::FuncRef || kind == TypeKind::BuiltinRef || kind == TypeKind::Lambda;
  }
  // Lanes of a float-based type; Spectrum's count is the evaluation context's (0 here).
  int fixedLanes() const;
  // Contains a callable anywhere (such values cannot cross the C ABI).
  bool containsCallable() const;
};

// Interns types; thread-safe so that independent front-end sessions can share it.
class TypeTable {
 public:
  static TypeTable& global();

  const Type* error() { return &basic_[0]; }
  const Type* boolean() { return basic(TypeKind::Bool); }
  const Type* integer() { return basic(TypeKind::Int); }
  const Type* floating() { return basic(TypeKind::Float); }
  const Type* vec(int n);  // 2, 3, 4 (1 gives Float)
  const Type* color() { return basic(TypeKind::Color); }
  const Type* spectrum() { return basic(TypeKind::Spectrum); }
  const Type* material() { return basic(TypeKind::Material); }
  const Type* image() { return basic(TypeKind::Image); }
  const Type* basic(TypeKind kind);
  const Type* record(std::vector<std::pair<std::string, const Type*>> fields);  // sorts them
  const Type* function(std::vector<const Type*> params, const Type* result);
  const Type* funcRef(const FunctionDecl* function);
  const Type* builtinRef(const std::string& name);
  const Type* lambda(const Expr* lambda, std::vector<std::pair<std::string, const Type*>> captures);
  const Type* hit();  // the Hit record

 private:
  TypeTable();
  const Type* intern(Type t);
  std::mutex mutex_;
  std::deque<Type> basic_;
  std::deque<Type> interned_;
  std::map<std::string, const Type*> byKey_;
};

std::string typeName(const Type* t);

}  // namespace tex::lang
