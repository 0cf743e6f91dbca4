#include "renderer/material/closure_kinds.h"

#include <vector>

namespace tex::render {

bool mayBuildPrimitive(const lang::ir::Program& program, int function, lang::ir::Prim prim) {
  using lang::ir::Node;
  std::vector<char> seen(program.functions.size(), 0);
  std::vector<int> functions{function};
  std::vector<const Node*> nodes;
  while (!functions.empty()) {
    const int f = functions.back();
    functions.pop_back();
    if (f < 0 || size_t(f) >= seen.size() || seen[size_t(f)]) continue;
    seen[size_t(f)] = 1;
    if (program.functions[size_t(f)].body) nodes.push_back(program.functions[size_t(f)].body);
    while (!nodes.empty()) {
      const Node* n = nodes.back();
      nodes.pop_back();
      if (n->kind == Node::Kind::Prim && n->prim == prim) return true;
      if (n->kind == Node::Kind::Call || n->kind == Node::Kind::Fold) functions.push_back(n->callee);
      for (const Node* a : n->args) nodes.push_back(a);
    }
  }
  return false;
}

}  // namespace tex::render
