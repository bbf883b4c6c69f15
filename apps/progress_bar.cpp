// Progress display on stderr (progress_bar.h).
#include "progress_bar.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>

namespace simpli::app {

ProgressBar::ProgressBar(std::string label, int64_t total, int64_t start, std::FILE* stream,
                         double plainInterval)
    : label_(std::move(label)), total_(std::max<int64_t>(total, 0)), start_(start), done_(start),
      stream_(stream), tty_(::isatty(::fileno(stream)) != 0), plainInterval_(plainInterval),
      begin_(std::chrono::steady_clock::now()), lastPlain_(begin_) {}

ProgressBar::~ProgressBar() {
  finish();
}

std::string ProgressBar::formatDuration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0)
    return "?";
  const long long s = static_cast<long long>(seconds + 0.5);
  char buf[32];
  if (s >= 3600)
    std::snprintf(buf, sizeof buf, "%lld:%02lld:%02lld", s / 3600, s / 60 % 60, s % 60);
  else
    std::snprintf(buf, sizeof buf, "%lld:%02lld", s / 60, s % 60);
  return buf;
}

void ProgressBar::update(int64_t done, const std::string& detail) {
  done_ = done;
  detail_ = detail;
  draw(done_ >= total_);
}

void ProgressBar::draw(bool force) {
  const auto now = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(now - begin_).count();
  const int64_t ran = done_ - start_;
  const double eta = ran > 0 ? elapsed / double(ran) * double(total_ - done_) : NAN;
  const double frac = total_ > 0 ? std::min(1.0, double(done_) / double(total_)) : 1.0;
  char counts[160];
  std::snprintf(counts, sizeof counts, "%lld/%lld %3d%% %s elapsed, ETA %s",
                static_cast<long long>(done_), static_cast<long long>(total_), int(frac * 100.0),
                formatDuration(elapsed).c_str(), formatDuration(eta).c_str());
  std::string line = label_ + " ";
  if (tty_) {
    const int width = 24, fill = int(frac * width);
    line += "[" + std::string(size_t(fill), '#') + std::string(size_t(width - fill), '.') + "] ";
  }
  line += counts;
  if (!detail_.empty())
    line += ", " + detail_;
  if (tty_) {
    std::fprintf(stream_, "\r%s\033[K", line.c_str());
    open_ = true;
  } else {
    const double sinceLast = std::chrono::duration<double>(now - lastPlain_).count();
    if (!force && printedPlain_ && sinceLast < plainInterval_)
      return;
    std::fprintf(stream_, "%s\n", line.c_str());
    lastPlain_ = now;
    printedPlain_ = true;
  }
  std::fflush(stream_);
}

void ProgressBar::finish() {
  if (open_) {
    std::fputc('\n', stream_);
    std::fflush(stream_);
    open_ = false;
  }
}

void ProgressBar::message(const std::string& text) {
  finish();
  std::fprintf(stream_, "%s\n", text.c_str());
  std::fflush(stream_);
}

} // namespace simpli::app
