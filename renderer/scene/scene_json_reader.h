// Internal to the scene JSON loader: typed access to a located JSON document, where every
// problem becomes an error "file:line:column: where.in.file: what is wrong".
#pragma once
#include <cmath>
#include <initializer_list>
#include <string>
#include <vector>

#include "renderer/scene/json_located.h"
#include "renderer/scene/scene_description.h"

namespace tex::render {

// A JSON value (nullptr when absent) and its JSON pointer.
struct JsonAt {
  const nlohmann::json* j = nullptr;
  std::string pointer;
  explicit operator bool() const { return j != nullptr; }
};

class SceneJsonReader {
 public:
  SceneJsonReader(const LocatedJson& doc, std::string file, std::string baseDirectory, std::vector<std::string>& errors)
      : doc_(doc), file_(std::move(file)), baseDirectory_(std::move(baseDirectory)), errors_(errors) {}

  JsonAt root() const { return {&doc_.root, ""}; }
  JsonAt child(const JsonAt& object, const std::string& key) const;
  JsonAt element(const JsonAt& array, size_t index) const;

  // "file:line:column" of a value's key (or of the value when it has no key).
  std::string where(const JsonAt& at) const;
  void error(const JsonAt& at, const std::string& message);
  void warn(SceneDescription& scene, const JsonAt& at, const std::string& message) const;
  size_t errorCount() const { return errors_.size(); }

  // Type checks that report "expected an object, got a string".
  bool isObject(const JsonAt& at);
  bool isArray(const JsonAt& at);
  // Unknown keys are errors, with a suggestion for near misses; keys starting with '_' are comments.
  bool checkKeys(const JsonAt& object, std::initializer_list<const char*> allowed);
  // Keys starting with '_' are comments at any level (docs/scene-format.md).
  static bool isCommentKey(const std::string& key) { return !key.empty() && key[0] == '_'; }
  // The number of an object's keys that are not comments.
  static size_t keyCount(const JsonAt& object);

  // Optional members: `out` is unchanged when the key is absent; false on a wrong type or range.
  bool number(const JsonAt& object, const char* key, float& out, float min = -INFINITY, float max = INFINITY);
  bool integer(const JsonAt& object, const char* key, int& out, int min, int max);
  bool unsigned64(const JsonAt& object, const char* key, uint64_t& out);
  bool boolean(const JsonAt& object, const char* key, bool& out);
  bool string(const JsonAt& object, const char* key, std::string& out);
  bool vec3(const JsonAt& object, const char* key, Vec3& out);
  bool vector(const JsonAt& at, int minSize, int maxSize, std::vector<float>& out);  // the value itself

  // A file path relative to the scene file; error (at `at`) when the file does not exist.
  bool existingFile(const JsonAt& at, const std::string& relative, std::string& resolved);

  // Values with a structure of their own (scene_json_values.cpp).
  bool spectrum(const JsonAt& at, SpectrumDesc& out);
  bool transform(const JsonAt& at, Mat4& out);
  bool texParam(const JsonAt& at, TexParamValue& out);

  static std::string typeName(const nlohmann::json& j);

 private:
  std::string readablePath(const std::string& pointer) const;

  const LocatedJson& doc_;
  std::string file_, baseDirectory_;
  std::vector<std::string>& errors_;
};

}  // namespace tex::render
