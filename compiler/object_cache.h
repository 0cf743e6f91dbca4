// Internal to compiler/: the on-disk cache of compiled object code (docs/abi.md, "Cache").
// An entry is a file named by the key's hash holding the full key (verified on load), the
// object's length and checksum, then the object. Writes are atomic (temp file + rename).
#pragma once
#include <string>

namespace tex::compiler {

std::string cacheDirectory(const std::string& configured);

enum class CacheLookup { Miss, Hit, Rejected };

// On Hit, `object` holds the verified object code. Rejected: an entry existed but was corrupt,
// truncated or for another key (it is left for store() to replace).
CacheLookup loadCachedObject(const std::string& directory, const std::string& key, std::string& object);

// Best effort: a cache that cannot be written is not an error (returns false).
bool storeCachedObject(const std::string& directory, const std::string& key, const std::string& object);

std::string cacheFilePath(const std::string& directory, const std::string& key);

}  // namespace tex::compiler
