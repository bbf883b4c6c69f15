#include "simpli/model/io/files.h"

#include "simpli/error.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>

#include <unistd.h>

namespace fs = std::filesystem;

namespace simpli::io {

std::vector<unsigned char> readFileBytes(const std::string& path, const std::string& what) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status))
    fail(what, " '", path, "' does not exist");
  if (fs::is_directory(status))
    fail(what, " '", path, "' is a directory, expected a file");
  std::ifstream in(path, std::ios::binary);
  if (!in)
    fail("cannot open ", what, " '", path, "': ", std::strerror(errno));
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0)
    fail("cannot read ", what, " '", path, "'");
  in.seekg(0, std::ios::beg);
  std::vector<unsigned char> bytes(static_cast<size_t>(size));
  if (size > 0 && !in.read(reinterpret_cast<char*>(bytes.data()), size))
    fail("cannot read ", what, " '", path, "' (", size, " bytes expected)");
  return bytes;
}

void writeFileAtomically(const std::string& path, const void* bytes, size_t size) {
  const fs::path target(path);
  // Same directory as the target so that the rename cannot cross file systems; the pid keeps
  // concurrent writers of the same file apart.
  fs::path tmp = target;
  tmp += ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out)
      fail("cannot create '", tmp.string(), "' (writing '", path, "'): ", std::strerror(errno));
    out.write(static_cast<const char*>(bytes), static_cast<std::streamsize>(size));
    out.flush();
    if (!out) {
      out.close();
      std::error_code ignored;
      fs::remove(tmp, ignored);
      fail("cannot write '", path, "' (", size, " bytes)");
    }
  }
  std::error_code ec;
  fs::rename(tmp, target, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    fail("cannot rename '", tmp.string(), "' to '", path, "': ", ec.message());
  }
}

} // namespace simpli::io
