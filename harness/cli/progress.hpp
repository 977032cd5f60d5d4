// A progress bar on stderr when it is a terminal; otherwise one line per finished item, and
// inside a long item one line at most every `logInterval` (logs of long batch runs show progress).
#pragma once
#include <chrono>
#include <string>

namespace vs {

class Progress {
 public:
  explicit Progress(int totalItems, std::chrono::seconds logInterval = std::chrono::seconds(60));
  ~Progress();
  void item(int index, const std::string& label);   // starts item `index` (0-based)
  void frames(int done, int total);                 // progress inside the current item
  void finished(const std::string& summary);        // ends the current item
  void note(const std::string& line);               // a message that does not break the bar
  void skip(int items);                             // items planned but not to be run

 private:
  void draw();
  bool tty_;
  std::chrono::seconds logInterval_;
  std::chrono::steady_clock::time_point lastLog_;
  int total_, index_ = 0, framesDone_ = 0, framesTotal_ = 0;
  std::string label_;
};

}  // namespace vs
