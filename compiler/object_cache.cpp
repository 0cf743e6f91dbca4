#include "compiler/object_cache.h"

#include <llvm/Support/xxhash.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

namespace fs = std::filesystem;

namespace tex::compiler {

namespace {

constexpr char kMagic[8] = {'T', 'E', 'X', 'O', 'B', 'J', '2', '\n'};

uint64_t hash64(const std::string& s) {
  return llvm::xxh3_64bits(llvm::ArrayRef<uint8_t>(reinterpret_cast<const uint8_t*>(s.data()), s.size()));
}

std::string hex(uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

void putU64(std::string& out, uint64_t v) {
  for (int i = 0; i < 8; ++i) out += char((v >> (8 * i)) & 0xff);
}

bool getU64(const std::string& in, size_t& at, uint64_t& v) {
  if (at + 8 > in.size()) return false;
  v = 0;
  for (int i = 0; i < 8; ++i) v |= uint64_t(uint8_t(in[at + size_t(i)])) << (8 * i);
  at += 8;
  return true;
}

// The payload: the number of objects, then each one's length and bytes.
std::string packObjects(const std::vector<std::string>& objects) {
  std::string out;
  putU64(out, objects.size());
  for (const std::string& o : objects) {
    putU64(out, o.size());
    out += o;
  }
  return out;
}

bool unpackObjects(const std::string& in, std::vector<std::string>& objects) {
  size_t at = 0;
  uint64_t count = 0;
  if (!getU64(in, at, count) || count == 0 || count > 64) return false;
  objects.clear();
  for (uint64_t i = 0; i < count; ++i) {
    uint64_t length = 0;
    if (!getU64(in, at, length) || length > in.size() - at) return false;
    objects.push_back(in.substr(at, length));
    at += length;
  }
  return at == in.size();
}

}  // namespace

std::string cacheDirectory(const std::string& configured) {
  if (!configured.empty()) return configured;
  if (const char* env = std::getenv("TEX_CACHE_DIR"); env && *env) return env;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return (fs::path(xdg) / "tex" / "jit").string();
  if (const char* home = std::getenv("HOME"); home && *home) return (fs::path(home) / ".cache" / "tex" / "jit").string();
  return (fs::temp_directory_path() / "tex-cache" / "jit").string();
}

std::string cacheFilePath(const std::string& directory, const std::string& key) {
  return (fs::path(directory) / (hex(hash64(key)) + ".texobj")).string();
}

CacheLookup loadCachedObjects(const std::string& directory, const std::string& key, std::vector<std::string>& objects) {
  std::ifstream in(cacheFilePath(directory, key), std::ios::binary);
  if (!in) return CacheLookup::Miss;
  std::ostringstream buffer;
  buffer << in.rdbuf();
  std::string data = buffer.str();
  size_t at = sizeof kMagic;
  uint64_t keyLength = 0, objectLength = 0, objectHash = 0;
  if (data.size() < sizeof kMagic || std::memcmp(data.data(), kMagic, sizeof kMagic) != 0) return CacheLookup::Rejected;
  if (!getU64(data, at, keyLength) || keyLength > data.size() - at) return CacheLookup::Rejected;
  if (data.compare(at, keyLength, key) != 0 || keyLength != key.size()) return CacheLookup::Rejected;
  at += keyLength;
  if (!getU64(data, at, objectLength) || !getU64(data, at, objectHash)) return CacheLookup::Rejected;
  if (objectLength != data.size() - at) return CacheLookup::Rejected;  // truncated or padded
  std::string payload = data.substr(at);
  if (hash64(payload) != objectHash) return CacheLookup::Rejected;
  if (!unpackObjects(payload, objects)) return CacheLookup::Rejected;
  return CacheLookup::Hit;
}

bool storeCachedObjects(const std::string& directory, const std::string& key, const std::vector<std::string>& objects) {
  const std::string payload = packObjects(objects);
  std::error_code ec;
  fs::create_directories(directory, ec);
  if (ec) return false;
  std::string data(kMagic, sizeof kMagic);
  putU64(data, key.size());
  data += key;
  putU64(data, payload.size());
  putU64(data, hash64(payload));
  data += payload;
  static std::atomic<uint64_t> counter{0};
  std::string target = cacheFilePath(directory, key);
  std::string temp = target + ".tmp." + std::to_string(getpid()) + "." + std::to_string(counter++);
  {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    if (!out) return false;
    out.write(data.data(), std::streamsize(data.size()));
    if (!out) {
      out.close();
      fs::remove(temp, ec);
      return false;
    }
  }
  fs::rename(temp, target, ec);  // atomic on POSIX: readers see the old or the new file
  if (ec) fs::remove(temp, ec);
  return !ec;
}

}  // namespace tex::compiler
