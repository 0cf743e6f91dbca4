// The parser: tokens to a syntax tree with spans, recovering at item boundaries so that one
// run reports every syntax error (docs/language.md section 2).
#pragma once
#include <memory>

#include "lang/ast.h"

namespace tex::lang {

constexpr int kMaxNestingDepth = 256;   // brackets, blocks, calls, unary operators, lets, lambdas
constexpr int kMaxChainLength = 4096;   // operators in one chain, calls in one postfix chain, lets in one block
// Levels of one definition's syntax tree, every node counted (so each operator of a chain is a
// level): chains nested in chains multiply, and the checker, interpreter and compiler recurse
// over the tree.
constexpr int kMaxTreeDepth = 8192;

// Lexes and parses a whole file. Always returns a module (possibly partial); errors go to diags.
std::unique_ptr<Module> parseModule(std::shared_ptr<SourceFile> file, Diagnostics& diags);

// Parses one REPL input: either items/imports, or a single expression. Sets `expr` for an
// expression input; otherwise adds the items and imports to the returned module.
std::unique_ptr<Module> parseReplInput(std::shared_ptr<SourceFile> file, Diagnostics& diags, Expr*& expr);

}  // namespace tex::lang
