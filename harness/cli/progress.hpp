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

// The progress of one long step in stages (loading a scene). On a terminal: a bar on stderr once
// the step has run for `delay` (a quick step draws nothing), redrawn at most ten times a second,
// cleared by finish() or the destructor. Otherwise nothing while it runs, and finish() prints one
// line when the step took longer than `delay` x 4 (logs of long batch runs say where time went).
class StepProgress {
 public:
  explicit StepProgress(std::string title, std::chrono::milliseconds delay = std::chrono::milliseconds(250));
  ~StepProgress();
  void update(const std::string& stage, double fraction);  // `fraction` of `stage` done, in [0, 1]
  void finish(const std::string& summary);                 // "title: summary" (see above)

 private:
  void clear();
  bool tty_, drawn_ = false, finished_ = false;
  std::string title_;
  std::chrono::milliseconds delay_;
  std::chrono::steady_clock::time_point start_, lastDraw_;
};

}  // namespace vs
