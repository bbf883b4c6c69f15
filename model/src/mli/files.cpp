// MLI folder reading and writing: format detection, dispatch and the replace rule (see
// mli/files.h).
#include "simpli/model/mli/files.h"

#include <algorithm>
#include <system_error>

#include "mli/files_internal.h"
#include "simpli/error.h"
#include "simpli/model/io/staged_folder.h"
#include "simpli/model/scene/camera_checks.h"
#include "simpli/warning.h"

namespace simpli::mli {

namespace {

std::string quoted(const std::string& s) {
  return "\"" + s + "\"";
}

} // namespace

MLIFormat detectMLIFormat(const std::string& path) {
  return mli::readMeta(path).format;
}

MLI readMLI(const std::string& path, const MLIReadOptions& options) {
  const mli::Meta meta = mli::readMeta(path);
  for (const scene::CameraConcern& c : scene::cameraConcerns(meta.camera))
    warn(path, "/meta.json: \"intrinsics_re\" ", c.field, " = ", c.value, ": ", c.why);
  const mli::fs::path folder(path);
  // Every layer file is there and of the right size before memory for the layers is taken.
  for (const std::string& name : mliFileNames(meta.format, static_cast<int>(meta.ranges.size())))
    if (name != "meta.json")
      checkLayerFile(folder / name, meta.height, meta.width);
  MLI mli = meta.format == MLIFormat::Lossless ? mli::readLosslessLayers(folder, meta)
                                               : mli::readJpegLayers(folder, meta, options);
  // Everything was checked file by file; this guards the invariant for the caller.
  validateMLI(mli, "readMLI " + path);
  return mli;
}

std::string mliReplaceRefusal(const std::string& path, const MLIFolderExtras& extras) {
  const fs::path folder(path);
  std::error_code ec;
  if (!fs::is_regular_file(fs::symlink_status(folder / "meta.json", ec)))
    return "it is not an MLI folder (no meta.json)";
  Meta meta;
  try {
    meta = readMeta(folder);
  } catch (const Error& e) {
    return std::string("it is not a valid MLI (") + e.what() + ")";
  }
  if (!meta.writtenBySimpli)
    return std::string("its meta.json has no \"") + kWrittenByKey + "\": \"" + kWrittenByValue +
           "\" (not an MLI written by simpli)";
  const std::vector<std::string> own =
      mliFileNames(meta.format, static_cast<int>(meta.ranges.size()));
  fs::directory_iterator it(folder, ec), end;
  if (ec)
    return "its contents cannot be listed (" + ec.message() + ")";
  for (; it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    const fs::file_status status = it->symlink_status(ec);
    const bool file = fs::is_regular_file(status);
    const bool subfolder = fs::is_directory(status);
    if (file && std::find(own.begin(), own.end(), name) != own.end())
      continue;
    if (file && extras.isExtraFile && extras.isExtraFile(name))
      continue;
    if (subfolder && std::find(extras.mliFolders.begin(), extras.mliFolders.end(), name) !=
                         extras.mliFolders.end()) {
      // The subfolder must be one MLI written by simpli, with nothing of its own.
      const std::string why = mliReplaceRefusal(it->path().string(), {});
      if (!why.empty())
        return "its subfolder " + quoted(name) + " is not replaceable: " + why;
      continue;
    }
    return "it holds " + quoted(name) + ", which is not a file of the MLI simpli wrote there";
  }
  if (ec)
    return "its contents cannot be listed (" + ec.message() + ")";
  return "";
}

void writeMLIFiles(const std::string& folder, const MLI& mli, MLIFormat format) {
  validateMLI(mli, "writeMLI " + folder);
  if (format == MLIFormat::Lossless)
    mli::writeLosslessLayers(folder, mli);
  else
    mli::writeJpegLayers(folder, mli);
}

void writeMLI(const std::string& path, const MLI& mli, MLIFormat format) {
  // Before anything touches the disk: an invalid MLI creates no folder at all.
  validateMLI(mli, "writeMLI " + path);
  io::StagedFolder out(
      path, [](const fs::path& existing) { return mliReplaceRefusal(existing.string()); },
      {"writeMLI"});
  try {
    writeMLIFiles(out.path().string(), mli, format);
  } catch (const fs::filesystem_error& e) {
    fail("writeMLI: ", out.target().string(), ": ", e.what());
  }
  out.commit();
}

} // namespace simpli::mli
