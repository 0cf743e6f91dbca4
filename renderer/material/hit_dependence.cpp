#include "renderer/material/hit_dependence.h"

#include <map>
#include <set>
#include <utility>
#include <vector>

namespace tex::render {

namespace {

using lang::ir::Function;
using lang::ir::Node;
using lang::ir::Program;

class Analysis {
 public:
  explicit Analysis(const Program& program) : program_(program) {}

  // Whether `function`'s result depends on the parameters flagged in `params`.
  bool resultDepends(int function, const std::vector<bool>& params) {
    if (function < 0 || size_t(function) >= program_.functions.size()) return true;
    const Key key{function, params};
    if (auto it = memo_.find(key); it != memo_.end()) return it->second;
    if (!active_.insert(key).second) return true;  // recursion: assume the worst
    const Function& f = program_.functions[size_t(function)];
    bool depends = true;
    if (f.body && params.size() == f.paramTypes.size() && f.numSlots >= int(params.size())) {
      // Slots only ever gain dependence (a Let marks its slot if its value depends), so the
      // walk is repeated until no slot changes: evaluation order cannot hide a flow.
      std::vector<bool> slots(size_t(f.numSlots), false);
      for (size_t i = 0; i < params.size(); ++i) slots[i] = params[i];
      for (;;) {
        const std::vector<bool> before = slots;
        depends = walk(f.body, slots);
        if (slots == before) break;
      }
    }
    active_.erase(key);
    memo_[key] = depends;
    return depends;
  }

 private:
  using Key = std::pair<int, std::vector<bool>>;

  bool walk(const Node* n, std::vector<bool>& slots) {
    if (!n) return true;
    switch (n->kind) {
      case Node::Kind::Const: return false;
      case Node::Kind::Local:
        return n->slot < 0 || size_t(n->slot) >= slots.size() || slots[size_t(n->slot)];
      case Node::Kind::Let: {
        if (n->args.size() != 2 || n->slot < 0 || size_t(n->slot) >= slots.size()) return true;
        if (walk(n->args[0], slots)) slots[size_t(n->slot)] = true;
        return walk(n->args[1], slots);
      }
      case Node::Kind::Call: {
        std::vector<bool> args;
        for (const Node* a : n->args) args.push_back(walk(a, slots));
        return resultDepends(n->callee, args);
      }
      case Node::Kind::Fold: {
        // acc = args[1]; for i < args[0]: acc = callee([args[2],] acc, i)
        if (n->args.size() < 2) return true;
        const bool count = walk(n->args[0], slots);
        bool acc = walk(n->args[1], slots);
        const bool hasClosure = n->args.size() > 2;
        const bool closure = hasClosure && walk(n->args[2], slots);
        for (;;) {  // the accumulator's dependence only grows: at most two rounds
          std::vector<bool> params;
          if (hasClosure) params.push_back(closure);
          params.push_back(acc);
          params.push_back(count);
          const bool next = acc || resultDepends(n->callee, params);
          if (next == acc) break;
          acc = next;
        }
        return acc || count;
      }
      case Node::Kind::If:
      case Node::Kind::And:
      case Node::Kind::Or:
      case Node::Kind::Prim:
      case Node::Kind::MakeRecord:
      case Node::Kind::GetField: {
        bool any = false;
        for (const Node* a : n->args) any = walk(a, slots) || any;  // walk every operand (their Lets)
        return any;
      }
    }
    return true;
  }

  const Program& program_;
  std::map<Key, bool> memo_;
  std::set<Key> active_;
};

}  // namespace

bool resultIgnoresParameter(const Program& program, int function, int parameter) {
  if (function < 0 || size_t(function) >= program.functions.size()) return false;
  const size_t count = program.functions[size_t(function)].paramTypes.size();
  if (parameter < 0 || size_t(parameter) >= count) return false;
  std::vector<bool> params(count, false);
  params[size_t(parameter)] = true;
  return !Analysis(program).resultDepends(function, params);
}

}  // namespace tex::render
