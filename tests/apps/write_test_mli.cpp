// Writes the MLI folders the `simpli convert` tests run on (tests/apps/CMakeLists.txt):
//   <dir>/jpeg, <dir>/lossless   the same valid 2-layer MLI (12 x 8) in both forms
//   <dir>/replace_me             a valid lossless MLI that a --force conversion replaces
//   <dir>/bad_meta               an MLI folder whose meta.json is cut off
// <dir> is emptied first, so outputs of earlier runs (<dir>/out) do not survive.
#include "simpli/model/mli/files.h"

#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;
using namespace simpli;

namespace {

mli::MLI testMLI() {
  scene::Camera cam;
  cam.fx = 0.9;
  cam.fy = 1.3;
  cam.cx = 0.5;
  cam.cy = 0.45;
  cam.width = 12;
  cam.height = 8;
  mli::MLI mli = mli::MLI::allocate(cam, 2);
  for (int k = 0; k < 2; ++k)
    for (int p = 0; p < 12 * 8; ++p) {
      mli.layers[k].depth[p] = static_cast<float>((k == 0 ? 10.0 : 3.0) + 0.01 * p);
      for (int c = 0; c < 4; ++c)
        mli.layers[k].rgba[4 * p + c] = static_cast<float>(0.5 + 0.4 * std::sin(0.3 * p + c + k));
    }
  return mli;
}

} // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUTPUT_DIR\n", argv[0]);
    return 2;
  }
  try {
    const fs::path out = argv[1];
    fs::remove_all(out);
    fs::create_directories(out / "out");
    const mli::MLI mli = testMLI();
    mli::writeMLI((out / "jpeg").string(), mli, mli::MLIFormat::Jpeg);
    mli::writeMLI((out / "lossless").string(), mli, mli::MLIFormat::Lossless);
    mli::writeMLI((out / "replace_me").string(), mli, mli::MLIFormat::Lossless);
    mli::writeMLI((out / "bad_meta").string(), mli, mli::MLIFormat::Jpeg);
    std::ofstream((out / "bad_meta" / "meta.json").string(), std::ios::trunc)
        << "{\"frame_size\": [8, 12], \"layer_depth_00\": [";
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "write_test_mli: %s\n", e.what());
    return 1;
  }
}
