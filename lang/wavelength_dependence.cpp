#include "lang/wavelength_dependence.h"

#include "lang/value.h"

namespace tex::lang::ir {

bool holdsSpectrum(const Type* t) {
  if (t->kind == TypeKind::Spectrum) return true;
  for (auto& f : t->fields)
    if (holdsSpectrum(f.second)) return true;
  return false;
}

bool WavelengthDependence::buildsMaterial(int function) {
  if (auto it = builds_.find(function); it != builds_.end()) return it->second;
  builds_[function] = false;  // no recursion in valid programs; guards against cycles anyway
  bool builds = nodeBuildsMaterial(program_.functions[size_t(function)].body);
  builds_[function] = builds;
  return builds;
}

bool WavelengthDependence::nodeBuildsMaterial(const Node* n) {
  if (n->kind == Node::Kind::Prim && isMaterialLeaf(n->prim)) return true;
  if ((n->kind == Node::Kind::Call || n->kind == Node::Kind::Fold) && buildsMaterial(n->callee)) return true;
  for (const Node* a : n->args)
    if (nodeBuildsMaterial(a)) return true;
  return false;
}

int WavelengthDependence::entryContext(int function) {
  const Function& fn = program_.functions[size_t(function)];
  std::vector<bool> params;
  for (const Type* t : fn.paramTypes) params.push_back(holdsSpectrum(t));
  return context(function, std::move(params));
}

int WavelengthDependence::calleeContext(int context, const Node* n) {
  if (context < 0 || size_t(context) >= contexts_.size()) return -1;
  const auto& callees = contexts_[size_t(context)]->callees;
  auto it = callees.find(n);
  return it == callees.end() ? -1 : it->second;
}

uint32_t WavelengthDependence::flags(int context, const Node* n) const {
  // An unanalysed call path (there should be none): assume the leaf varies, the safe answer.
  if (context < 0 || size_t(context) >= contexts_.size()) return kMaterialVariesWithWavelength;
  const auto& leaves = contexts_[size_t(context)]->leafFlags;
  auto it = leaves.find(n);
  return it == leaves.end() ? 0 : it->second;
}

int WavelengthDependence::context(int function, std::vector<bool> params) {
  auto key = std::make_pair(function, params);
  if (auto it = ids_.find(key); it != ids_.end()) return it->second;
  int id = int(contexts_.size());
  ids_[key] = id;
  contexts_.push_back(std::make_unique<Context>());
  Context& c = *contexts_.back();
  c.function = function;
  c.params = std::move(params);
  const Function& fn = program_.functions[size_t(function)];
  std::vector<bool> slots(size_t(std::max<int>(fn.numSlots, int(c.params.size()))), false);
  for (size_t i = 0; i < c.params.size(); ++i) slots[i] = c.params[i];
  c.resultDepends = walk(c, fn.body, slots);
  c.done = true;
  return id;
}

bool WavelengthDependence::canDepend(const Type* t) {
  auto [it, inserted] = typeHoldsSpectrum_.emplace(t, false);
  if (inserted) it->second = holdsSpectrum(t);
  return it->second;
}

// The dependence of `n`'s value; records leaf flags and callee contexts on the way.
bool WavelengthDependence::walk(Context& c, const Node* n, std::vector<bool>& slots) {
  return walkNode(c, n, slots) && canDepend(n->type);
}

bool WavelengthDependence::walkNode(Context& c, const Node* n, std::vector<bool>& slots) {
  auto anyArg = [&] {
    bool depends = false;
    for (const Node* a : n->args) depends = walk(c, a, slots) || depends;  // walk every argument
    return depends;
  };
  // A node reached twice (shared by the builder) keeps the union of what it saw.
  auto recordCallee = [&](int callee) {
    auto [it, inserted] = c.callees.emplace(n, callee);
    if (inserted || it->second == callee) return callee;
    const Context& a = *contexts_[size_t(it->second)];
    const Context& b = *contexts_[size_t(callee)];
    std::vector<bool> both(a.params.size());
    for (size_t i = 0; i < both.size(); ++i) both[i] = a.params[i] || b.params[i];
    it->second = context(a.function, std::move(both));
    return it->second;
  };
  auto resultOf = [&](int ctx) {
    const Context& callee = *contexts_[size_t(ctx)];
    return !callee.done || callee.resultDepends;  // a cycle (never valid) is assumed to depend
  };
  switch (n->kind) {
    case Node::Kind::Const: return false;
    case Node::Kind::Local: return slots[size_t(n->slot)];
    case Node::Kind::Let: {
      bool value = walk(c, n->args[0], slots);
      slots[size_t(n->slot)] = value;
      return walk(c, n->args[1], slots);
    }
    case Node::Kind::Prim: {
      // The argument is walked even where the result depends regardless: calls inside it need
      // their callee contexts (code generation of a material built in such a call had read
      // context -1 and crashed: reflectance_spectrum(c()) with c building a diffuse).
      bool depends = anyArg();
      if (n->prim == Prim::Wavelengths || n->prim == Prim::RgbReflectance || n->prim == Prim::RgbUnbounded ||
          n->prim == Prim::RgbIlluminant)
        return true;
      if (isMaterialLeaf(n->prim) && depends) c.leafFlags[n] |= kMaterialVariesWithWavelength;
      return depends;
    }
    case Node::Kind::Call: {
      std::vector<bool> params;
      for (const Node* a : n->args) params.push_back(walk(c, a, slots));
      return resultOf(recordCallee(context(n->callee, std::move(params))));
    }
    case Node::Kind::Fold: {
      // step(closure?, acc, i): the accumulator depends if its initial value does or if a step
      // makes it depend (at most one more round: dependence only grows).
      walk(c, n->args[0], slots);
      bool acc = walk(c, n->args[1], slots);
      bool hasClosure = n->args.size() > 2;
      bool closure = hasClosure && walk(c, n->args[2], slots);
      int ctx = -1;
      for (int round = 0; round < 2; ++round) {
        std::vector<bool> params;
        if (hasClosure) params.push_back(closure);
        params.push_back(acc);
        params.push_back(false);
        ctx = context(n->callee, std::move(params));
        if (!resultOf(ctx) || acc) break;
        acc = true;
      }
      recordCallee(ctx);
      return acc || resultOf(ctx);
    }
    default: return anyArg();  // If, And, Or, MakeRecord, GetField
  }
}

}  // namespace tex::lang::ir
