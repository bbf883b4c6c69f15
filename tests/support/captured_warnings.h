#pragma once
// Captures the warnings (simpli/warning.h) emitted while it lives, for tests that check that a
// poor input is reported, and that a good one is not.
#include "simpli/warning.h"

#include <string>
#include <vector>

namespace simpli::test {

class CapturedWarnings {
public:
  CapturedWarnings()
      : previous_(setWarningHandler([this](const std::string& m) { messages_.push_back(m); })) {}
  ~CapturedWarnings() { setWarningHandler(std::move(previous_)); }
  CapturedWarnings(const CapturedWarnings&) = delete;
  CapturedWarnings& operator=(const CapturedWarnings&) = delete;

  const std::vector<std::string>& messages() const { return messages_; }
  /// The number of warnings that contain every one of `parts`.
  int count(const std::vector<std::string>& parts) const {
    int n = 0;
    for (const std::string& m : messages_) {
      bool all = true;
      for (const std::string& p : parts)
        all = all && m.find(p) != std::string::npos;
      n += all ? 1 : 0;
    }
    return n;
  }
  /// All warnings, one per line (for assertion messages).
  std::string text() const {
    std::string s;
    for (const std::string& m : messages_)
      s += m + "\n";
    return s;
  }

private:
  std::vector<std::string> messages_;
  WarningHandler previous_;
};

} // namespace simpli::test
