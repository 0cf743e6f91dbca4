// JSON parsing that remembers where every key and value starts in the text, so scene-file
// errors can say "scene.json:12:5" (nlohmann-json 3.11 keeps no positions in its values).
#pragma once
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace tex::render {

struct LocatedJson {
  nlohmann::json root;
  std::string text;
  // By JSON pointer ("/lights/0/type"): byte offset of the value and of its key (objects).
  std::map<std::string, size_t> valueOffset, keyOffset;

  // "line:column" (1-based, column in characters) of a byte offset. Scans from the nearest
  // checkpoint (built on first use), not from the start: scene files with thousands of lights or
  // bindings asked for one position each, and loading took time quadratic in the file's size.
  std::string lineColumn(size_t offset) const;
  // Position of the key of `pointer` if it has one, else of its value, else "".
  std::string keyPosition(const std::string& pointer) const;
  std::string valuePosition(const std::string& pointer) const;

 private:
  static constexpr size_t kCheckpointBytes = 4096;
  struct LineColumn {
    size_t line = 1, column = 1;
  };
  mutable std::vector<LineColumn> checkpoints_;  // the position at byte k * kCheckpointBytes
};

// Parses `text`; on a syntax error returns nullopt and sets `error` to
// "line:column: what is wrong". Duplicate keys are errors too.
std::optional<LocatedJson> parseLocatedJson(std::string text, std::string& error);

// A JSON pointer segment for an object key (escapes '~' and '/').
std::string pointerSegment(const std::string& key);

}  // namespace tex::render
