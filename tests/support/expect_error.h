#pragma once
// The assertion every bad-input test uses: a simpli::Error whose one-line message names what is
// wrong.
#include "simpli/error.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace simpli::test {

/// Expects `f` to throw simpli::Error whose message is one line and contains every string in
/// `parts`; returns the message (empty when nothing or something else was thrown).
template <typename F> std::string expectError(F&& f, const std::vector<std::string>& parts) {
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

} // namespace simpli::test
