// The lexer: UTF-8 validation, comments, literals, operators (docs/language.md section 1).
#pragma once
#include <string_view>
#include <vector>

#include "lang/source.h"
#include "lang/token.h"

namespace tex::lang {

// Tokenises a whole file. Lexical errors are reported to `diags` and the offending bytes are
// skipped, so the parser still sees the rest. The last token is always Tok::End.
std::vector<Token> lex(const SourceFile& file, Diagnostics& diags);

constexpr size_t kMaxSourceBytes = size_t(64) << 20;

// Whether `word` is a keyword (fn, let, type, ...): such a name cannot be imported as a module.
bool isKeyword(std::string_view word);

}  // namespace tex::lang
