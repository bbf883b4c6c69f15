// Checks the output folder of `simpli render` (tests/apps/CMakeLists.txt):
//   check_render DIR FRAMES WIDTH HEIGHT MIN_COVERED
// DIR must hold exactly FRAMES pairs rgb_NNN.png (8-bit, 3 channels) and depth_NNN.png (16-bit,
// 1 channel) of WIDTH x HEIGHT, and render.json listing them with their cameras; in every frame
// at least MIN_COVERED of the pixels have a non-zero depth, and every such pixel has a
// plausible depth (> 0.5 MLI units at the default scale of 1000). Prints what it found; exit 0
// when all holds.
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  if (argc != 6) {
    std::fprintf(stderr, "usage: %s DIR FRAMES WIDTH HEIGHT MIN_COVERED\n", argv[0]);
    return 2;
  }
  const fs::path dir = argv[1];
  const int frames = std::stoi(argv[2]), W = std::stoi(argv[3]), H = std::stoi(argv[4]);
  const double minCovered = std::stod(argv[5]);
  int pngs = 0;
  for (const auto& e : fs::directory_iterator(dir))
    pngs += e.path().extension() == ".png";
  if (pngs != 2 * frames) {
    std::fprintf(stderr, "FAIL: %d PNG files in %s, expected %d\n", pngs, dir.c_str(), 2 * frames);
    return 1;
  }
  nlohmann::json meta;
  std::ifstream(dir / "render.json") >> meta;
  if (!meta.contains("frames") || int(meta["frames"].size()) != frames ||
      !meta.contains("depth_scale")) {
    std::fprintf(stderr, "FAIL: render.json does not list %d frames with a depth_scale\n", frames);
    return 1;
  }
  const double depthScale = meta["depth_scale"].get<double>();
  for (int i = 0; i < frames; ++i) {
    const auto& f = meta["frames"][size_t(i)];
    const cv::Mat rgb =
        cv::imread((dir / f["rgb"].get<std::string>()).string(), cv::IMREAD_UNCHANGED);
    const cv::Mat z =
        cv::imread((dir / f["depth"].get<std::string>()).string(), cv::IMREAD_UNCHANGED);
    if (rgb.empty() || z.empty() || rgb.type() != CV_8UC3 || z.type() != CV_16UC1) {
      std::fprintf(stderr, "FAIL: frame %d: unreadable, or not 8-bit RGB + 16-bit depth\n", i);
      return 1;
    }
    if (rgb.cols != W || rgb.rows != H || z.cols != W || z.rows != H ||
        f["frame_size"][0].get<int>() != H || f["frame_size"][1].get<int>() != W) {
      std::fprintf(stderr, "FAIL: frame %d is %d x %d, expected %d x %d\n", i, rgb.cols, rgb.rows,
                   W, H);
      return 1;
    }
    int covered = 0, coloured = 0;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        const uint16_t d = z.at<uint16_t>(y, x);
        const cv::Vec3b c = rgb.at<cv::Vec3b>(y, x);
        coloured += c[0] || c[1] || c[2];
        if (d == 0)
          continue;
        ++covered;
        if (d * depthScale < 0.5) {
          std::fprintf(stderr, "FAIL: frame %d: depth %g at (%d, %d)\n", i, d * depthScale, x, y);
          return 1;
        }
      }
    const double fraction = double(covered) / (double(W) * H);
    std::printf("frame %d: %d x %d, %.1f %% covered, %d coloured pixels\n", i, W, H,
                100.0 * fraction, coloured);
    if (fraction < minCovered || coloured == 0) {
      std::fprintf(stderr,
                   "FAIL: frame %d: %.3f of the pixels covered (expected >= %.3f), %d "
                   "coloured\n",
                   i, fraction, minCovered, coloured);
      return 1;
    }
  }
  std::printf("render output OK: %d frame(s)\n", frames);
  return 0;
}
