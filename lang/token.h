// Tokens produced by the lexer.
#pragma once
#include <cstdint>
#include <string_view>

namespace tex::lang {

enum class Tok : uint8_t {
  End, Error,
  Ident, Int, Float,
  String,  // "...": only as the path argument of image() and image_data()
  // keywords
  KwFn, KwLet, KwIn, KwIf, KwElse, KwImport, KwExport, KwAs, KwType, KwTrue, KwFalse, KwWith,
  // punctuation
  LParen, RParen, LBrace, RBrace, Comma, Colon, Semi, Dot, Assign, Arrow,
  // operators
  Plus, Minus, Star, Slash, Percent,
  EqEq, NotEq, Lt, Le, Gt, Ge,
  AndAnd, OrOr, Bang, Tilde, Amp, Pipe, Caret, Shl, Shr,
};

struct Token {
  Tok kind = Tok::End;
  uint32_t begin = 0, end = 0;  // byte offsets into the file
  int64_t intValue = 0;        // Tok::Int (may be 2147483648, see docs/language.md); Tok::String: 1 if malformed
  float floatValue = 0;        // Tok::Float
};

const char* tokenName(Tok kind);  // for messages: "'('", "identifier", ...

}  // namespace tex::lang
