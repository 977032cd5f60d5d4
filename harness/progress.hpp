// A progress bar on stderr when it is a terminal; one line per finished item otherwise.
#pragma once
#include <string>

namespace vs {

class Progress {
 public:
  explicit Progress(int totalItems);
  ~Progress();
  void item(int index, const std::string& label);   // starts item `index` (0-based)
  void frames(int done, int total);                 // progress inside the current item
  void finished(const std::string& summary);        // ends the current item
  void note(const std::string& line);               // a message that does not break the bar
  void skip(int items);                             // items planned but not to be run

 private:
  void draw();
  bool tty_;
  int total_, index_ = 0, framesDone_ = 0, framesTotal_ = 0;
  std::string label_;
};

}  // namespace vs
