#pragma once
// Helpers shared by the model tests: error assertions and camera construction.
#include <simpli/error.h>
#include <simpli/model/scene/camera.h>

#include <gtest/gtest.h>

#include <initializer_list>
#include <string>

namespace simpli::test {

/// Expects `f` to throw simpli::Error whose message contains every string in `parts`;
/// returns the message.
template <typename F> std::string expectError(F&& f, std::initializer_list<std::string> parts) {
  try {
    f();
  } catch (const Error& e) {
    const std::string msg = e.what();
    for (const std::string& p : parts)
      EXPECT_NE(msg.find(p), std::string::npos) << "message: " << msg << "\nmissing: " << p;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "message is not one line: " << msg;
    return msg;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not a simpli::Error: " << e.what();
    return {};
  }
  ADD_FAILURE() << "no simpli::Error thrown";
  return {};
}

/// A camera at the world origin looking down +z (identity pose) with relative intrinsics.
inline scene::Camera pinholeCamera(int width, int height, double fx, double fy, double cx,
                                   double cy) {
  scene::Camera c;
  c.width = width;
  c.height = height;
  c.fx = fx;
  c.fy = fy;
  c.cx = cx;
  c.cy = cy;
  return c;
}

} // namespace simpli::test
