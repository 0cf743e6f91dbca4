#include "lang/lexer.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <string>
#include <unordered_map>

namespace tex::lang {

const char* tokenName(Tok kind) {
  switch (kind) {
    case Tok::End: return "end of file";
    case Tok::Error: return "invalid token";
    case Tok::Ident: return "identifier";
    case Tok::Int: return "integer literal";
    case Tok::Float: return "float literal";
    case Tok::String: return "string literal";
    case Tok::KwFn: return "'fn'";
    case Tok::KwLet: return "'let'";
    case Tok::KwIn: return "'in'";
    case Tok::KwIf: return "'if'";
    case Tok::KwElse: return "'else'";
    case Tok::KwImport: return "'import'";
    case Tok::KwExport: return "'export'";
    case Tok::KwAs: return "'as'";
    case Tok::KwType: return "'type'";
    case Tok::KwTrue: return "'true'";
    case Tok::KwFalse: return "'false'";
    case Tok::KwWith: return "'with'";
    case Tok::LParen: return "'('";
    case Tok::RParen: return "')'";
    case Tok::LBrace: return "'{'";
    case Tok::RBrace: return "'}'";
    case Tok::Comma: return "','";
    case Tok::Colon: return "':'";
    case Tok::Semi: return "';'";
    case Tok::Dot: return "'.'";
    case Tok::Assign: return "'='";
    case Tok::Arrow: return "'->'";
    case Tok::Plus: return "'+'";
    case Tok::Minus: return "'-'";
    case Tok::Star: return "'*'";
    case Tok::Slash: return "'/'";
    case Tok::Percent: return "'%'";
    case Tok::EqEq: return "'=='";
    case Tok::NotEq: return "'!='";
    case Tok::Lt: return "'<'";
    case Tok::Le: return "'<='";
    case Tok::Gt: return "'>'";
    case Tok::Ge: return "'>='";
    case Tok::AndAnd: return "'&&'";
    case Tok::OrOr: return "'||'";
    case Tok::Bang: return "'!'";
    case Tok::Tilde: return "'~'";
    case Tok::Amp: return "'&'";
    case Tok::Pipe: return "'|'";
    case Tok::Caret: return "'^'";
    case Tok::Shl: return "'<<'";
    case Tok::Shr: return "'>>'";
  }
  return "token";
}

namespace {

// Length of the valid UTF-8 sequence starting at p, or 0 if invalid (overlong, surrogate,
// out of range, truncated).
size_t utf8SequenceLength(const unsigned char* p, const unsigned char* end) {
  unsigned char c = p[0];
  if (c < 0x80) return 1;
  size_t n;
  uint32_t cp;
  if ((c & 0xE0) == 0xC0) { n = 2; cp = c & 0x1F; }
  else if ((c & 0xF0) == 0xE0) { n = 3; cp = c & 0x0F; }
  else if ((c & 0xF8) == 0xF0) { n = 4; cp = c & 0x07; }
  else return 0;
  if (size_t(end - p) < n) return 0;
  for (size_t i = 1; i < n; ++i) {
    if ((p[i] & 0xC0) != 0x80) return 0;
    cp = (cp << 6) | (p[i] & 0x3F);
  }
  static const uint32_t minimum[5] = {0, 0, 0x80, 0x800, 0x10000};
  if (cp < minimum[n] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return 0;
  return n;
}

const std::unordered_map<std::string_view, Tok>& keywords() {
  static const std::unordered_map<std::string_view, Tok> table = {
      {"fn", Tok::KwFn},       {"let", Tok::KwLet},       {"in", Tok::KwIn},
      {"if", Tok::KwIf},       {"else", Tok::KwElse},     {"import", Tok::KwImport},
      {"export", Tok::KwExport}, {"as", Tok::KwAs},       {"type", Tok::KwType},
      {"true", Tok::KwTrue},   {"false", Tok::KwFalse},   {"with", Tok::KwWith},
  };
  return table;
}

}  // namespace

bool isKeyword(std::string_view word) { return keywords().count(word) > 0; }

namespace {

bool isIdentStart(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }
bool isDigit(char c) { return c >= '0' && c <= '9'; }
bool isHexDigit(char c) { return isDigit(c) || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F'); }
bool isIdentChar(char c) { return isIdentStart(c) || isDigit(c); }

class Lexer {
 public:
  Lexer(const SourceFile& file, Diagnostics& diags) : file_(file), text_(file.text), diags_(diags) {}

  std::vector<Token> run() {
    std::vector<Token> tokens;
    validateUtf8();
    while (true) {
      skipTrivia();
      if (pos_ >= text_.size()) break;
      Token t = next();
      if (t.kind != Tok::Error) tokens.push_back(t);
    }
    Token end;
    end.kind = Tok::End;
    end.begin = end.end = uint32_t(text_.size());
    tokens.push_back(end);
    return tokens;
  }

 private:
  Span span(size_t b, size_t e) const { return Span{&file_, uint32_t(b), uint32_t(e)}; }

  // Reports every invalid UTF-8 sequence once (up to a limit) before lexing; the main loop
  // then treats any non-ASCII byte outside comments as an unexpected character silently.
  void validateUtf8() {
    auto* p = reinterpret_cast<const unsigned char*>(text_.data());
    auto* end = p + text_.size();
    int reported = 0;
    for (auto* q = p; q < end;) {
      size_t n = utf8SequenceLength(q, end);
      if (n == 0) {
        if (reported++ < 10) {
          char hex[8];
          std::snprintf(hex, sizeof hex, "0x%02x", unsigned(*q));
          diags_.error("E0101", span(q - p, q - p + 1),
                       std::string("invalid UTF-8 byte ") + hex,
                       "tex source files must be UTF-8 encoded");
        }
        invalidUtf8_ = true;
        ++q;
      } else {
        q += n;
      }
    }
  }

  void skipTrivia() {
    while (pos_ < text_.size()) {
      char c = text_[pos_];
      if (c == ' ' || c == '\t' || c == '\n' || c == '\r') {
        ++pos_;
      } else if (c == '/' && peek(1) == '/') {
        while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
      } else if (c == '/' && peek(1) == '*') {
        skipBlockComment();
      } else {
        break;
      }
    }
  }

  void skipBlockComment() {
    size_t start = pos_;
    int depth = 0;
    while (pos_ < text_.size()) {
      if (text_[pos_] == '/' && peek(1) == '*') {
        ++depth;
        pos_ += 2;
      } else if (text_[pos_] == '*' && peek(1) == '/') {
        pos_ += 2;
        if (--depth == 0) return;
      } else {
        ++pos_;
      }
    }
    diags_.error("E0103", span(start, start + 2), "unterminated block comment",
                 "close it with '*/' (block comments nest)");
  }

  char peek(size_t ahead) const { return pos_ + ahead < text_.size() ? text_[pos_ + ahead] : '\0'; }

  Token make(Tok kind, size_t begin) {
    Token t;
    t.kind = kind;
    t.begin = uint32_t(begin);
    t.end = uint32_t(pos_);
    return t;
  }

  Token next() {
    size_t begin = pos_;
    char c = text_[pos_];
    if (isIdentStart(c)) {
      while (pos_ < text_.size() && isIdentChar(text_[pos_])) ++pos_;
      std::string_view word(text_.data() + begin, pos_ - begin);
      auto it = keywords().find(word);
      return make(it == keywords().end() ? Tok::Ident : it->second, begin);
    }
    if (isDigit(c)) return number();
    ++pos_;
    switch (c) {
      case '(': return make(Tok::LParen, begin);
      case ')': return make(Tok::RParen, begin);
      case '{': return make(Tok::LBrace, begin);
      case '}': return make(Tok::RBrace, begin);
      case ',': return make(Tok::Comma, begin);
      case ':': return make(Tok::Colon, begin);
      case ';': return make(Tok::Semi, begin);
      case '+': return make(Tok::Plus, begin);
      case '*': return make(Tok::Star, begin);
      case '/': return make(Tok::Slash, begin);
      case '%': return make(Tok::Percent, begin);
      case '~': return make(Tok::Tilde, begin);
      case '^': return make(Tok::Caret, begin);
      case '"': return stringLiteral(begin);
      case '.':
        if (isDigit(peek(0))) {
          while (pos_ < text_.size() && isIdentChar(text_[pos_])) ++pos_;
          diags_.error("E0104", span(begin, pos_), "malformed number literal",
                       "write a digit before the decimal point, e.g. 0.5");
          return make(Tok::Float, begin);  // a placeholder 0.0 keeps the parser quiet
        }
        return make(Tok::Dot, begin);
      case '-':
        if (peek(0) == '>') { ++pos_; return make(Tok::Arrow, begin); }
        return make(Tok::Minus, begin);
      case '=':
        if (peek(0) == '=') { ++pos_; return make(Tok::EqEq, begin); }
        return make(Tok::Assign, begin);
      case '!':
        if (peek(0) == '=') { ++pos_; return make(Tok::NotEq, begin); }
        return make(Tok::Bang, begin);
      case '<':
        if (peek(0) == '=') { ++pos_; return make(Tok::Le, begin); }
        if (peek(0) == '<') { ++pos_; return make(Tok::Shl, begin); }
        return make(Tok::Lt, begin);
      case '>':
        if (peek(0) == '=') { ++pos_; return make(Tok::Ge, begin); }
        if (peek(0) == '>') { ++pos_; return make(Tok::Shr, begin); }
        return make(Tok::Gt, begin);
      case '&':
        if (peek(0) == '&') { ++pos_; return make(Tok::AndAnd, begin); }
        return make(Tok::Amp, begin);
      case '|':
        if (peek(0) == '|') { ++pos_; return make(Tok::OrOr, begin); }
        return make(Tok::Pipe, begin);
      default: break;
    }
    // Anything else: skip the whole UTF-8 sequence (or one invalid byte) and report it,
    // unless the UTF-8 pass already did.
    auto* p = reinterpret_cast<const unsigned char*>(text_.data()) + begin;
    size_t n = utf8SequenceLength(p, reinterpret_cast<const unsigned char*>(text_.data()) + text_.size());
    pos_ = begin + (n == 0 ? 1 : n);
    if (n != 0) reportUnexpected(begin, c);
    return make(Tok::Error, begin);
  }

  void reportUnexpected(size_t begin, char c) {
    if (unexpectedReported_++ >= 20) return;
    std::string what;
    if (c == '\0') what = "NUL byte";
    else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "0x%02x", unsigned(static_cast<unsigned char>(c)));
      what = std::string("control character ") + hex;
    } else {
      what = "character '" + std::string(text_.substr(begin, pos_ - begin)) + "'";
    }
    diags_.error("E0102", span(begin, pos_), "unexpected " + what,
                 static_cast<unsigned char>(c) >= 0x80 ? "non-ASCII characters are allowed only in comments" : "");
  }

