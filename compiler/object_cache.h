// Internal to compiler/: the on-disk cache of compiled object code (docs/abi.md, "Cache").
// An entry is a file named by the key's hash holding the full key (verified on load), the
// payload's length and checksum, then the payload: the module's object files (one, or two when
// code generation was split across threads), each with its length. Writes are atomic (temp file + rename).
#pragma once
#include <string>
#include <vector>

namespace tex::compiler {

std::string cacheDirectory(const std::string& configured);

enum class CacheLookup { Miss, Hit, Rejected };

// On Hit, `objects` holds the verified object files. Rejected: an entry existed but was corrupt,
// truncated or for another key (it is left for store() to replace).
CacheLookup loadCachedObjects(const std::string& directory, const std::string& key, std::vector<std::string>& objects);

// Best effort: a cache that cannot be written is not an error (returns false).
bool storeCachedObjects(const std::string& directory, const std::string& key, const std::vector<std::string>& objects);

std::string cacheFilePath(const std::string& directory, const std::string& key);

}  // namespace tex::compiler
