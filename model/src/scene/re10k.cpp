// RealEstate10K / SWORD camera files (see scene/readers.h and spec §9.1).
#include "scene/text_fields.h"
#include "simpli/error.h"
#include "simpli/model/scene/readers.h"
#include "simpli/warning.h"

#include <filesystem>
#include <map>
#include <utility>

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

// Line 1 of a RealEstate10K file is the video's URL, but a file may also start with a frame
// (SWORD's files, or lines cut from a longer file): line 1 is a frame line when it has the 19
// fields of one or starts with an integer frame id (a timestamp), and is then read as one.
bool isHeaderLine(const std::vector<std::string>& fields) {
  return !(fields.size() == 19 || (!fields.empty() && isIntegerToken(fields[0])));
}

// "frame_id fx fy cx cy 0 0 r11 r12 r13 t1 r21 r22 r23 t2 r31 r32 r33 t3"; errors name the
// line and the field.
Camera parseFrameLine(const std::vector<std::string>& f, const std::string& file, size_t lineNo) {
  if (f.size() != 19)
    fail(file, " line ", lineNo,
         ": expected 19 fields (frame_id fx fy cx cy 0 0 and a 3x4 world->camera matrix), got ",
         f.size());
  Camera cam;
  cam.fx = parseFinite(f[1], file, lineNo, "fx");
  cam.fy = parseFinite(f[2], file, lineNo, "fy");
  cam.cx = parseFinite(f[3], file, lineNo, "cx");
  cam.cy = parseFinite(f[4], file, lineNo, "cy");
  parseFinite(f[5], file, lineNo, "k1");
  parseFinite(f[6], file, lineNo, "k2");
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
  checkCamera(cam, file, "'" + lineExcerpt(f[0]) + "' (line " + std::to_string(lineNo) + ")");
  return cam;
}

// "1000 (line 2), 2000 (line 3), ... and 7 more" for a warning.
std::string listFrames(const std::vector<std::pair<std::string, size_t>>& frames) {
  constexpr size_t kShown = 5;
  std::string s;
  for (size_t k = 0; k < frames.size() && k < kShown; ++k)
    s += (k ? ", " : "") + lineExcerpt(frames[k].first) + " (line " +
         std::to_string(frames[k].second) + ")";
  if (frames.size() > kShown)
    s += " and " + std::to_string(frames.size() - kShown) + " more";
  return s;
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
  std::map<std::string, size_t> lineOfFrame;
  std::vector<std::pair<std::string, size_t>> missing; // frame id, line
  size_t frames = 0;
  for (size_t ln = 0; ln < lines.size(); ++ln) {
    if (isCommentOrBlank(lines[ln]))
      continue;
    const size_t lineNo = ln + 1;
    const auto f = splitFields(lines[ln]);
    if (ln == 0 && isHeaderLine(f))
      continue;
    const Camera cam = parseFrameLine(f, file, lineNo);
    const std::string& frameId = f[0];
    const auto [it, fresh] = lineOfFrame.emplace(frameId, lineNo);
    if (!fresh)
      fail(file, " line ", lineNo, ": frame id ", lineExcerpt(frameId),
           " appears twice (also line ", it->second,
           "); frame ids (timestamps) name the images and must be unique");
    ++frames;
    const std::string image = findFrameImage(imageFolder, frameId);
    if (image.empty()) {
      missing.emplace_back(frameId, lineNo);
      continue;
    }
    src.names.push_back(frameId);
    src.imagePaths.push_back(image);
    src.cameras.push_back(cam);
  }
  if (frames == 0)
    fail(file, ": no frames (expected an optional header line, then one line per frame)");
  if (src.cameras.empty())
    fail(file, ": none of its ", frames, " frames has an image <frame id>.png/.jpg/.jpeg in '",
         imageFolder.string(), "' (frames: ", listFrames(missing), ")");
  if (!missing.empty())
    warn(file, ": ", missing.size(), " of its ", frames, " frames have no image in '",
         imageFolder.string(), "' and are left out: ", listFrames(missing));
  return src;
}

} // namespace simpli::scene
