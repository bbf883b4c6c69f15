// COLMAP text models: cameras.txt, images.txt, optional points3D.txt (see scene/readers.h).
#include "scene/text_fields.h"
#include "simpli/error.h"
#include "simpli/model/scene/normalisation.h"
#include "simpli/model/scene/readers.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

namespace fs = std::filesystem;

namespace simpli::scene {

namespace {

struct ColmapCamera {
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
};

std::string findModelFolder(const std::string& root) {
  for (const fs::path& dir :
       {fs::path(root) / "sparse" / "0", fs::path(root) / "sparse", fs::path(root)}) {
    std::error_code ec;
    if (fs::is_regular_file(dir / "cameras.txt", ec) && fs::is_regular_file(dir / "images.txt", ec))
      return dir.string();
  }
  for (const fs::path& dir :
       {fs::path(root) / "sparse" / "0", fs::path(root) / "sparse", fs::path(root)}) {
    std::error_code ec;
    if (fs::is_regular_file(dir / "cameras.bin", ec))
      fail("COLMAP model in '", dir.string(),
           "' is binary (cameras.bin); convert it to text with `colmap model_converter "
           "--input_path ",
           dir.string(), " --output_path ", dir.string(), " --output_type TXT`");
  }
  fail("no COLMAP text model (cameras.txt + images.txt) in '", root, "', '", root, "/sparse' or '",
       root, "/sparse/0'");
}

std::map<long long, ColmapCamera> readCameras(const std::string& path) {
  const auto lines = readLines(path, "COLMAP cameras file");
  std::map<long long, ColmapCamera> cameras;
  for (size_t ln = 0; ln < lines.size(); ++ln) {
    if (isCommentOrBlank(lines[ln]))
      continue;
    const size_t lineNo = ln + 1;
    const auto f = splitFields(lines[ln]);
    if (f.size() < 4)
      fail(path, " line ", lineNo, ": expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS..., got '",
           lineExcerpt(lines[ln]), "'");
    const long long id = parseInteger(f[0], path, lineNo, "CAMERA_ID");
    const std::string& model = f[1];
    ColmapCamera cam;
    const long long w = parseInteger(f[2], path, lineNo, "WIDTH");
    const long long h = parseInteger(f[3], path, lineNo, "HEIGHT");
    if (w <= 0 || h <= 0 || w > 1000000 || h > 1000000)
      fail(path, " line ", lineNo, ": camera ", id, " has invalid size ", w, " x ", h);
    cam.width = int(w);
    cam.height = int(h);
    std::vector<double> params;
    for (size_t k = 4; k < f.size(); ++k)
      params.push_back(parseFinite(f[k], path, lineNo, "PARAMS"));
    size_t expected = 0;
    if (model == "PINHOLE") {
      expected = 4;
    } else if (model == "SIMPLE_PINHOLE") {
      expected = 3;
    } else if (model == "SIMPLE_RADIAL" || model == "RADIAL" || model == "OPENCV" ||
               model == "OPENCV_FISHEYE" || model == "FULL_OPENCV" || model == "FOV" ||
               model == "SIMPLE_RADIAL_FISHEYE" || model == "RADIAL_FISHEYE" ||
               model == "THIN_PRISM_FISHEYE") {
      fail(path, " line ", lineNo, ": camera ", id, " uses model ", model,
           " with lens distortion; simpli needs undistorted PINHOLE images: run `colmap "
           "image_undistorter --image_path <images> --input_path <sparse model> --output_path "
           "<out>` and read <out> instead");
    } else {
      fail(path, " line ", lineNo, ": camera ", id, " has unknown camera model '",
           lineExcerpt(model), "' (supported: PINHOLE, SIMPLE_PINHOLE)");
    }
    if (params.size() != expected)
      fail(path, " line ", lineNo, ": camera ", id, " (", model, ") has ", params.size(),
           " parameters, expected ", expected);
    if (model == "PINHOLE") {
      cam.fx = params[0];
      cam.fy = params[1];
      cam.cx = params[2];
      cam.cy = params[3];
    } else {
      cam.fx = cam.fy = params[0];
      cam.cx = params[1];
      cam.cy = params[2];
    }
    if (!cameras.emplace(id, cam).second)
      fail(path, " line ", lineNo, ": duplicate CAMERA_ID ", id);
  }
  if (cameras.empty())
    fail(path, ": no cameras");
  return cameras;
}

std::vector<Eigen::Vector3d> readPoints(const std::string& path) {
  const auto lines = readLines(path, "COLMAP points file");
  std::vector<Eigen::Vector3d> points;
  for (size_t ln = 0; ln < lines.size(); ++ln) {
    if (isCommentOrBlank(lines[ln]))
      continue;
    const auto f = splitFields(lines[ln]);
    if (f.size() < 4)
      fail(path, " line ", ln + 1, ": expected POINT3D_ID X Y Z ..., got '", lineExcerpt(lines[ln]),
           "'");
    points.emplace_back(parseFinite(f[1], path, ln + 1, "X"), parseFinite(f[2], path, ln + 1, "Y"),
                        parseFinite(f[3], path, ln + 1, "Z"));
  }
  return points;
}

struct ImageEntry {
  long long id = 0;
  std::string name;
  Camera camera;
  size_t line = 0;
};

// A POINTS2D line: X Y POINT3D_ID triplets (POINT3D_ID -1 for none), or nothing at all.
bool isPoints2DLine(const std::vector<std::string>& f) {
  if (f.size() % 3 != 0)
    return false;
  for (size_t k = 0; k < f.size(); ++k)
    if (!(k % 3 == 2 ? isIntegerToken(f[k]) : isNumberToken(f[k])))
      return false;
  return true;
}

// IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME; errors name the line and the field.
ImageEntry parsePoseLine(const std::string& line, const std::string& path, size_t lineNo,
                         const std::map<long long, ColmapCamera>& cameras,
                         const std::string& camerasPath) {
  const auto f = splitFields(line);
  if (f.size() < 10)
    fail(path, " line ", lineNo,
         ": expected a pose line IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME (10 fields) or a "
         "POINTS2D line (X Y POINT3D_ID triplets), got ",
         f.size(), " field(s): '", lineExcerpt(line), "'");
  ImageEntry e;
  e.line = lineNo;
  e.id = parseInteger(f[0], path, lineNo, "IMAGE_ID");
  const char* qnames[4] = {"QW", "QX", "QY", "QZ"};
  double q[4];
  for (int k = 0; k < 4; ++k)
    q[k] = parseFinite(f[size_t(1 + k)], path, lineNo, qnames[k]);
  const char* tnames[3] = {"TX", "TY", "TZ"};
  Eigen::Vector3d t;
  for (int k = 0; k < 3; ++k)
    t[k] = parseFinite(f[size_t(5 + k)], path, lineNo, tnames[k]);
  const long long camId = parseInteger(f[8], path, lineNo, "CAMERA_ID");
  // NAME is the rest of the line (it may contain spaces).
  e.name = restAfterFields(line, 9);

  const double qnorm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (std::abs(qnorm - 1.0) > kRotationTolerance)
    fail(path, " line ", lineNo, ": view '", lineExcerpt(e.name), "': quaternion (", q[0], ", ",
         q[1], ", ", q[2], ", ", q[3], ") has norm ", qnorm, ", not a rotation (tolerance ",
         kRotationTolerance, ")");
  const auto camIt = cameras.find(camId);
  if (camIt == cameras.end())
    fail(path, " line ", lineNo, ": view '", lineExcerpt(e.name), "': CAMERA_ID ", camId,
         " is not in ", camerasPath);
  const ColmapCamera& cc = camIt->second;
  e.camera.R = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
  e.camera.t = t;
  e.camera.fx = cc.fx / cc.width;
  e.camera.fy = cc.fy / cc.height;
  e.camera.cx = cc.cx / cc.width;
  e.camera.cy = cc.cy / cc.height;
  e.camera.width = cc.width;
  e.camera.height = cc.height;
  checkCamera(e.camera, path,
              "'" + lineExcerpt(e.name) + "' (line " + std::to_string(lineNo) + ")");
  return e;
}

// images.txt: per image a pose line, then a POINTS2D line. The POINTS2D line may be empty, and
// some tools write none at all, so a line is told by its shape, not by its position: after a
// pose line, a blank line or X Y POINT3D_ID triplets are its POINTS2D, anything else is the
// next pose line (and is parsed as one, so a malformed line gets an error naming its field).
std::vector<ImageEntry> readImageEntries(const std::string& path,
                                         const std::map<long long, ColmapCamera>& cameras,
                                         const std::string& camerasPath) {
  const auto lines = readLines(path, "COLMAP images file");
  std::vector<ImageEntry> entries;
  std::map<long long, size_t> lineOfId;
  bool afterPose = false;
  for (size_t ln = 0; ln < lines.size(); ++ln) {
    const std::string& line = lines[ln];
    const size_t first = line.find_first_not_of(" \t");
    if (first != std::string::npos && line[first] == '#')
      continue;
    const auto f = splitFields(line);
    if (afterPose && isPoints2DLine(f)) {
      afterPose = false;
      continue;
    }
    if (f.empty())
      continue;
    entries.push_back(parsePoseLine(line, path, ln + 1, cameras, camerasPath));
    const auto [it, fresh] = lineOfId.emplace(entries.back().id, ln + 1);
    if (!fresh)
      fail(path, " line ", ln + 1, ": IMAGE_ID ", entries.back().id, " appears twice (also line ",
           it->second, ")");
    afterPose = true;
  }
  if (entries.empty())
    fail(path, ": no images");
  return entries;
}

} // namespace

SceneSource readColmapSource(const std::string& root, const std::string& imagesDir) {
  std::error_code ec;
  if (!fs::is_directory(root, ec))
    fail("scene folder '", root, "' does not exist");
  const std::string modelDir = findModelFolder(root);
  const std::string camerasPath = (fs::path(modelDir) / "cameras.txt").string();
  const std::string imagesPath = (fs::path(modelDir) / "images.txt").string();
  const std::string pointsPath = (fs::path(modelDir) / "points3D.txt").string();
  const auto cameras = readCameras(camerasPath);

  const std::string imageFolder =
      (fs::path(root) / (imagesDir.empty() ? std::string("images") : imagesDir)).string();
  if (!fs::is_directory(imageFolder, ec))
    fail("image folder '", imageFolder, "' does not exist");

  std::vector<ImageEntry> entries = readImageEntries(imagesPath, cameras, camerasPath);
  std::sort(entries.begin(), entries.end(),
            [](const ImageEntry& a, const ImageEntry& b) { return a.name < b.name; });
  for (size_t i = 1; i < entries.size(); ++i)
    if (entries[i].name == entries[i - 1].name)
      fail(imagesPath, " line ", entries[i].line, ": image '", lineExcerpt(entries[i].name),
           "' appears twice");

  SceneSource src;
  src.format = SceneFormat::Colmap;
  src.root = root;
  src.posesFile = imagesPath;
  for (const ImageEntry& e : entries) {
    const fs::path imagePath = fs::path(imageFolder) / e.name;
    if (!fs::is_regular_file(imagePath, ec))
      fail(imagesPath, " line ", e.line, ": image '", lineExcerpt(e.name), "' not found at '",
           io::excerpt(imagePath.string(), 400), "'");
    src.names.push_back(e.name);
    src.imagePaths.push_back(imagePath.string());
    src.cameras.push_back(e.camera);
  }

  if (fs::is_regular_file(pointsPath, ec)) {
    src.points = readPoints(pointsPath);
    double nearB = 0, farB = 0;
    bool any = false;
    for (const Camera& cam : src.cameras) {
      const std::vector<double> depths = visiblePointDepths(cam, src.points);
      if (depths.empty())
        continue;
      const double lo = percentile(depths, 1.0), hi = percentile(depths, 99.0);
      nearB = any ? std::min(nearB, lo) : lo;
      farB = any ? std::max(farB, hi) : hi;
      any = true;
    }
    if (any) {
      src.near = nearB;
      src.far = farB;
      src.boundsSource = pointsPath + ": min over views of p1, max of p99 of point depths";
    }
  }
  return src;
}

} // namespace simpli::scene
