// Positions come from counting the characters nlohmann's lexer reads (through a counting
// iterator) and, at each SAX event, skipping from the end of the previous token over
// whitespace and separators to the start of the current one.
#include "renderer/scene/json_located.h"

#include <iterator>
#include <vector>

namespace tex::render {

namespace {

using json = nlohmann::json;

struct CountingIterator {
  using iterator_category = std::input_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;

  const char* p = nullptr;
  size_t* count = nullptr;

  reference operator*() const { return *p; }
  CountingIterator& operator++() {
    ++p;
    ++*count;
    return *this;
  }
  CountingIterator operator++(int) {
    CountingIterator old = *this;
    ++*this;
    return old;
  }
  bool operator==(const CountingIterator& o) const { return p == o.p; }
  bool operator!=(const CountingIterator& o) const { return p != o.p; }
};

class LocatingSax {
 public:
  LocatingSax(LocatedJson& out, const size_t& consumed) : out_(out), consumed_(consumed) {}

  bool null() { return scalar(nullptr); }
  bool boolean(bool v) { return scalar(v); }
  bool number_integer(json::number_integer_t v) { return scalar(v); }
  bool number_unsigned(json::number_unsigned_t v) { return scalar(v); }
  bool number_float(json::number_float_t v, const json::string_t&) { return scalar(v); }
  bool string(json::string_t& v) { return scalar(v); }
  bool binary(json::binary_t& v) { return scalar(json::binary(v)); }
  bool start_object(size_t) { return open(json::object()); }
  bool start_array(size_t) { return open(json::array()); }
  bool end_object() { return close(); }
  bool end_array() { return close(); }
  bool key(json::string_t& k) {
    const size_t start = tokenStart();
    Frame& frame = stack_.back();
    if (frame.node->contains(k)) {
      refusal_ = "duplicate key \"" + k + "\"";
      refusalOffset_ = start;
      return false;
    }
    frame.key = k;
    out_.keyOffset[frame.path + "/" + pointerSegment(k)] = start;
    lastEnd_ = consumed_;
    return true;
  }
  bool parse_error(size_t position, const std::string&, const nlohmann::detail::exception& e) {
    errorOffset_ = position > 0 ? position - 1 : 0;
    std::string message = e.what();
    // "[json.exception.parse_error.101] parse error at line 3, column 5: syntax error ..."
    const size_t column = message.find("column ");
    const size_t colon = column == std::string::npos ? std::string::npos : message.find(": ", column);
    errorMessage_ = colon == std::string::npos ? message : message.substr(colon + 2);
    return false;
  }

  std::string error() const {
    if (!refusal_.empty()) return out_.lineColumn(refusalOffset_) + ": " + refusal_;
    if (!errorMessage_.empty()) return out_.lineColumn(errorOffset_) + ": " + errorMessage_;
    return "";
  }

 private:
  struct Frame {
    json* node;
    std::string path;
    std::string key;  // objects: the key of the next value
    size_t nextIndex = 0;
  };

  size_t tokenStart() const {
    size_t i = lastEnd_;
    const std::string& t = out_.text;
    while (i < t.size() && (t[i] == ' ' || t[i] == '\t' || t[i] == '\n' || t[i] == '\r' || t[i] == ',' || t[i] == ':'))
      ++i;
    return i;
  }

  // Places a value in the current container; returns it and its pointer.
  json* place(json&& value, std::string& pointer) {
    if (stack_.empty()) {
      out_.root = std::move(value);
      pointer = "";
      return &out_.root;
    }
    Frame& frame = stack_.back();
    if (frame.node->is_object()) {
      pointer = frame.path + "/" + pointerSegment(frame.key);
      return &((*frame.node)[frame.key] = std::move(value));
    }
    pointer = frame.path + "/" + std::to_string(frame.nextIndex++);
    frame.node->push_back(std::move(value));
    return &frame.node->back();
  }

  bool scalar(json&& value) {
    const size_t start = tokenStart();
    std::string pointer;
    place(std::move(value), pointer);
    out_.valueOffset[pointer] = start;
    lastEnd_ = consumed_;
    return true;
  }
  // Scene files nest a few levels; each level keeps its JSON pointer, so a file nested 40000
  // deep took 3.3 GB before this limit.
  static constexpr size_t kMaxNesting = 128;
  bool open(json&& container) {
    const size_t start = tokenStart();
    if (stack_.size() >= kMaxNesting) {
      refusal_ = "arrays and objects nest more than " + std::to_string(kMaxNesting) + " levels deep";
      refusalOffset_ = start;
      return false;
    }
    std::string pointer;
    json* node = place(std::move(container), pointer);
    out_.valueOffset[pointer] = start;
    stack_.push_back(Frame{node, pointer, "", 0});
    lastEnd_ = consumed_;
    return true;
  }
  bool close() {
    stack_.pop_back();
    lastEnd_ = consumed_;
    return true;
  }

  LocatedJson& out_;
  const size_t& consumed_;
  size_t lastEnd_ = 0;
  std::vector<Frame> stack_;
  std::string refusal_, errorMessage_;
  size_t refusalOffset_ = 0, errorOffset_ = 0;
};

}  // namespace

std::string pointerSegment(const std::string& key) {
  std::string out;
  for (char c : key) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}

std::string LocatedJson::lineColumn(size_t offset) const {
  offset = std::min(offset, text.size());
  // A UTF-8 byte order mark is not a character of the first line.
  const size_t first = text.size() >= 3 && text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;
  const auto advance = [&](LineColumn& at, size_t from, size_t to) {
    for (size_t i = std::max(from, first); i < to; ++i) {
      if (text[i] == '\n') {
        ++at.line;
        at.column = 1;
      } else if ((static_cast<unsigned char>(text[i]) & 0xC0) != 0x80) {
        ++at.column;  // UTF-8 continuation bytes do not start a character
      }
    }
  };
  if (checkpoints_.empty()) {
    LineColumn at;
    checkpoints_.push_back(at);
    for (size_t k = 1; k * kCheckpointBytes <= text.size(); ++k) {
      advance(at, (k - 1) * kCheckpointBytes, k * kCheckpointBytes);
      checkpoints_.push_back(at);
    }
  }
  const size_t k = std::min(offset / kCheckpointBytes, checkpoints_.size() - 1);
  LineColumn at = checkpoints_[k];
  advance(at, k * kCheckpointBytes, offset);
  return std::to_string(at.line) + ":" + std::to_string(at.column);
}

std::string LocatedJson::keyPosition(const std::string& pointer) const {
  auto it = keyOffset.find(pointer);
  if (it != keyOffset.end()) return lineColumn(it->second);
  return valuePosition(pointer);
}

std::string LocatedJson::valuePosition(const std::string& pointer) const {
  auto it = valueOffset.find(pointer);
  return it == valueOffset.end() ? std::string() : lineColumn(it->second);
}

std::optional<LocatedJson> parseLocatedJson(std::string text, std::string& error) {
  LocatedJson out;
  out.text = std::move(text);
  size_t consumed = 0;
  LocatingSax sax(out, consumed);
  const char* begin = out.text.data();
  CountingIterator first{begin, &consumed}, last{begin + out.text.size(), &consumed};
  bool ok = false;
  try {
    ok = json::sax_parse(first, last, &sax);
  } catch (const std::exception& e) {
    error = std::string("1:1: ") + e.what();
    return std::nullopt;
  }
  if (!ok) {
    error = sax.error();
    if (error.empty()) error = "1:1: invalid JSON";
    return std::nullopt;
  }
  return out;
}

}  // namespace tex::render
