#include "lang/source.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace tex::lang {

SourceFile::SourceFile(std::string p, std::string t) : path(std::move(p)), text(std::move(t)) {
  lineStarts.push_back(0);
  for (uint32_t i = 0; i < text.size(); ++i)
    if (text[i] == '\n') lineStarts.push_back(i + 1);
}

static bool isContinuationByte(char c) { return (static_cast<unsigned char>(c) & 0xC0) == 0x80; }

SourceFile::LineCol SourceFile::lineCol(uint32_t offset) const {
  offset = std::min<uint32_t>(offset, uint32_t(text.size()));
  auto it = std::upper_bound(lineStarts.begin(), lineStarts.end(), offset);
  uint32_t line = uint32_t(it - lineStarts.begin());
  uint32_t start = lineStarts[line - 1];
  uint32_t col = 1;
  for (uint32_t i = start; i < offset; ++i)
    if (!isContinuationByte(text[i])) ++col;
  return {line, col};
}

std::string_view SourceFile::lineText(uint32_t line) const {
  if (line == 0 || line > lineStarts.size()) return {};
  uint32_t start = lineStarts[line - 1];
  uint32_t end = line < lineStarts.size() ? lineStarts[line] - 1 : uint32_t(text.size());
  std::string_view view(text.data() + start, end - start);
  if (!view.empty() && view.back() == '\r') view.remove_suffix(1);
  return view;
}

Diagnostic& Diagnostics::error(std::string code, Span span, std::string message, std::string help) {
  Diagnostic d;
  d.code = std::move(code);
  d.span = span;
  d.message = std::move(message);
  d.help = std::move(help);
  items_.push_back(std::move(d));
  return items_.back();
}

bool Diagnostics::hasErrors() const {
  return std::any_of(items_.begin(), items_.end(),
                     [](const Diagnostic& d) { return d.severity == Severity::Error; });
}

// Replaces control and non-printable bytes so a hostile line cannot garble the terminal.
static std::string printable(std::string_view s) {
  std::string out;
  for (unsigned char c : s) out += (c == '\t' || (c >= 0x20 && c != 0x7f)) ? char(c) : '?';
  return out;
}

static const char* severityName(Severity s) {
  switch (s) {
    case Severity::Error: return "error";
    case Severity::Warning: return "warning";
    case Severity::Note: return "note";
  }
  return "error";
}

static void renderSnippet(std::ostringstream& out, const Span& span) {
  if (!span.file) return;
  auto lc = span.file->lineCol(span.begin);
  std::string_view line = span.file->lineText(lc.line);
  if (line.size() > 400) return;  // a caret under a huge line helps nobody
  std::string num = std::to_string(lc.line);
  std::string pad(num.size(), ' ');
  out << ' ' << num << " | " << printable(line) << '\n';
  out << ' ' << pad << " | ";
  for (uint32_t c = 1; c < lc.col; ++c) out << (c - 1 < line.size() && line[c - 1] == '\t' ? '\t' : ' ');
  uint32_t endOnLine = std::min<uint32_t>(span.end, span.file->lineStarts[lc.line - 1] + uint32_t(line.size()));
  uint32_t width = endOnLine > span.begin ? span.file->lineCol(endOnLine).col - lc.col : 1;
  out << std::string(std::max<uint32_t>(1, std::min<uint32_t>(width, 200)), '^') << '\n';
}

std::string renderDiagnostic(const Diagnostic& d) {
  std::ostringstream out;
  if (d.span.file) {
    auto lc = d.span.file->lineCol(d.span.begin);
    out << d.span.file->path << ':' << lc.line << ':' << lc.col << ": ";
  }
  out << severityName(d.severity);
  if (!d.code.empty()) out << '[' << d.code << ']';
  out << ": " << d.message << '\n';
  renderSnippet(out, d.span);
  for (const auto& [span, text] : d.notes) {
    if (span.file) {
      auto lc = span.file->lineCol(span.begin);
      out << span.file->path << ':' << lc.line << ':' << lc.col << ": ";
    }
    out << "note: " << text << '\n';
    renderSnippet(out, span);
  }
  if (!d.help.empty()) out << "help: " << d.help << '\n';
  return out.str();
}

bool readFile(const std::string& path, std::string& text, std::string& error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    error = "cannot open '" + path + "'";
    return false;
  }
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) {
    error = "cannot read '" + path + "'";
    return false;
  }
  text = buffer.str();
  return true;
}

}  // namespace tex::lang