  // A string literal: one line, no escapes (a backslash is refused so that escapes can come
  // later without changing the meaning of existing programs).
  Token stringLiteral(size_t begin) {
    while (pos_ < text_.size() && text_[pos_] != '"' && text_[pos_] != '\n' && text_[pos_] != '\\') ++pos_;
    if (pos_ < text_.size() && text_[pos_] == '"') {
      ++pos_;
      return make(Tok::String, begin);
    }
    bool backslash = pos_ < text_.size() && text_[pos_] == '\\';
    diags_.error("E0106", span(begin, pos_), backslash ? "escape sequences are not supported in string literals"
                                                        : "unterminated string literal",
                 backslash ? "write paths with '/'" : "close the string with '\"' on the same line");
    while (pos_ < text_.size() && text_[pos_] != '"' && text_[pos_] != '\n') ++pos_;
    if (pos_ < text_.size() && text_[pos_] == '"') ++pos_;
    Token t = make(Tok::String, begin);
    t.intValue = 1;  // reported: later stages stay quiet about it
    return t;
  }

  // Number literals (docs/language.md section 1). Underscores group the digits of integer
  // literals and must sit between two digits (`1_000`, `0xff_ff`); `1_`, `1__0`, `0x_1`, `1_e5`
  // and any underscore in a float literal are E0104, as are `1.`, `1.e5` and `.5`.
  Token number() {
    size_t begin = pos_;
    std::string digits;
    const char* problem = nullptr;  // why the literal is malformed (its help text)
    const char* kMisplacedUnderscore = "an underscore must stand between two digits, as in 1_000 or 0xff_ff";
    // Reads digits and underscores; returns how many digits. `hex` selects the digit set.
    auto readDigits = [&](bool hex, bool& sawUnderscore) {
      auto digit = [&](char ch) { return hex ? isHexDigit(ch) : isDigit(ch); };
      size_t n = 0;
      while (pos_ < text_.size() && (digit(text_[pos_]) || text_[pos_] == '_')) {
        if (text_[pos_] == '_') {
          sawUnderscore = true;
          if (!(pos_ > begin && digit(text_[pos_ - 1]) && digit(peek(1))) && !problem) problem = kMisplacedUnderscore;
        } else {
          digits += text_[pos_];
          ++n;
        }
        ++pos_;
      }
      return n;
    };
    bool underscore = false;
    if (text_[pos_] == '0' && (peek(1) == 'x' || peek(1) == 'X')) {
      pos_ += 2;
      if (readDigits(true, underscore) == 0 && !problem) problem = "write hex digits after 0x, e.g. 0x2a";
      if (pos_ < text_.size() && isIdentChar(text_[pos_]) && !problem) problem = "numbers look like 42, 0x2a, 1_000, 1.5 or 2.5e-3";
      while (pos_ < text_.size() && isIdentChar(text_[pos_])) ++pos_;
      // A hex "float" (0x1.5, 0x1.8p3) is one malformed literal, not an Int and then a '.5'
      // that cascaded into a second error.
      if (peek(0) == '.' && (isHexDigit(peek(1)) || peek(1) == 'p' || peek(1) == 'P')) {
        ++pos_;
        while (pos_ < text_.size() && (isIdentChar(text_[pos_]) ||
                                       ((text_[pos_] == '+' || text_[pos_] == '-') && (text_[pos_ - 1] | 0x20) == 'p')))
          ++pos_;
        if (!problem) problem = "hex literals are integers; write a float in decimal, e.g. 1.3125";
      }
      if (problem) return malformedNumber(begin, problem);
      return intToken(begin, digits, 16);
    }
    readDigits(false, underscore);
    bool isFloat = false, fractionUnderscore = false;
    // A '.' followed by a letter is a field access on an Int (an error later), so only a '.'
    // followed by a digit (or nothing) belongs to the number; and `1.e5` is a float missing
    // the digits after its point.
    bool dotExponent = peek(0) == '.' && (peek(1) == 'e' || peek(1) == 'E') &&
                       (isDigit(peek(2)) || peek(2) == '+' || peek(2) == '-' || peek(2) == '_');
    if (pos_ < text_.size() && text_[pos_] == '.' && (!isIdentStart(peek(1)) || dotExponent)) {
      isFloat = true;
      digits += '.';
      ++pos_;
      if (readDigits(false, fractionUnderscore) == 0 && !problem)
        problem = "write a digit after the decimal point, e.g. 1.0 or 1.0e5";
    }
    if (pos_ < text_.size() && (text_[pos_] == 'e' || text_[pos_] == 'E')) {
      isFloat = true;
      digits += 'e';
      ++pos_;
      if (pos_ < text_.size() && (text_[pos_] == '+' || text_[pos_] == '-')) digits += text_[pos_++];
      if (readDigits(false, fractionUnderscore) == 0 && !problem) problem = "write the exponent's digits, e.g. 2.5e-3";
    }
    if (pos_ < text_.size() && isIdentChar(text_[pos_]) && !problem) problem = "numbers look like 42, 0x2a, 1_000, 1.5 or 2.5e-3";
    while (pos_ < text_.size() && isIdentChar(text_[pos_])) ++pos_;
    if (isFloat && (underscore || fractionUnderscore) && !problem)
      problem = "underscores group the digits of integer literals only; write float literals without them (1000.5)";
    if (problem) return malformedNumber(begin, problem);
    if (!isFloat) return intToken(begin, digits, 10);
    Token t = make(Tok::Float, begin);
    // strtof rounds correctly to binary32 and gives inf on overflow, as the spec says.
    t.floatValue = std::strtof(digits.c_str(), nullptr);
    return t;
  }

