// Name resolution over every definition, instantiated or not: unknown names and types,
// module member access, recursion (E0307) and export annotations (E0308).
#include <algorithm>
#include <functional>

#include "lang/session_impl.h"

namespace tex::lang {

namespace {

struct Reference {
  const FunctionDecl* target;
  Span span;
};

class Resolver {
 public:
  Resolver(Session::Impl& impl, ModuleInfo* module) : impl_(impl), module_(module) {}

  std::vector<Reference> references;  // to this module's own decls

  void type(const TypeExpr* t) {
    if (!t) return;
    switch (t->kind) {
      case TypeExpr::Kind::Name: impl_.resolveType(t, module_); break;
      case TypeExpr::Kind::Record:
        for (auto& f : t->fields) type(f.second);
        break;
      case TypeExpr::Kind::Function:
        for (auto* p : t->params) type(p);
        type(t->result);
        break;
    }
  }

  void expr(const Expr* e) {
    if (!e) return;
    switch (e->kind) {
      case Expr::Kind::IntLit:
      case Expr::Kind::FloatLit:
      case Expr::Kind::BoolLit:
      case Expr::Kind::StringLit: return;
      case Expr::Kind::Name: name(e->name, e->nameSpan, true); return;
      case Expr::Kind::Unary: expr(e->a); return;
      case Expr::Kind::Binary: expr(e->a); expr(e->b); return;
      case Expr::Kind::Call:
        expr(e->a);
        for (auto& arg : e->args) expr(arg.value);
        return;
      case Expr::Kind::Field:
        if (e->a->kind == Expr::Kind::Name && !isLocal(e->a->name)) {
          const Symbol* sym = lookupSymbol(module_, e->a->name);
          if (sym && sym->kind == Symbol::Kind::Module) {
            member(sym->module, e->a->name, e->name, e->nameSpan);
            return;
          }
        }
        expr(e->a);
        return;
      case Expr::Kind::Let:
        expr(e->a);
        type(e->annotation);
        locals_.push_back(e->name);
        expr(e->b);
        locals_.pop_back();
        return;
      case Expr::Kind::If: expr(e->a); expr(e->b); expr(e->c); return;
      case Expr::Kind::Lambda:
        for (auto& p : e->params) {
          type(p.type);
          locals_.push_back(p.name);
        }
        expr(e->a);
        locals_.resize(locals_.size() - e->params.size());
        return;
      case Expr::Kind::Record:
        for (auto& f : e->fields) expr(f.value);
        return;
      case Expr::Kind::RecordUpdate:
        expr(e->a);
        for (auto& f : e->fields) expr(f.value);
        return;
    }
  }

  void pushLocal(const std::string& n) { locals_.push_back(n); }

 private:
  bool isLocal(const std::string& n) const { return std::find(locals_.begin(), locals_.end(), n) != locals_.end(); }

  void name(const std::string& n, Span span, bool asValue) {
    if (isLocal(n)) return;
    if (const Symbol* sym = lookupSymbol(module_, n)) {
      if (sym->kind == Symbol::Kind::Decl && sym->decl && sym->decl->module == module_)
        references.push_back({sym->decl, span});
      if (sym->kind == Symbol::Kind::TypeAlias && asValue)
        impl_.error("E0301", span, "'" + n + "' is a type, not a value");
      return;
    }
    if (isBuiltinFunction(n) || isBuiltinConstant(n)) return;
    impl_.error("E0301", span, "unknown name '" + n + "'", suggestion(n));
  }

  void member(ModuleInfo* target, const std::string& alias, const std::string& n, Span span) {
    if (!target) return;  // the import already failed
    const Symbol* sym = lookupSymbol(target, n);
    bool exported = sym && !sym->imported &&
                    ((sym->kind == Symbol::Kind::Decl && sym->decl && sym->decl->item->exported));
    if (!exported)
      impl_.error("E0305", span, "module '" + alias + "' does not export '" + n + "'",
                  sym && !sym->imported ? "mark its definition with 'export'" : "");
  }

  std::string suggestion(const std::string& n) const {
    // The closest local or module name by edit distance, if it is close.
    auto distance = [](const std::string& a, const std::string& b) {
      std::vector<size_t> row(b.size() + 1);
      for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
      for (size_t i = 1; i <= a.size(); ++i) {
        size_t prev = row[0];
        row[0] = i;
        for (size_t j = 1; j <= b.size(); ++j) {
          size_t cur = row[j];
          row[j] = std::min({row[j] + 1, row[j - 1] + 1, prev + (a[i - 1] != b[j - 1])});
          prev = cur;
        }
      }
      return row[b.size()];
    };
    std::string best;
    size_t bestDistance = n.size() / 3 + 1;
    auto consider = [&](const std::string& c) {
      size_t d = distance(n, c);
      if (d < bestDistance || (d == bestDistance && best.empty() && d <= 2)) {
        bestDistance = d;
        best = c;
      }
    };
    for (auto& l : locals_) consider(l);
    for (auto& [k, v] : module_->scope) consider(k);
    return best.empty() || best == n ? "" : "did you mean '" + best + "'?";
  }

