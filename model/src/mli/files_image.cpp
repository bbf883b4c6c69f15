// Checked image-file reads and writes for the MLI folder formats (see mli/files_internal.h).
#include <opencv2/imgcodecs.hpp>

#include "io/image_decode.h"
#include "mli/files_internal.h"
#include "simpli/error.h"
#include "simpli/model/io/image_header.h"

namespace simpli::mli {

void checkLayerFile(const fs::path& file, int H, int W) {
  const std::string name = file.string();
  std::error_code ec;
  if (!fs::is_regular_file(file, ec))
    fail(name, ": missing layer file");
  // The declared size before the pixels are decoded: a wrong or huge one is refused unread.
  if (const auto header = io::readImageHeader(name);
      header && (header->width != W || header->height != H))
    fail(name, ": image is ", header->width, " x ", header->height, " (W x H) by its ",
         header->format, " header, but meta.json frame_size is [H, W] = [", H, ", ", W, "]");
}

cv::Mat readLayerImage(const fs::path& file, int imreadFlags, int H, int W) {
  const std::string name = file.string();
  checkLayerFile(file, H, W);
  const cv::Mat image = io::decodeImageFile(name, imreadFlags, "layer file");
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
