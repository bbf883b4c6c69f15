#pragma once
// A progress display for long commands on stderr: on a terminal one line redrawn in place
// ("label [#####.....] 45/100 45% 0:12 elapsed, ETA 0:15, <detail>"); otherwise (a log file, a
// pipe, CI) plain lines, at most one per `plainInterval` seconds plus the last one, so logs stay
// readable.
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>

namespace simpli::app {

class ProgressBar {
public:
  /// `start` is where counting begins (e.g. the resumed step); the ETA uses only the rate of
  /// this process.
  ProgressBar(std::string label, int64_t total, int64_t start = 0, std::FILE* stream = stderr,
              double plainInterval = 5.0);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  /// Changes the total (work whose size is known only once it runs).
  void setTotal(int64_t total) { total_ = total < 0 ? 0 : total; }
  /// Reports `done` of total with an optional detail text.
  void update(int64_t done, const std::string& detail = "");
  /// Ends the line (terminal mode); later output starts on a fresh line.
  void finish();
  /// Prints a message on its own line without garbling the bar.
  void message(const std::string& text);

  bool isTerminal() const { return tty_; }
  /// "1:02:03" or "2:03".
  static std::string formatDuration(double seconds);

private:
  void draw(bool force);

  std::string label_;
  int64_t total_, start_, done_;
  std::string detail_;
  std::FILE* stream_;
  bool tty_;
  bool open_ = false; ///< a bar line is on screen without its newline
  double plainInterval_;
  std::chrono::steady_clock::time_point begin_, lastPlain_;
  bool printedPlain_ = false;
};

} // namespace simpli::app
