// MLI folder reading and writing: format detection and dispatch (see mli/files.h).
#include "simpli/model/mli/files.h"

#include "mli/files_internal.h"
#include "simpli/error.h"

namespace simpli::mli {

MLIFormat detectMLIFormat(const std::string& path) {
  return mli::readMeta(path).format;
}

MLI readMLI(const std::string& path, const MLIReadOptions& options) {
  const mli::Meta meta = mli::readMeta(path);
  const mli::fs::path folder(path);
  MLI mli = meta.format == MLIFormat::Lossless ? mli::readLosslessLayers(folder, meta)
                                               : mli::readJpegLayers(folder, meta, options);
  // Everything was checked file by file; this guards the invariant for the caller.
  validateMLI(mli, "readMLI " + path);
  return mli;
}

void writeMLI(const std::string& path, const MLI& mli, MLIFormat format) {
  // Before anything touches the disk: an invalid MLI creates no folder at all.
  validateMLI(mli, "writeMLI " + path);
  mli::writeFolderAtomically(path, [&](const mli::fs::path& tmp) {
    if (format == MLIFormat::Lossless)
      mli::writeLosslessLayers(tmp, mli);
    else
      mli::writeJpegLayers(tmp, mli);
  });
}

} // namespace simpli::mli
