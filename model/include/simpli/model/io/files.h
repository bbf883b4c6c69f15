#pragma once
// Whole-file reading and atomic writing, shared by the readers and writers in model/.
#include <string>
#include <vector>

namespace simpli::io {

/// Reads a whole file. `what` describes it in errors ("image", "poses file", ...); throws
/// simpli::Error naming the file when it is missing, a directory, or unreadable.
std::vector<unsigned char> readFileBytes(const std::string& path, const std::string& what);

/// Writes `bytes` to a temporary file beside `path`, then renames it over `path`, so that a
/// reader never sees a partial file and a failed write leaves no output. Throws simpli::Error.
void writeFileAtomically(const std::string& path, const void* bytes, size_t size);

} // namespace simpli::io
