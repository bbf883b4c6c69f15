// Writes the small scenes the command-line tests run on (tests/apps/CMakeLists.txt):
//   <dir>/llff, <dir>/colmap, <dir>/re10k            valid scenes, 3 views of 48 x 32
//   <dir>/bad_npy, <dir>/bad_rotation, <dir>/distorted  bad input
//   <dir>/extreme_bounds, <dir>/truncated_image          degenerate or cut input
//   <dir>/re10k_missing (two of five images missing, no URL line)
#include "support/scene_fixtures.h"

#include "simpli/model/io/npy.h"

#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>

namespace fs = std::filesystem;
using namespace simpli;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUTPUT_DIR\n", argv[0]);
    return 2;
  }
  try {
    const fs::path out = argv[1];
    fs::remove_all(out);
    fs::create_directories(out);
    const auto rig = test::makeRig(3);
    test::writeLlffScene((out / "llff").string(), rig, 2.0, 50.0);
    test::writeColmapScene((out / "colmap").string(), rig, test::makePoints(100));
    test::writeRealEstateScene((out / "re10k").string(), rig);

    // Truncated .npy header.
    test::writeLlffScene((out / "bad_npy").string(), rig, 2.0, 50.0);
    const std::string npy = (out / "bad_npy" / "poses_bounds.npy").string();
    test::writeText(npy, test::readText(npy).substr(0, 40));

    // View 1's "right" axis stretched: not a rotation.
    test::writeLlffScene((out / "bad_rotation").string(), rig, 2.0, 50.0);
    const std::string rot = (out / "bad_rotation" / "poses_bounds.npy").string();
    io::NpyArray a = io::readNpy(rot);
    a.data[17 + 1] *= 1.5; // right_x of view 1 (1 for the rig)
    io::writeNpy(rot, a.data, a.shape);

    // COLMAP camera with lens distortion.
    test::writeColmapScene((out / "distorted").string(), rig, {});
    test::writeText((out / "distorted" / "sparse" / "0" / "cameras.txt").string(),
                    "1 OPENCV 48 32 48 48 24 16 0.1 0 0 0\n2 PINHOLE 48 32 48 48 24 16\n"
                    "3 PINHOLE 48 32 48 48 24 16\n");

    // Valid but poor: near..far 1e-4..1e6 (a warning, not an error).
    test::writeLlffScene((out / "extreme_bounds").string(), rig, 1e-4, 1e6);

    // A scene image cut in half: a named error, not a grey-padded decode.
    test::writeLlffScene((out / "truncated_image").string(), rig, 2.0, 50.0);
    const std::string image = (out / "truncated_image" / "images" / "img_01.png").string();
    const std::string bytes = test::readText(image);
    test::writeText(image, bytes.substr(0, bytes.size() / 2));

    // RealEstate10K file starting with a frame (no URL line), two images missing.
    const fs::path missing = out / "re10k_missing";
    test::writeRealEstateScene(missing.string(), test::makeRig(5));
    const std::string cameras = (missing / "re10k_missing.txt").string();
    const std::string text = test::readText(cameras);
    test::writeText(cameras, text.substr(text.find('\n') + 1));
    fs::remove(missing / "2000.png");
    fs::remove(missing / "4000.png");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "write_test_scenes: %s\n", e.what());
    return 1;
  }
  return 0;
}
