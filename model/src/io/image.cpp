#include "simpli/model/io/image.h"

#include "io/image_decode.h"
#include "simpli/error.h"
#include "simpli/model/io/files.h"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace simpli::io {

Image::Image(int w, int h) : width(w), height(h) {
  if (w < 0 || h < 0)
    fail("Image: negative size ", w, " x ", h);
  data.assign(size_t(channels) * size_t(w) * size_t(h), 0.0f);
}

int floorToMultiple(int size, int multiple) {
  if (multiple <= 1)
    return size;
  return size / multiple * multiple;
}

namespace {

// Interleaved float RGB (CV_32FC3) -> planar Image.
Image fromInterleaved(const cv::Mat& rgb) {
  Image image(rgb.cols, rgb.rows);
  std::vector<cv::Mat> planes;
  for (int c = 0; c < Image::channels; ++c)
    planes.emplace_back(rgb.rows, rgb.cols, CV_32FC1, image.plane(c));
  cv::split(rgb, planes); // writes straight into the Image's planes
  return image;
}

cv::Mat toInterleaved(const Image& image) {
  std::vector<cv::Mat> planes;
  for (int c = 0; c < Image::channels; ++c)
    planes.emplace_back(image.height, image.width, CV_32FC1, const_cast<float*>(image.plane(c)));
  cv::Mat rgb;
  cv::merge(planes, rgb);
  return rgb;
}

} // namespace

Image readImage(const std::string& path, int sizeMultiple, ImageSize* originalSize) {
  const cv::Mat raw =
      decodeImageFile(path, cv::IMREAD_UNCHANGED | cv::IMREAD_IGNORE_ORIENTATION, "image file");

  double scale = 0;
  switch (raw.depth()) {
  case CV_8U:
    scale = 1.0 / 127.5;
    break;
  case CV_16U:
    scale = 1.0 / 32767.5;
    break;
  default:
    fail("image file '", path, "' has unsupported pixel depth (OpenCV depth code ", raw.depth(),
         "); expected 8-bit or 16-bit");
  }

  cv::Mat rgb;
  switch (raw.channels()) {
  case 1:
    cv::cvtColor(raw, rgb, cv::COLOR_GRAY2RGB);
    break;
  case 2: { // grey + alpha: keep the grey
    cv::Mat grey;
    cv::extractChannel(raw, grey, 0);
    cv::cvtColor(grey, rgb, cv::COLOR_GRAY2RGB);
    break;
  }
  case 3:
    cv::cvtColor(raw, rgb, cv::COLOR_BGR2RGB);
    break;
  case 4:
    cv::cvtColor(raw, rgb, cv::COLOR_BGRA2RGB);
    break;
  default:
    fail("image file '", path, "' has ", raw.channels(), " channels; expected 1, 2, 3 or 4");
  }

  if (originalSize)
    *originalSize = {rgb.cols, rgb.rows};
  const int w = floorToMultiple(rgb.cols, sizeMultiple);
  const int h = floorToMultiple(rgb.rows, sizeMultiple);
  if (w == 0 || h == 0)
    fail("image file '", path, "' is ", rgb.cols, " x ", rgb.rows,
         " pixels, smaller than the required multiple of ", sizeMultiple);

  // x * scale - 1 in double, rounded once to float: in float the subtraction cancels and
  // mid-grey values would be off by several ulps.
  cv::Mat dbl, fl;
  rgb.convertTo(dbl, CV_64FC3, scale, -1.0);
  dbl.convertTo(fl, CV_32FC3);
  if (w != fl.cols || h != fl.rows) {
    cv::Mat resized;
    cv::resize(fl, resized, cv::Size(w, h), 0, 0, cv::INTER_AREA);
    fl = resized;
  }
  return fromInterleaved(fl);
}

Image resizeImage(const Image& image, int width, int height) {
  if (width <= 0 || height <= 0)
    fail("resizeImage: target size ", width, " x ", height, " is not positive");
  if (image.empty())
    fail("resizeImage: the image is empty");
  if (width == image.width && height == image.height)
    return image;
  const bool down = width <= image.width && height <= image.height;
  cv::Mat resized;
  cv::resize(toInterleaved(image), resized, cv::Size(width, height), 0, 0,
             down ? cv::INTER_AREA : cv::INTER_LINEAR);
  return fromInterleaved(resized);
}

void writeImagePng(const Image& image, const std::string& path) {
  if (image.empty())
    fail("cannot write '", path, "': the image is empty");
  if (image.data.size() != size_t(Image::channels) * image.width * image.height)
    fail("cannot write '", path, "': image data has ", image.data.size(), " values, expected ",
         size_t(Image::channels) * image.width * image.height);
  cv::Mat rgb8, bgr8;
  // convertTo rounds to nearest and saturates to [0, 255].
  toInterleaved(image).convertTo(rgb8, CV_8UC3, 127.5, 127.5);
  cv::cvtColor(rgb8, bgr8, cv::COLOR_RGB2BGR);
  std::vector<unsigned char> png;
  bool ok = false;
  try {
    ok = cv::imencode(".png", bgr8, png);
  } catch (const cv::Exception& e) {
    fail("cannot encode '", path, "' as PNG: ", e.what());
  }
  if (!ok)
    fail("cannot encode '", path, "' as PNG");
  writeFileAtomically(path, png.data(), png.size());
}

} // namespace simpli::io