  Token malformedNumber(size_t begin, const char* help) {
    diags_.error("E0104", span(begin, pos_), "malformed number literal", help);
    return make(Tok::Float, begin);  // a placeholder 0.0 keeps the parser quiet
  }

  Token intToken(size_t begin, const std::string& digits, int base) {
    uint64_t value = 0;
    bool overflow = false;
    for (char d : digits) {
      int v = isDigit(d) ? d - '0' : (d | 0x20) - 'a' + 10;
      value = value * base + v;
      if (value > 0xFFFFFFFFull) { overflow = true; break; }
    }
    if (overflow || (base == 10 && value > 2147483648ull) || (base == 16 && value > 0x7FFFFFFFull)) {
      diags_.error("E0105", span(begin, pos_), "integer literal out of range",
                   "Int is 32-bit: from -2147483648 to 2147483647; use a Float literal for larger values");
      return make(Tok::Int, begin);  // a placeholder 0 keeps the parser quiet
    }
    Token t = make(Tok::Int, begin);
    t.intValue = int64_t(value);
    return t;
  }

  const SourceFile& file_;
  std::string_view text_;
  Diagnostics& diags_;
  size_t pos_ = 0;
  bool invalidUtf8_ = false;
  int unexpectedReported_ = 0;
};

}  // namespace

std::vector<Token> lex(const SourceFile& file, Diagnostics& diags) {
  if (file.text.size() > kMaxSourceBytes) {
    diags.error("E0107", Span{&file, 0, 0},
                "source file is " + std::to_string(file.text.size() >> 20) + " MiB; the limit is 64 MiB");
    Token end;
    return {end};
  }
  return Lexer(file, diags).run();
}

}  // namespace tex::lang
