// Parsing of option values shared by the develop, compare and demo commands: resolutions,
// sample counts with k/M/G suffixes, index ranges, seconds. Each returns false on bad input
// so the command can say which option was wrong.
#pragma once
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "runtime/index_range.h"

namespace tex::cli {

// "640x480" -> 640, 480 (each 1..65536).
inline bool parseResolution(const std::string& text, int& width, int& height) {
  const size_t x = text.find('x');
  if (x == std::string::npos || x == 0 || x + 1 >= text.size()) return false;
  char* end = nullptr;
  const long w = std::strtol(text.c_str(), &end, 10);
  if (end != text.c_str() + x) return false;
  const long h = std::strtol(text.c_str() + x + 1, &end, 10);
  if (*end != '\0' || w < 1 || h < 1 || w > 65536 || h > 65536) return false;
  width = int(w), height = int(h);
  return true;
}

inline bool parseUnsigned(const std::string& text, uint64_t& value);

// "1000", "4M", "2.5k", "1G" -> a count; also "2^20". Plain integers are read exactly (through a
// double they rounded above 2^53: a --range of 64-bit indices ran other samples than asked).
inline bool parseCount(const std::string& text, uint64_t& count) {
  if (parseUnsigned(text, count)) return true;
  if (text.size() > 2 && text.rfind("2^", 0) == 0) {
    char* end = nullptr;
    const long p = std::strtol(text.c_str() + 2, &end, 10);
    if (*end != '\0' || p < 0 || p > 62) return false;
    count = uint64_t(1) << p;
    return true;
  }
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (end == text.c_str()) return false;
  double scale = 1;
  const std::string suffix(end);
  if (suffix == "k" || suffix == "K") scale = 1e3;
  else if (suffix == "M" || suffix == "m") scale = 1e6;
  else if (suffix == "G" || suffix == "g") scale = 1e9;
  else if (!suffix.empty()) return false;
  const double total = value * scale;
  if (!(total >= 0) || total > 1.8e19 || total != std::floor(total)) return false;
  count = uint64_t(total);
  return true;
}

// A plain decimal integer 0..2^64-1, exactly (seeds: parseCount goes through a double, which
// rounds above 2^53).
inline bool parseUnsigned(const std::string& text, uint64_t& value) {
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos) return false;
  errno = 0;
  char* end = nullptr;
  const unsigned long long v = std::strtoull(text.c_str(), &end, 10);
  if (errno == ERANGE || *end != '\0') return false;
  value = uint64_t(v);
  return true;
}

// Whether two paths name one file (existing or not yet: through ./, .. and symlinks of their
// directories). Paths that cannot be resolved name no file in common.
inline bool samePath(const std::string& a, const std::string& b) {
  std::error_code ecA, ecB;
  const std::filesystem::path ca = std::filesystem::weakly_canonical(a, ecA), cb = std::filesystem::weakly_canonical(b, ecB);
  return !ecA && !ecB && ca == cb;
}

// Why an output file could not be written into its directory ("" if it can): checked before
// hours of rendering, not after.
inline std::string outputDirectoryProblem(const std::string& path) {
  std::filesystem::path dir = std::filesystem::path(path).parent_path();
  if (dir.empty()) dir = ".";
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return path + ": the directory '" + dir.string() + "' does not exist";
  if (::access(dir.c_str(), W_OK) != 0) return path + ": the directory '" + dir.string() + "' is not writable";
  // An existing output must be a writable file (a directory or a read-only file was found only
  // after the whole render).
  if (std::filesystem::exists(path, ec)) {
    if (std::filesystem::is_directory(path, ec)) return path + ": is a directory";
    if (::access(path.c_str(), W_OK) != 0) return path + ": the file is not writable";
  }
  return "";
}

// "A:B" -> [A, B) with A <= B.
inline bool parseIndexRange(const std::string& text, runtime::IndexRange& range) {
  const size_t colon = text.find(':');
  if (colon == std::string::npos) return false;
  uint64_t a = 0, b = 0;
  if (!parseCount(text.substr(0, colon), a) || !parseCount(text.substr(colon + 1), b) || b < a) return false;
  range = {a, b};
  return true;
}

inline bool parseSeconds(const std::string& text, double& seconds) {
  char* end = nullptr;
  seconds = std::strtod(text.c_str(), &end);
  return end != text.c_str() && *end == '\0' && seconds >= 0 && seconds < 1e9;
}

inline bool parseIntInRange(const std::string& text, int& value, int min, int max) {
  char* end = nullptr;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || v < min || v > max) return false;
  value = int(v);
  return true;
}

}  // namespace tex::cli
