// Checked image-file reads and writes for the MLI folder formats (see mli/files_internal.h).
#include <opencv2/imgcodecs.hpp>

#include "mli/files_internal.h"
#include "simpli/error.h"

namespace simpli::mli {

cv::Mat readLayerImage(const fs::path& file, int imreadFlags, int H, int W) {
  const std::string name = file.string();
  std::error_code ec;
  if (!fs::is_regular_file(file, ec))
    fail(name, ": missing layer file");
  cv::Mat image;
  try {
    image = cv::imread(name, imreadFlags);
  } catch (const cv::Exception& e) {
    fail(name, ": cannot be decoded (", e.what(), ")");
  }
  if (image.empty())
    fail(name, ": not a readable image");
  if (image.rows != H || image.cols != W)
    fail(name, ": image is ", image.cols, " x ", image.rows, " (W x H) but meta.json frame_size",
         " is [H, W] = [", H, ", ", W, "]");
  return image;
}

void writeLayerImage(const fs::path& file, const cv::Mat& image, const std::vector<int>& params) {
  const std::string name = file.string();
  bool ok = false;
  try {
    ok = cv::imwrite(name, image, params);
  } catch (const cv::Exception& e) {
    fail(name, ": write failed (", e.what(), ")");
  }
  if (!ok)
    fail(name, ": write failed");
}

} // namespace simpli::mli
