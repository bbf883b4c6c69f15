// RealEstate10K / SWORD camera files (see scene/readers.h and spec §9.1).
#include "scene/text_fields.h"
#include "simpli/error.h"
#include "simpli/model/scene/readers.h"

#include <filesystem>

namespace fs = std::filesystem;

namespace simpli::scene {

namespace {

std::string findCameraFile(const fs::path& folder) {
  std::error_code ec;
  const fs::path named = folder / (folder.filename().string() + ".txt");
  if (fs::is_regular_file(named, ec))
    return named.string();
  const fs::path cameras = folder / "cameras.txt";
  if (fs::is_regular_file(cameras, ec))
    return cameras.string();
  fail("no RealEstate10K camera file in '", folder.string(), "' (expected '", named.string(),
       "' or '", cameras.string(), "')");
}

// The image of a frame: <folder>/<frame id>.{png,jpg,jpeg} in any letter case; empty if none.
std::string findFrameImage(const fs::path& folder, const std::string& frameId) {
  std::error_code ec;
  for (const char* ext : {".png", ".jpg", ".jpeg", ".PNG", ".JPG", ".JPEG"}) {
    const fs::path p = folder / (frameId + ext);
    if (fs::is_regular_file(p, ec))
      return p.string();
  }
  return {};
}

} // namespace

SceneSource readRealEstateSource(const std::string& path, const std::string& imagesDir) {
  std::error_code ec;
  if (!fs::exists(path, ec))
    fail("scene path '", path, "' does not exist");
  // Strip a trailing separator so that filename() is the folder's name.
  const fs::path given = fs::path(path).lexically_normal();
  const fs::path folderPath = fs::is_directory(given, ec)
                                  ? (given.has_filename() ? given : given.parent_path())
                                  : (given.has_parent_path() ? given.parent_path() : fs::path("."));
  const std::string file = fs::is_directory(given, ec) ? findCameraFile(folderPath) : path;

  fs::path imageFolder = folderPath;
  if (!imagesDir.empty()) {
    imageFolder = folderPath / imagesDir;
    if (!fs::is_directory(imageFolder, ec))
      fail("image folder '", imageFolder.string(), "' does not exist");
  } else if (fs::is_directory(folderPath / "images", ec)) {
    imageFolder = folderPath / "images";
  }

  SceneSource src;
  src.format = SceneFormat::RealEstate10K;
  src.root = folderPath.string();
  src.posesFile = file;
  const auto lines = readLines(file, "RealEstate10K camera file");
  std::string firstMissing;
  for (size_t ln = 1; ln < lines.size(); ++ln) { // line 1 (index 0) is the header
    if (isCommentOrBlank(lines[ln]))
      continue;
    const size_t lineNo = ln + 1;
    const auto f = splitFields(lines[ln]);
    if (f.size() != 19)
      fail(file, " line ", lineNo,
           ": expected 19 fields (frame_id fx fy cx cy 0 0 and a 3x4 "
           "world->camera matrix), got ",
           f.size());
    const std::string& frameId = f[0];
    const std::string image = findFrameImage(imageFolder, frameId);
    if (image.empty()) {
      // The reference stops reading at the first frame without an image.
      firstMissing = (imageFolder / (frameId + ".png")).string();
      break;
    }
    Camera cam;
    cam.fx = parseFinite(f[1], file, lineNo, "fx");
    cam.fy = parseFinite(f[2], file, lineNo, "fy");
    cam.cx = parseFinite(f[3], file, lineNo, "cx");
    cam.cy = parseFinite(f[4], file, lineNo, "cy");
    static const char* names[12] = {"r11", "r12", "r13", "t1",  "r21", "r22",
                                    "r23", "t2",  "r31", "r32", "r33", "t3"};
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) {
        const int k = 4 * r + c;
        const double v = parseFinite(f[size_t(7 + k)], file, lineNo, names[k]);
        if (c < 3)
          cam.R(r, c) = v;
        else
          cam.t[r] = v;
      }
    }
    checkCamera(cam, file, "'" + frameId + "' (line " + std::to_string(lineNo) + ")");
    src.names.push_back(frameId);
    src.imagePaths.push_back(image);
    src.cameras.push_back(cam);
  }
  if (src.cameras.empty()) {
    if (!firstMissing.empty())
      fail(file, ": no images: the first frame's image '", firstMissing,
           "' (or .jpg/.jpeg) does not exist");
    fail(file, ": no frames (expected a header line, then one line per frame)");
  }
  return src;
}

} // namespace simpli::scene
