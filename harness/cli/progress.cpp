#include "harness/cli/progress.hpp"

#include <unistd.h>

#include <cstdio>
#include <utility>

namespace vs {

Progress::Progress(int totalItems, std::chrono::seconds logInterval)
    : tty_(::isatty(2) != 0), logInterval_(logInterval), lastLog_(std::chrono::steady_clock::now()), total_(totalItems) {}

Progress::~Progress() {
  if (tty_) std::fprintf(stderr, "\r\033[K");
}

void Progress::item(int index, const std::string& label) {
  index_ = index;
  label_ = label;
  framesDone_ = framesTotal_ = 0;
  lastLog_ = std::chrono::steady_clock::now();
  draw();
}

void Progress::frames(int done, int total) {
  framesDone_ = done;
  framesTotal_ = total;
  if (tty_) return draw();
  auto now = std::chrono::steady_clock::now();
  if (now - lastLog_ < logInterval_ || done >= total) return;
  lastLog_ = now;
  std::fprintf(stderr, "[%d/%d] %s: %d/%d\n", index_ + 1, total_, label_.c_str(), done, total);
  std::fflush(stderr);
}

void Progress::draw() {
  if (!tty_) return;
  const int width = 30;
  double fraction = total_ > 0 ? (index_ + (framesTotal_ > 0 ? double(framesDone_) / framesTotal_ : 0.0)) / total_ : 1.0;
  int filled = int(fraction * width + 0.5);
  std::string bar(size_t(filled), '#');
  bar.resize(width, '.');
  std::fprintf(stderr, "\r\033[K[%s] %d/%d %s", bar.c_str(), index_ + 1, total_, label_.c_str());
  if (framesTotal_ > 0) std::fprintf(stderr, " (frame %d/%d)", framesDone_, framesTotal_);
  std::fflush(stderr);
}

void Progress::finished(const std::string& summary) {
  if (tty_) std::fprintf(stderr, "\r\033[K");
  std::fprintf(stderr, "[%d/%d] %s: %s\n", index_ + 1, total_, label_.c_str(), summary.c_str());
  std::fflush(stderr);
}

void Progress::skip(int items) {
  total_ = total_ > items ? total_ - items : 0;
}

void Progress::note(const std::string& line) {
  if (tty_) std::fprintf(stderr, "\r\033[K");
  std::fprintf(stderr, "%s\n", line.c_str());
  draw();
}

StepProgress::StepProgress(std::string title, std::chrono::milliseconds delay)
    : tty_(::isatty(2) != 0), title_(std::move(title)), delay_(delay), start_(std::chrono::steady_clock::now()) {}

StepProgress::~StepProgress() { clear(); }

void StepProgress::update(const std::string& stage, double fraction) {
  if (!tty_ || finished_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - start_ < delay_ || (drawn_ && now - lastDraw_ < std::chrono::milliseconds(100))) return;
  lastDraw_ = now;
  drawn_ = true;
  const int width = 30;
  fraction = fraction > 0.0 ? (fraction < 1.0 ? fraction : 1.0) : 0.0;
  std::string bar(size_t(fraction * width + 0.5), '#');
  bar.resize(width, '.');
  std::fprintf(stderr, "\r\033[K[%s] %s: %s %d%%", bar.c_str(), title_.c_str(), stage.c_str(), int(fraction * 100.0));
  std::fflush(stderr);
}

void StepProgress::clear() {
  if (!drawn_) return;
  std::fprintf(stderr, "\r\033[K");
  std::fflush(stderr);
  drawn_ = false;
}

void StepProgress::finish(const std::string& summary) {
  if (finished_) return;
  finished_ = true;
  clear();
  if (tty_ || std::chrono::steady_clock::now() - start_ < 4 * delay_) return;
  std::fprintf(stderr, "%s: %s\n", title_.c_str(), summary.c_str());
  std::fflush(stderr);
}

}  // namespace vs
