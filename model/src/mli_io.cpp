// MLI folder reading and writing: format detection and dispatch (see mli_io.h).
#include "simpli/model/mli_io.h"

#include "mli_io_internal.h"
#include "simpli/error.h"

namespace simpli {

MLIFormat detectMLIFormat(const std::string& path) {
  return mli_io::readMeta(path).format;
}

MLI readMLI(const std::string& path, const MLIReadOptions& options) {
  const mli_io::Meta meta = mli_io::readMeta(path);
  const mli_io::fs::path folder(path);
  MLI mli = meta.format == MLIFormat::Lossless ? mli_io::readLosslessLayers(folder, meta)
                                               : mli_io::readJpegLayers(folder, meta, options);
  // Everything was checked file by file; this guards the invariant for the caller.
  validateMLI(mli, "readMLI " + path);
  return mli;
}

void writeMLI(const std::string& path, const MLI& mli, MLIFormat format) {
  // Before anything touches the disk: an invalid MLI creates no folder at all.
  validateMLI(mli, "writeMLI " + path);
  mli_io::writeFolderAtomically(path, [&](const mli_io::fs::path& tmp) {
    if (format == MLIFormat::Lossless)
      mli_io::writeLosslessLayers(tmp, mli);
    else
      mli_io::writeJpegLayers(tmp, mli);
  });
}

} // namespace simpli
