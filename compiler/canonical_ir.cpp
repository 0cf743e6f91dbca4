#include "compiler/canonical_ir.h"

#include <cstring>
#include <deque>
#include <map>
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

uint64_t nodeSize(const lang::ir::Program& program, const Node* n, std::map<int, uint64_t>& memo);

uint64_t functionSize(const lang::ir::Program& program, int f, std::map<int, uint64_t>& memo) {
  if (auto it = memo.find(f); it != memo.end()) return it->second;
  memo[f] = 0;  // no recursion in valid programs; guards against cycles anyway
  uint64_t size = nodeSize(program, program.functions[size_t(f)].body, memo);
  memo[f] = size;
  return size;
}

uint64_t nodeSize(const lang::ir::Program& program, const Node* n, std::map<int, uint64_t>& memo) {
  uint64_t size = 1;
  if (n->kind == Node::Kind::Call || n->kind == Node::Kind::Fold)
    size = saturatingAdd(size, functionSize(program, n->callee, memo));
  for (const Node* a : n->args) size = saturatingAdd(size, nodeSize(program, a, memo));
  return size;
}

}  // namespace

std::string canonicalText(const lang::ir::Program& program, const std::vector<int>& entries) {
  return Canonicaliser(program).run(entries);
}

uint64_t inlinedSize(const lang::ir::Program& program, int function) {
  std::map<int, uint64_t> memo;
  return functionSize(program, function, memo);
}

}  // namespace tex::compiler
