// Photographs for the synthetic scenes' textures (see synthetic/photos.h).
#include "simpli/model/synthetic/photos.h"

#include "simpli/error.h"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>

namespace fs = std::filesystem;

namespace simpli::synthetic {

namespace {

// Mirrored repetition of integer pixel index i over [0, n): ... 1 0 | 0 1 .. n-1 | n-1 n-2 ...
int mirrorIndex(int64_t i, int n) {
  const int64_t period = 2 * int64_t(n);
  int64_t m = i % period;
  if (m < 0)
    m += period;
  return int(m < n ? m : period - 1 - m);
}

constexpr const char* kMate = "mate-backgrounds";
constexpr const char* kPlasma = "plasma-workspace-wallpapers";
constexpr const char* kMateLicence = "GPL-2+";
constexpr const char* kPlasmaLicence =
    "GPL-2+ (debian/copyright, Files: *, 2014 KDE Visual Design Group; upstream "
    "metadata.json: LGPLv3)";

std::string lowerExtension(const fs::path& p) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return e;
}

} // namespace

Eigen::Vector3d Photo::sample(double x, double y) const {
  if (width <= 0 || height <= 0)
    fail("Photo::sample: photo '", name, "' is empty");
  // Bilinear between the four nearest pixel centres.
  const double fx = x - 0.5, fy = y - 0.5;
  const double x0f = std::floor(fx), y0f = std::floor(fy);
  const double tx = fx - x0f, ty = fy - y0f;
  const int64_t x0 = int64_t(x0f), y0 = int64_t(y0f);
  const int xa = mirrorIndex(x0, width), xb = mirrorIndex(x0 + 1, width);
  const int ya = mirrorIndex(y0, height), yb = mirrorIndex(y0 + 1, height);
  const auto px = [&](int xi, int yi, int c) {
    return double(rgb[(size_t(yi) * size_t(width) + size_t(xi)) * 3 + size_t(c)]);
  };
  Eigen::Vector3d out;
  for (int c = 0; c < 3; ++c) {
    const double top = px(xa, ya, c) + (px(xb, ya, c) - px(xa, ya, c)) * tx;
    const double bottom = px(xa, yb, c) + (px(xb, yb, c) - px(xa, yb, c)) * tx;
    out[c] = (top + (bottom - top) * ty) * (1.0 / 255.0);
  }
  return out;
}

const std::vector<DebianPhoto>& debianPhotos() {
  static const std::vector<DebianPhoto> photos{
      {kMate, "/usr/share/backgrounds/mate/nature/Aqua.jpg", "Charles Barbin", kMateLicence},
      {kMate, "/usr/share/backgrounds/mate/nature/Blinds.jpg", "Lennart Poettering, Andrea Cimitan",
       kMateLicence},
      {kMate, "/usr/share/backgrounds/mate/nature/Dune.jpg", "Marco Cogoni, Hylke Bons",
       kMateLicence},
      {kMate, "/usr/share/backgrounds/mate/nature/FreshFlower.jpg", "Jens Ansorg", kMateLicence},
      {kMate, "/usr/share/backgrounds/mate/nature/Garden.jpg", "Charles Barbin", kMateLicence},
      {kMate, "/usr/share/backgrounds/mate/nature/GreenMeadow.jpg",
       "Timothy Schellhase, Lapo Calamandrei", kMateLicence},
      {kMate, "/usr/share/backgrounds/mate/nature/LadyBird.jpg", "Charles Barbin", kMateLicence},
      {kMate, "/usr/share/backgrounds/mate/nature/RainDrops.jpg", "\"blackcombwhistler07\"",
       kMateLicence},
      {kMate, "/usr/share/backgrounds/mate/nature/Storm.jpg", "Sergey Nazarov", kMateLicence},
      {kMate, "/usr/share/backgrounds/mate/nature/TwoWings.jpg", "Charles Barbin, Hylke Bons",
       kMateLicence},
      {kMate, "/usr/share/backgrounds/mate/nature/Wood.jpg", "Jean-Francois Fortin Tam",
       kMateLicence},
      {kMate, "/usr/share/backgrounds/mate/nature/YellowFlower.jpg", "Charles Barbin",
       kMateLicence},
      {kPlasma, "/usr/share/wallpapers/BytheWater/contents/images/2560x1600.jpg", "Maciej Wiklo",
       kPlasmaLicence},
      {kPlasma, "/usr/share/wallpapers/ColdRipple/contents/images/2560x1600.jpg", "Risto Saukonpaa",
       kPlasmaLicence},
      {kPlasma, "/usr/share/wallpapers/ColorfulCups/contents/images/2560x1600.jpg", "Dmitri Popov",
       kPlasmaLicence},
      {kPlasma, "/usr/share/wallpapers/DarkestHour/contents/images/2560x1600.jpg",
       "Risto Saukonpaa", kPlasmaLicence},
      {kPlasma, "/usr/share/wallpapers/EveningGlow/contents/images/2560x1600.jpg", "Ian Hex",
       kPlasmaLicence},
      {kPlasma, "/usr/share/wallpapers/FallenLeaf/contents/images/2560x1600.jpg", "Martin Klapetek",
       kPlasmaLicence},
      {kPlasma, "/usr/share/wallpapers/Grey/contents/images/2560x1600.jpg", "Sigi Sagi",
       kPlasmaLicence},
      {kPlasma, "/usr/share/wallpapers/Kite/contents/images/2560x1600.jpg", "Risto Saukonpaa",
       kPlasmaLicence},
      {kPlasma, "/usr/share/wallpapers/OneStandsOut/contents/images/2560x1600.jpg",
       "Risto Saukonpaa", kPlasmaLicence},
      {kPlasma, "/usr/share/wallpapers/Path/contents/images/2560x1600.jpg", "Risto Saukonpaa",
       kPlasmaLicence},
      {kPlasma, "/usr/share/wallpapers/summer_1am/contents/images/2560x1600.jpg", "Risto Saukonpaa",
       kPlasmaLicence},
  };
  return photos;
}

