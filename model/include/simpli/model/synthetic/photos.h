#pragma once
// Photographs as surface textures of the synthetic scenes (texture.h, Pattern::Photo).
//
// Where they come from: by default the DFSG-free photographs of Debian's `mate-backgrounds`
// and `plasma-workspace-wallpapers` packages (the list, with licences: debianPhotos() and
// docs/training_photos.md; scripts/install-photos.sh installs the packages), or every
// .jpg / .jpeg / .png file under a folder the caller names. Each photo is read once,
// downscaled so that its longer side is at most `maxSize` pixels and kept in memory as 8-bit
// RGB; PhotoLibrary::cached shares one library per (folder, size) in the process, so that
// scene generation never touches the disk after the first call.
#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace simpli::synthetic {

/// One photograph in memory: 8-bit RGB, row-major, height x width x 3.
struct Photo {
  std::string name; ///< file name without folder, e.g. "Garden.jpg"
  std::string path; ///< the file it was read from
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;

  /// RGB in [0, 1] at pixel coordinates (x, y) (pixel i covers [i, i + 1); its centre is
  /// i + 0.5): bilinear, continued beyond the edges by mirrored repetition, so any (x, y) is
  /// valid and the continued image has no seams.
  Eigen::Vector3d sample(double x, double y) const;
};

/// A photograph of the Debian packages that the default library uses.
struct DebianPhoto {
  const char* package; ///< Debian package
  const char* path;    ///< installed file
  const char* author;  ///< as /usr/share/doc/<package>/copyright (and the upstream metadata)
  const char* licence; ///< as /usr/share/doc/<package>/copyright
};

/// The photographs (not drawings or renders) of mate-backgrounds and
/// plasma-workspace-wallpapers that the default library reads (docs/training_photos.md).
const std::vector<DebianPhoto>& debianPhotos();

/// The Debian packages that hold debianPhotos().
const std::vector<std::string>& photoPackages();

/// The files a library for `dir` reads: "" = the debianPhotos() that are installed, in the
/// table's order; otherwise every .jpg / .jpeg / .png (any case) under `dir`, recursively,
/// sorted by path. Throws simpli::Error naming `dir` when it is given but is not a folder.
std::vector<std::string> findPhotoFiles(const std::string& dir);

/// One line telling the user how to install the default photographs (the script's path).
std::string photoInstallHint();

class PhotoLibrary {
public:
  /// Reads and downscales `files` (longer side <= maxSize, area averaging). Throws
  /// simpli::Error naming the file that cannot be read as an image, or for maxSize < 16.
  /// `source` names the collection in describe() (default: "N files").
  static std::shared_ptr<const PhotoLibrary>
  load(const std::vector<std::string>& files, int maxSize = 1024, const std::string& source = "");
  /// load(findPhotoFiles(dir), maxSize), done once per (dir, maxSize) in the process and
  /// shared afterwards (thread-safe). An empty library (no photos found) is cached too.
  static std::shared_ptr<const PhotoLibrary> cached(const std::string& dir, int maxSize = 1024);

  bool empty() const { return photos_.empty(); }
  size_t size() const { return photos_.size(); }
  const std::shared_ptr<const Photo>& photo(size_t index) const { return photos_.at(index); }
  int maxSize() const { return maxSize_; }
  double loadSeconds() const { return loadSeconds_; } ///< wall time of reading + downscaling
  const std::string& source() const { return source_; }
  /// "23 photos (<source>, <= 1024 px, 45 MB, read in 0.8 s)" or "no photos (<source>)".
  std::string describe() const;

private:
  std::vector<std::shared_ptr<const Photo>> photos_;
  int maxSize_ = 1024;
  double loadSeconds_ = 0;
  std::string source_;
};

} // namespace simpli::synthetic
