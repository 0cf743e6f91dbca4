#include "renderer/scene/scene_json_reader.h"

#include <algorithm>
#include <filesystem>

namespace tex::render {

namespace {

size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

}  // namespace

JsonAt SceneJsonReader::child(const JsonAt& object, const std::string& key) const {
  if (!object || !object.j->is_object()) return {nullptr, object.pointer + "/" + pointerSegment(key)};
  auto it = object.j->find(key);
  return {it == object.j->end() ? nullptr : &*it, object.pointer + "/" + pointerSegment(key)};
}

JsonAt SceneJsonReader::element(const JsonAt& array, size_t index) const {
  const std::string pointer = array.pointer + "/" + std::to_string(index);
  if (!array || !array.j->is_array() || index >= array.j->size()) return {nullptr, pointer};
  return {&(*array.j)[index], pointer};
}

std::string SceneJsonReader::readablePath(const std::string& pointer) const {
  // "/lights/0/type" -> "lights[0].type"
  std::string out;
  size_t start = 1;
  while (start <= pointer.size() && !pointer.empty()) {
    size_t end = pointer.find('/', start);
    if (end == std::string::npos) end = pointer.size();
    std::string segment = pointer.substr(start, end - start);
    const bool index = !segment.empty() && std::all_of(segment.begin(), segment.end(), ::isdigit);
    out += index ? "[" + segment + "]" : (out.empty() ? "" : ".") + segment;
    start = end + 1;
  }
  return out;
}

std::string SceneJsonReader::where(const JsonAt& at) const {
  // Absent values: point at the nearest enclosing value that exists.
  std::string pointer = at.pointer;
  std::string position = doc_.keyPosition(pointer);
  while (position.empty() && !pointer.empty()) {
    pointer = pointer.substr(0, pointer.find_last_of('/'));
    position = doc_.keyPosition(pointer);
  }
  return file_ + (position.empty() ? "" : ":" + position);
}

void SceneJsonReader::error(const JsonAt& at, const std::string& message) {
  const std::string path = readablePath(at.pointer);
  errors_.push_back(where(at) + ": " + (path.empty() ? "" : path + ": ") + message);
}

void SceneJsonReader::warn(SceneDescription& scene, const JsonAt& at, const std::string& message) const {
  const std::string path = readablePath(at.pointer);
  scene.warnings.push_back(where(at) + ": " + (path.empty() ? "" : path + ": ") + message);
}

std::string SceneJsonReader::typeName(const nlohmann::json& j) {
  switch (j.type()) {
    case nlohmann::json::value_t::null: return "null";
    case nlohmann::json::value_t::boolean: return "a boolean";
    case nlohmann::json::value_t::number_integer:
    case nlohmann::json::value_t::number_unsigned:
    case nlohmann::json::value_t::number_float: return "a number";
    case nlohmann::json::value_t::string: return "a string";
    case nlohmann::json::value_t::array: return "an array";
    case nlohmann::json::value_t::object: return "an object";
    default: return "binary data";
  }
}

bool SceneJsonReader::isObject(const JsonAt& at) {
  if (at && at.j->is_object()) return true;
  error(at, std::string("expected an object, got ") + (at ? typeName(*at.j) : "nothing"));
  return false;
}

bool SceneJsonReader::isArray(const JsonAt& at) {
  if (at && at.j->is_array()) return true;
  error(at, std::string("expected an array, got ") + (at ? typeName(*at.j) : "nothing"));
  return false;
}

size_t SceneJsonReader::keyCount(const JsonAt& object) {
  size_t n = 0;
  for (auto it = object.j->begin(); it != object.j->end(); ++it) n += !isCommentKey(it.key());
  return n;
}

bool SceneJsonReader::checkKeys(const JsonAt& object, std::initializer_list<const char*> allowed) {
  if (!isObject(object)) return false;
  bool ok = true;
  for (auto it = object.j->begin(); it != object.j->end(); ++it) {
    const std::string& key = it.key();
    if (isCommentKey(key)) continue;
    if (std::any_of(allowed.begin(), allowed.end(), [&](const char* a) { return key == a; })) continue;
    std::string best;
    size_t bestDistance = 3;
    for (const char* a : allowed) {
      const size_t d = editDistance(key, a);
      if (d < bestDistance) bestDistance = d, best = a;
    }
    std::string message = "unknown key \"" + key + "\"";
    if (!best.empty()) message += "; did you mean \"" + best + "\"?";
    else {
      message += " (allowed:";
      for (const char* a : allowed) message += std::string(" ") + a;
      message += ")";
    }
    error(child(object, key), message);
    ok = false;
  }
  return ok;
}

bool SceneJsonReader::number(const JsonAt& object, const char* key, float& out, float min, float max) {
  const JsonAt at = child(object, key);
  if (!at) return true;
  if (!at.j->is_number()) return error(at, "expected a number, got " + typeName(*at.j)), false;
  const double v = at.j->get<double>();
  if (std::isfinite(v) && !std::isfinite(float(v)))
    return error(at, "is beyond the range of a 32-bit float (about 3.4e38)"), false;
  // Compared as the float it becomes: a documented bound written in the file (fov_deg 0.001)
  // is the float bound, whatever the double's last digits.
  if (!std::isfinite(v) || float(v) < min || float(v) > max) {
    const auto text = [](float x) {
      char buf[32];
      std::snprintf(buf, sizeof(buf), "%g", double(x));
      return std::string(buf);
    };
    // A tiny positive minimum (1e-30) stands for "greater than 0".
    const std::string lower = min > 0.0f && min <= 1e-20f ? "> 0 (at least " + text(min) + ")" : ">= " + text(min);
    std::string range = std::isinf(max) ? lower : "in [" + text(min) + ", " + text(max) + "]";
    if (min > 0.0f && min <= 1e-20f && !std::isinf(max)) range = "in (0, " + text(max) + "]";
    if (std::isinf(min) && std::isinf(max)) range = "finite";
    return error(at, "must be " + range), false;
  }
  out = float(v);
  return true;
}

bool SceneJsonReader::integer(const JsonAt& object, const char* key, int& out, int min, int max) {
  const JsonAt at = child(object, key);
  if (!at) return true;
  if (!at.j->is_number_integer()) return error(at, "expected an integer, got " + typeName(*at.j)), false;
  const int64_t v = at.j->is_number_unsigned() ? int64_t(std::min<uint64_t>(at.j->get<uint64_t>(), INT64_MAX))
                                                : at.j->get<int64_t>();
  if (v < min || v > max)
    return error(at, "must be in [" + std::to_string(min) + ", " + std::to_string(max) + "]"), false;
  out = int(v);
  return true;
}

bool SceneJsonReader::unsigned64(const JsonAt& object, const char* key, uint64_t& out) {
  const JsonAt at = child(object, key);
  if (!at) return true;
  if (!at.j->is_number_unsigned()) return error(at, "expected a non-negative integer, got " + typeName(*at.j)), false;
  out = at.j->get<uint64_t>();
  return true;
}

bool SceneJsonReader::boolean(const JsonAt& object, const char* key, bool& out) {
  const JsonAt at = child(object, key);
  if (!at) return true;
  if (!at.j->is_boolean()) return error(at, "expected true or false, got " + typeName(*at.j)), false;
  out = at.j->get<bool>();
  return true;
}

bool SceneJsonReader::string(const JsonAt& object, const char* key, std::string& out) {
  const JsonAt at = child(object, key);
  if (!at) return true;
  if (!at.j->is_string()) return error(at, "expected a string, got " + typeName(*at.j)), false;
  out = at.j->get<std::string>();
  return true;
}

bool SceneJsonReader::vector(const JsonAt& at, int minSize, int maxSize, std::vector<float>& out) {
  const std::string sizes = minSize == maxSize ? std::to_string(minSize) : std::to_string(minSize) + " to " + std::to_string(maxSize);
  if (!at.j->is_array() || at.j->size() < size_t(minSize) || at.j->size() > size_t(maxSize))
    return error(at, "expected an array of " + sizes + " numbers, got " +
                         (at.j->is_array() ? std::to_string(at.j->size()) + " elements" : typeName(*at.j))),
           false;
  out.clear();
  for (size_t i = 0; i < at.j->size(); ++i) {
    const auto& e = (*at.j)[i];
    if (!e.is_number() || !std::isfinite(e.get<double>()))
      return error(element(at, i), "expected a finite number, got " + typeName(e)), false;
    if (!std::isfinite(float(e.get<double>())))  // 1e39 is finite as JSON, not as a float
      return error(element(at, i), "is beyond the float range (about 3.4e38)"), false;
    out.push_back(float(e.get<double>()));
  }
  return true;
}

bool SceneJsonReader::vec3(const JsonAt& object, const char* key, Vec3& out) {
  const JsonAt at = child(object, key);
  if (!at) return true;
  std::vector<float> v;
  if (!vector(at, 3, 3, v)) return false;
  out = Vec3(v[0], v[1], v[2]);
  return true;
}

bool SceneJsonReader::existingFile(const JsonAt& at, const std::string& relative, std::string& resolved) {
  namespace fs = std::filesystem;
  fs::path p(relative);
  if (p.is_relative()) p = fs::path(baseDirectory_) / p;
  resolved = p.lexically_normal().string();
  std::error_code ec;
  if (!fs::is_regular_file(p, ec)) {
    error(at, "file \"" + relative + "\" not found (looked for " + resolved + ")");
    return false;
  }
  return true;
}

}  // namespace tex::render