const std::vector<std::string>& photoPackages() {
  static const std::vector<std::string> packages{kMate, kPlasma};
  return packages;
}

std::vector<std::string> findPhotoFiles(const std::string& dir) {
  std::vector<std::string> files;
  std::error_code ec;
  if (dir.empty()) {
    for (const DebianPhoto& p : debianPhotos())
      if (fs::is_regular_file(p.path, ec))
        files.emplace_back(p.path);
    return files;
  }
  if (!fs::is_directory(dir, ec))
    fail("photo folder '", dir, "': ", fs::exists(dir, ec) ? "not a folder" : "does not exist");
  for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::end(it);
       it.increment(ec)) {
    if (!it->is_regular_file(ec))
      continue;
    const std::string e = lowerExtension(it->path());
    if (e == ".jpg" || e == ".jpeg" || e == ".png")
      files.push_back(it->path().string());
  }
  if (ec)
    fail("photo folder '", dir, "': ", ec.message());
  std::sort(files.begin(), files.end());
  return files;
}

std::string photoInstallHint() {
  return "install the photographs with " + std::string(SIMPLI_SOURCE_DIR) +
         "/scripts/install-photos.sh (apt-get install mate-backgrounds "
         "plasma-workspace-wallpapers; docs/training_photos.md)";
}

std::shared_ptr<const PhotoLibrary> PhotoLibrary::load(const std::vector<std::string>& files,
                                                       int maxSize, const std::string& source) {
  if (maxSize < 16)
    fail("photo library: maximum size ", maxSize, " must be >= 16 pixels");
  const auto start = std::chrono::steady_clock::now();
  auto lib = std::make_shared<PhotoLibrary>();
  lib->maxSize_ = maxSize;
  lib->source_ = source.empty() ? std::to_string(files.size()) + " files" : source;
  for (const std::string& file : files) {
    // JPEG decoding can halve the size on the fly at a quarter of the cost: take that when
    // the half size still reaches maxSize, else decode in full.
    const int flags = cv::IMREAD_IGNORE_ORIENTATION;
    cv::Mat bgr = cv::imread(file, cv::IMREAD_REDUCED_COLOR_2 | flags);
    if (bgr.empty() || std::max(bgr.cols, bgr.rows) < maxSize)
      bgr = cv::imread(file, cv::IMREAD_COLOR | flags);
    if (bgr.empty() || bgr.cols < 1 || bgr.rows < 1)
      fail("photo '", file, "': cannot be read as an image");
    const int longer = std::max(bgr.cols, bgr.rows);
    if (longer > maxSize) {
      const double f = double(maxSize) / double(longer);
      cv::resize(bgr, bgr,
                 cv::Size(std::max(1, int(std::lround(bgr.cols * f))),
                          std::max(1, int(std::lround(bgr.rows * f)))),
                 0, 0, cv::INTER_AREA);
    }
    cv::Mat rgb;
    cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
    auto photo = std::make_shared<Photo>();
    photo->name = fs::path(file).filename().string();
    photo->path = file;
    photo->width = rgb.cols;
    photo->height = rgb.rows;
    photo->rgb.resize(size_t(rgb.cols) * size_t(rgb.rows) * 3);
    for (int y = 0; y < rgb.rows; ++y)
      std::copy(rgb.ptr<uint8_t>(y), rgb.ptr<uint8_t>(y) + size_t(rgb.cols) * 3,
                photo->rgb.begin() + ptrdiff_t(size_t(y) * size_t(rgb.cols) * 3));
    lib->photos_.push_back(std::move(photo));
  }
  lib->loadSeconds_ =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return lib;
}

std::shared_ptr<const PhotoLibrary> PhotoLibrary::cached(const std::string& dir, int maxSize) {
  static std::mutex mutex;
  static std::map<std::pair<std::string, int>, std::shared_ptr<const PhotoLibrary>> cache;
  std::lock_guard<std::mutex> lock(mutex);
  const auto key = std::make_pair(dir, maxSize);
  auto it = cache.find(key);
  if (it != cache.end())
    return it->second;
  auto lib = load(findPhotoFiles(dir), maxSize,
                  dir.empty() ? "the Debian photo packages" : "'" + dir + "'");
  cache.emplace(key, lib);
  return lib;
}

std::string PhotoLibrary::describe() const {
  const std::string where = source_.empty() ? "" : " (" + source_ + ")";
  if (photos_.empty())
    return "no photos" + where;
  size_t bytes = 0;
  for (const auto& p : photos_)
    bytes += p->rgb.size();
  char text[160];
  std::snprintf(text, sizeof text, "%zu photos%s, <= %d px, %.0f MB, read in %.2f s",
                photos_.size(), where.c_str(), maxSize_, double(bytes) / 1e6, loadSeconds_);
  return text;
}

} // namespace simpli::synthetic