  Session::Impl& impl_;
  ModuleInfo* module_;
  std::vector<std::string> locals_;
};

}  // namespace

void Session::Impl::resolveModule(ModuleInfo* module, Module& ast) {
  std::map<const FunctionDecl*, std::vector<Reference>> edges;
  std::vector<const FunctionDecl*> decls;
  for (const Item& item : ast.items) {
    Resolver r(*this, module);
    const Symbol* sym = lookupSymbol(module, item.name);
    const FunctionDecl* self = sym && sym->kind == Symbol::Kind::Decl && sym->decl && sym->decl->item == &item ? sym->decl : nullptr;
    if (item.kind == Item::Kind::Type) {
      r.type(item.resultType);
      continue;
    }
    bool missingAnnotation = false;
    for (const Param& p : item.params) {
      r.type(p.type);
      missingAnnotation |= !p.type;
    }
    for (const Param& p : item.params) r.expr(p.defaultValue);  // defaults see only module scope
    for (const Param& p : item.params) r.pushLocal(p.name);
    r.type(item.resultType);
    r.expr(item.body);
    if (item.exported && (missingAnnotation || !item.resultType)) {
      std::string what = item.kind == Item::Kind::Let ? "an exported constant needs a type annotation"
                                                      : "an exported function needs a type on every parameter and its result";
      error("E0308", item.nameSpan, "'" + item.name + "': " + what,
            "exported definitions are entry points for the renderer; write e.g. 'export fn f(h: Hit) -> Color'");
    }
    if (self) {
      decls.push_back(self);
      edges[self] = std::move(r.references);
    }
  }
  // Recursion: every reference between two definitions of one strongly connected component
  // of the reference graph (Tarjan's algorithm), self-references included.
  std::map<const FunctionDecl*, int> index, low;
  std::map<const FunctionDecl*, int> component;
  std::vector<const FunctionDecl*> stack;
  std::set<const FunctionDecl*> onStack;
  int counter = 0, components = 0;
  std::function<void(const FunctionDecl*)> strongConnect = [&](const FunctionDecl* v) {
    index[v] = low[v] = counter++;
    stack.push_back(v);
    onStack.insert(v);
    for (const Reference& ref : edges[v]) {
      const FunctionDecl* w = ref.target;
      if (!edges.count(w)) continue;
      if (!index.count(w)) {
        strongConnect(w);
        low[v] = std::min(low[v], low[w]);
      } else if (onStack.count(w)) {
        low[v] = std::min(low[v], index[w]);
      }
    }
    if (low[v] == index[v]) {
      const FunctionDecl* w;
      do {
        w = stack.back();
        stack.pop_back();
        onStack.erase(w);
        component[w] = components;
      } while (w != v);
      ++components;
    }
  };
  for (const FunctionDecl* d : decls)
    if (!index.count(d)) strongConnect(d);
  // Report the references that close a cycle: those to a definition at or before the
  // referring one in the file (every cycle has one), so a cycle is reported once per back edge.
  std::map<const FunctionDecl*, size_t> order;
  for (size_t i = 0; i < decls.size(); ++i) order[decls[i]] = i;
  for (const FunctionDecl* d : decls) {
    for (const Reference& ref : edges[d]) {
      if (!component.count(ref.target) || component[ref.target] != component[d]) continue;
      if (order[ref.target] > order[d]) continue;
      bool cyclic = ref.target == d;
      for (const FunctionDecl* other : decls)
        cyclic |= other != d && component[other] == component[d];
      if (!cyclic) continue;
      error("E0307", ref.span,
            ref.target == d ? "'" + d->item->name + "' refers to itself: recursion is not allowed"
                            : "'" + d->item->name + "' and '" + ref.target->item->name + "' refer to each other: recursion is not allowed",
            "tex programs always terminate; use fold(n, init, f) for repetition");
    }
  }
}

void Session::Impl::resolveExpression(ModuleInfo* module, const Expr* expr, const std::vector<std::string>& params) {
  Resolver r(*this, module);
  for (auto& p : params) r.pushLocal(p);
  r.expr(expr);
}

}  // namespace tex::lang
