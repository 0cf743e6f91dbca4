#include "compiler/canonical_ir.h"

#include <algorithm>
#include <cstring>
#include <deque>
#include <map>
#include <set>
#include <sstream>

#include "lang/image_table.h"

namespace tex::compiler {

using lang::Type;
using lang::ir::Node;

namespace {

class Canonicaliser {
 public:
  explicit Canonicaliser(const lang::ir::Program& p) : program_(p) {}

  std::string run(const std::vector<int>& entries) {
    for (int e : entries) number(e);
    body_ << "entries";
    for (int e : entries) body_ << " @" << functionIds_[e];
    body_ << "\n";
    while (!queue_.empty()) {
      int f = queue_.front();
      queue_.pop_front();
      printFunction(f);
    }
    return types_.str() + body_.str();
  }

 private:
  int number(int function) {
    auto [it, inserted] = functionIds_.emplace(function, int(functionIds_.size()));
    if (inserted) queue_.push_back(function);
    return it->second;
  }

  // Types are printed once each, in first-use order, and referred to by number.
  int type(const Type* t) {
    if (auto it = typeIds_.find(t); it != typeIds_.end()) return it->second;
    std::vector<int> fieldIds;
    for (auto& f : t->fields) fieldIds.push_back(type(f.second));
    std::vector<int> paramIds;
    for (const Type* p : t->params) paramIds.push_back(type(p));
    int result = t->result ? type(t->result) : -1;
    int id = int(typeIds_.size());
    typeIds_[t] = id;
    types_ << "type " << id << " kind " << int(t->kind);
    for (size_t i = 0; i < t->fields.size(); ++i) types_ << " " << t->fields[i].first << ":" << fieldIds[i];
    for (int p : paramIds) types_ << " p" << p;
    if (result >= 0) types_ << " r" << result;
    // Lambda and function identities only matter through the code they lead to, which is
    // part of this text; builtins are named.
    if (!t->builtin.empty()) types_ << " builtin " << t->builtin;
    types_ << "\n";
    return id;
  }

  void printFunction(int f) {
    const lang::ir::Function& fn = program_.functions[size_t(f)];
    body_ << "fn @" << functionIds_[f] << " slots " << fn.numSlots << " (";
    for (const Type* t : fn.paramTypes) body_ << type(t) << ",";
    body_ << ") -> " << type(fn.resultType) << "\n";
    printNode(fn.body);
    body_ << "\n";
  }

  void printNode(const Node* n) {
    body_ << "(" << int(n->kind) << " t" << type(n->type);
    switch (n->kind) {
      case Node::Kind::Const: {
        if (n->type->kind == lang::TypeKind::Image) {
          // The file, not the process-specific handle: code resolves it at run time by path,
          // and the file's size and mtime keep an edited image from matching an old key.
          const lang::LoadedImage* image = lang::ImageTable::global().get(n->intValue);
          if (image)
            body_ << " image " << image->path.size() << ":" << image->path << " data" << image->data << " bytes "
                  << image->fileBytes << " mtime " << image->mtimeNs;
          else
            body_ << " image ?" << n->intValue;
          break;
        }
        uint32_t bits[8];
        std::memcpy(bits, n->floatValue, sizeof bits);
        body_ << " i" << n->intValue << " b" << n->boolValue << " f";
        for (uint32_t b : bits) body_ << std::hex << b << std::dec << ",";
        break;
      }
      case Node::Kind::Local:
      case Node::Kind::Let: body_ << " %" << n->slot; break;
      case Node::Kind::Prim:
        body_ << " " << lang::ir::primName(n->prim);
        for (uint8_t l : n->lanes) body_ << " l" << int(l);
        break;
      case Node::Kind::Call:
      case Node::Kind::Fold: body_ << " @" << number(n->callee); break;
      case Node::Kind::GetField: body_ << " ." << n->index; break;
      default: break;
    }
    for (const Node* a : n->args) printNode(a);
    body_ << ")";
  }

  const lang::ir::Program& program_;
  std::map<int, int> functionIds_;
  std::map<const Type*, int> typeIds_;
  std::deque<int> queue_;
  std::ostringstream types_, body_;
};

uint64_t saturatingAdd(uint64_t a, uint64_t b) { return a + b < a ? UINT64_MAX : a + b; }

// The inlined size of function f (its nodes, each call or fold counting its callee's inlined
// size), memoised per function; iterative over the nodes and the call chain (bodies 8192 levels
// deep calling each other 60 deep overflowed the stack when this recursed).
uint64_t functionSize(const lang::ir::Program& program, int f, std::map<int, uint64_t>& memo) {
  std::vector<const Node*> nodes;
  return lang::ir::bottomUpOverCalls(f, memo, [&](int g, const auto& callee) -> std::optional<uint64_t> {
    uint64_t size = 0;
    bool complete = true;
    nodes.assign(1, program.functions[size_t(g)].body);
    while (!nodes.empty()) {
      const Node* n = nodes.back();
      nodes.pop_back();
      if (!n) continue;
      size = saturatingAdd(size, 1);
      if (n->kind == Node::Kind::Call || n->kind == Node::Kind::Fold) {
        const std::optional<uint64_t> inlined = callee(n->callee);
        if (inlined) size = saturatingAdd(size, *inlined);
        else complete = false;
      }
      for (const Node* a : n->args) nodes.push_back(a);
    }
    return complete ? std::optional<uint64_t>(size) : std::nullopt;
  });
}

}  // namespace

std::string canonicalText(const lang::ir::Program& program, const std::vector<int>& entries) {
  return Canonicaliser(program).run(entries);
}

namespace {

uint64_t typeWords(const lang::Type* type, int wavelengths, std::map<const lang::Type*, uint64_t>& memo) {
  if (auto it = memo.find(type); it != memo.end()) return it->second;
  uint64_t words = 0;
  switch (type->kind) {
    case lang::TypeKind::Spectrum: words = uint64_t(wavelengths); break;
    case lang::TypeKind::Record:
    case lang::TypeKind::Lambda:
      // Field types are strictly smaller than the record (types are finite trees, shared):
      // the recursion is as deep as the type's nesting, which the checker bounds.
      for (auto& field : type->fields) words = saturatingAdd(words, typeWords(field.second, wavelengths, memo));
      break;
    default: words = uint64_t(std::max(type->fixedLanes(), 1));
  }
  memo[type] = words;
  return words;
}

}  // namespace

LargestValue largestValue(const lang::ir::Program& program, int function, int wavelengths) {
  LargestValue largest;
  std::map<const lang::Type*, uint64_t> memo;
  std::set<int> seen = {function};
  std::vector<int> functions = {function};
  std::vector<const Node*> nodes;
  while (!functions.empty()) {
    const lang::ir::Function& fn = program.functions[size_t(functions.back())];
    functions.pop_back();
    nodes.assign(1, fn.body);
    while (!nodes.empty()) {
      const Node* n = nodes.back();
      nodes.pop_back();
      if (!n) continue;
      if (n->type) {
        const uint64_t words = typeWords(n->type, wavelengths, memo);
        if (words > largest.words) largest = {words, n->type};
      }
      if ((n->kind == Node::Kind::Call || n->kind == Node::Kind::Fold) && seen.insert(n->callee).second)
        functions.push_back(n->callee);
      for (const Node* a : n->args) nodes.push_back(a);
    }
  }
  return largest;
}

uint64_t inlinedSize(const lang::ir::Program& program, int function) {
  std::map<int, uint64_t> memo;
  return functionSize(program, function, memo);
}

}  // namespace tex::compiler
