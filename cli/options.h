// Small helpers for parsing subcommand flags with clear errors.
#pragma once
#include <string>
#include <vector>

#include "cli/command.h"

namespace tex::cli {

// Reports a usage error as `tex <command>: error: ...` and returns exit status 2.
int usageError(const char* command, const std::string& message);

// The value after flag args[i]: advances i and sets `out`, or returns false at the end.
bool takeValue(const Args& args, size_t& i, std::string& out);

// Parses "WxH" with 1 <= W, H <= 32768; false on malformed input.
bool parseSize(const std::string& text, int& width, int& height);
// Parses a whole decimal int / float; false on junk.
bool parseInt(const std::string& text, int& value);
bool parseFloat(const std::string& text, float& value);

}  // namespace tex::cli
