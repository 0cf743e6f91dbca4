#include "cli/options.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace tex::cli {

int usageError(const char* command, const std::string& message) {
  std::fprintf(stderr, "tex %s: error: %s\n(run `tex %s --help` for usage)\n", command, message.c_str(), command);
  return 2;
}

bool takeValue(const Args& args, size_t& i, std::string& out) {
  if (i + 1 >= args.size()) return false;
  out = args[++i];
  return true;
}

bool parseInt(const std::string& text, int& value) {
  auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  return ec == std::errc() && ptr == text.data() + text.size() && !text.empty();
}

bool parseFloat(const std::string& text, float& value) {
  if (text.empty()) return false;
  char* end = nullptr;
  value = std::strtof(text.c_str(), &end);
  return end == text.c_str() + text.size() && std::isfinite(value);
}

bool parseSize(const std::string& text, int& width, int& height) {
  size_t x = text.find_first_of("xX");
  if (x == std::string::npos) return false;
  if (!parseInt(text.substr(0, x), width) || !parseInt(text.substr(x + 1), height)) return false;
  return width >= 1 && height >= 1 && width <= 32768 && height <= 32768;
}

}  // namespace tex::cli
