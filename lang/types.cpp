#include "lang/types.h"

#include <algorithm>
#include <cstdio>

#include "lang/ast.h"

namespace tex::lang {

int Type::fixedLanes() const {
  switch (kind) {
    case TypeKind::Float: return 1;
    case TypeKind::Vec2: return 2;
    case TypeKind::Vec3: return 3;
    case TypeKind::Vec4: return 4;
    case TypeKind::Color: return 3;
    default: return 0;
  }
}

bool Type::containsCallable() const {
  if (isCallable() || kind == TypeKind::Function) return true;
  for (auto& f : fields)
    if (f.second->containsCallable()) return true;
  return false;
}

TypeTable& TypeTable::global() {
  static TypeTable table;
  return table;
}

TypeTable::TypeTable() {
  for (int k = 0; k <= int(TypeKind::Image); ++k) {
    Type t;
    t.kind = TypeKind(k);
    basic_.push_back(t);
  }
}

const Type* TypeTable::basic(TypeKind kind) { return &basic_[size_t(kind)]; }

const Type* TypeTable::vec(int n) {
  switch (n) {
    case 1: return floating();
    case 2: return basic(TypeKind::Vec2);
    case 3: return basic(TypeKind::Vec3);
    case 4: return basic(TypeKind::Vec4);
    default: return error();
  }
}

static std::string ptrKey(const void* p) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%p", p);
  return buf;
}

// A structural key: two types are equal iff their keys are.
static std::string keyOf(const Type& t) {
  std::string key = std::to_string(int(t.kind));
  key += "(";
  for (auto& [name, ft] : t.fields) key += name + ":" + ptrKey(ft) + ",";
  key += "|";
  for (auto* p : t.params) key += ptrKey(p) + ",";
  for (const std::string& part : {ptrKey(t.result), ptrKey(t.function), ptrKey(t.lambda), t.builtin}) {
    key += '|';
    key += part;
  }
  return key;
}

const Type* TypeTable::intern(Type t) {
  std::string key = keyOf(t);
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = byKey_.find(key);
  if (it != byKey_.end()) return it->second;
  interned_.push_back(std::move(t));
  const Type* p = &interned_.back();
  byKey_.emplace(std::move(key), p);
  return p;
}

const Type* TypeTable::record(std::vector<std::pair<std::string, const Type*>> fields) {
  std::sort(fields.begin(), fields.end(), [](auto& a, auto& b) { return a.first < b.first; });
  Type t;
  t.kind = TypeKind::Record;
  t.fields = std::move(fields);
  return intern(std::move(t));
}

const Type* TypeTable::function(std::vector<const Type*> params, const Type* result) {
  Type t;
  t.kind = TypeKind::Function;
  t.params = std::move(params);
  t.result = result;
  return intern(std::move(t));
}

const Type* TypeTable::funcRef(const FunctionDecl* function) {
  Type t;
  t.kind = TypeKind::FuncRef;
  t.function = function;
  return intern(std::move(t));
}

const Type* TypeTable::builtinRef(const std::string& name) {
  Type t;
  t.kind = TypeKind::BuiltinRef;
  t.builtin = name;
  return intern(std::move(t));
}

const Type* TypeTable::lambda(const Expr* lambda, std::vector<std::pair<std::string, const Type*>> captures) {
  Type t;
  t.kind = TypeKind::Lambda;
  t.lambda = lambda;
  t.fields = std::move(captures);
  return intern(std::move(t));
}

const Type* TypeTable::hit() {
  return record({{"p", vec(3)}, {"n", vec(3)}, {"uv", vec(2)}, {"dpdx", vec(3)},
                 {"dpdy", vec(3)}, {"duvdx", vec(2)}, {"duvdy", vec(2)}});
}

static std::string typeNameUnbounded(const Type* t, int depth);

std::string typeName(const Type* t) {
  // Nested records can be exponentially large when printed; messages get a bounded form.
  std::string s = typeNameUnbounded(t, 0);
  return s.size() > 240 ? s.substr(0, 237) + "..." : s;
}

static std::string typeNameUnbounded(const Type* t, int depth) {
  if (!t) return "?";
  if (depth > 6) return "...";
  switch (t->kind) {
    case TypeKind::Error: return "<error>";
    case TypeKind::Bool: return "Bool";
    case TypeKind::Int: return "Int";
    case TypeKind::Float: return "Float";
    case TypeKind::Vec2: return "Vec2";
    case TypeKind::Vec3: return "Vec3";
    case TypeKind::Vec4: return "Vec4";
    case TypeKind::Color: return "Color";
    case TypeKind::Spectrum: return "Spectrum";
    case TypeKind::Material: return "Material";
    case TypeKind::Image: return "Image";
    case TypeKind::Record: {
      if (t == TypeTable::global().hit()) return "Hit";
      std::string s = "{";
      for (size_t i = 0; i < t->fields.size(); ++i) {
        if (i) s += ", ";
        s += t->fields[i].first + ": " + typeNameUnbounded(t->fields[i].second, depth + 1);
      }
      return s + "}";
    }
    case TypeKind::Function: {
      std::string s = "(";
      for (size_t i = 0; i < t->params.size(); ++i) {
        if (i) s += ", ";
        s += typeNameUnbounded(t->params[i], depth + 1);
      }
      return s + ") -> " + typeNameUnbounded(t->result, depth + 1);
    }
    case TypeKind::FuncRef: return "<function>";
    case TypeKind::BuiltinRef: return "<builtin " + t->builtin + ">";
    case TypeKind::Lambda: return "<lambda>";
  }
  return "?";
}

}  // namespace tex::lang
