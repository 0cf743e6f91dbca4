// Source files, spans and diagnostics: the front end's shared vocabulary for locations.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace tex::lang {

// A loaded source file. Text is kept whole; line starts are computed once for line:col lookup.
struct SourceFile {
  std::string path;  // as given by the user or resolved by the module loader
  std::string text;
  std::vector<uint32_t> lineStarts;  // byte offset of each line's first byte

  SourceFile(std::string path, std::string text);
  struct LineCol {
    uint32_t line, col;  // 1-based; col counts code points
  };
  LineCol lineCol(uint32_t offset) const;
  std::string_view lineText(uint32_t line) const;  // without the newline
};

// A half-open byte range [begin, end) in one file.
struct Span {
  const SourceFile* file = nullptr;
  uint32_t begin = 0, end = 0;
};

enum class Severity { Error, Warning, Note };

struct Diagnostic {
  Severity severity = Severity::Error;
  std::string code;  // stable, e.g. "E0401" (docs/language.md section 7)
  Span span;
  std::string message;
  std::string help;  // optional actionable hint
  std::vector<std::pair<Span, std::string>> notes;  // related places ("opened here")
};

// Collects diagnostics in the order they are found.
class Diagnostics {
 public:
  Diagnostic& error(std::string code, Span span, std::string message, std::string help = {});
  void add(Diagnostic d) { items_.push_back(std::move(d)); }
  bool hasErrors() const;
  size_t size() const { return items_.size(); }
  const std::vector<Diagnostic>& items() const { return items_; }
  Diagnostic& at(size_t i) { return items_[i]; }
  void clear() { items_.clear(); }

 private:
  std::vector<Diagnostic> items_;
};

// Renders one diagnostic the way `tex check` prints it:
//   file:line:col: error[CODE]: message, the source line, a caret under the span, help.
std::string renderDiagnostic(const Diagnostic& d);

// Reads a whole file; returns false and sets `error` on failure.
bool readFile(const std::string& path, std::string& text, std::string& error);

}  // namespace tex::lang
