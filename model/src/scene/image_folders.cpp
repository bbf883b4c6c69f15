// chooseImageFolder: which of a scene's image folders (images/, images_N/) to read.
#include "simpli/error.h"
#include "simpli/model/io/image.h"
#include "simpli/model/io/image_header.h"
#include "simpli/model/scene/readers.h"

#include <cmath>
#include <filesystem>
#include <optional>
#include <regex>

namespace fs = std::filesystem;

namespace simpli::scene {

namespace {

// "images" and "images_<N>" (N a positive integer) folders directly under root, sorted.
std::vector<std::string> imageFolders(const fs::path& root) {
  static const std::regex name("images(_[1-9][0-9]*)?");
  std::vector<std::string> found;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(root, ec))
    if (entry.is_directory(ec) && std::regex_match(entry.path().filename().string(), name))
      found.push_back(entry.path().filename().string());
  std::sort(found.begin(), found.end());
  return found;
}

std::string joinNames(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names)
    s += (s.empty() ? "" : ", ") + n;
  return s.empty() ? "none" : s;
}

} // namespace

std::string chooseImageFolder(const std::string& root, int factor, int preferredWidth) {
  if (factor < 0)
    fail("image factor ", factor, " must be >= 0");
  if (preferredWidth < 0)
    fail("preferred image width ", preferredWidth, " must be >= 0");
  const std::vector<std::string> folders = imageFolders(root);
  if (factor > 0) {
    // The NeRF loaders' convention: factor N reads images_N (factor 1 is images/ itself).
    const std::string wanted = factor == 1 ? "images" : "images_" + std::to_string(factor);
    if (std::find(folders.begin(), folders.end(), wanted) == folders.end())
      fail("scene '", root, "': image factor ", factor, " needs the folder '", wanted,
           "', which does not exist (image folders: ", joinNames(folders), ")");
    return wanted;
  }
  if (preferredWidth == 0 || folders.empty())
    return "";
  // The folder whose images are closest in width to the one requested, on a log scale (a
  // factor of 2 too large counts as much as 2 too small); ties go to the larger images, which
  // are then resized down rather than up.
  std::string best;
  double bestDistance = 0;
  int bestWidth = 0;
  for (const std::string& f : folders) {
    const std::vector<std::string> files = listImageFiles((fs::path(root) / f).string());
    if (files.empty())
      continue;
    // The header alone gives the size; a file without a recognised header is decoded.
    int width = 0;
    if (const std::optional<io::ImageHeader> header = io::readImageHeader(files.front())) {
      width = int(header->width);
    } else {
      io::ImageSize size;
      io::readImage(files.front(), 1, &size);
      width = size.width;
    }
    const double distance = std::abs(std::log(double(width) / preferredWidth));
    if (best.empty() || distance < bestDistance - 1e-12 ||
        (std::abs(distance - bestDistance) <= 1e-12 && width > bestWidth)) {
      best = f;
      bestDistance = distance;
      bestWidth = width;
    }
  }
  return best;
}

} // namespace simpli::scene
