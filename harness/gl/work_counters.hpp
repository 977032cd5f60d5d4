// Per-pixel work counters of an instrumented pass (e.g. traversal steps per pixel), for the
// result row's method_stats: an R32UI 2D array, one layer per counter, that fragment shaders add
// to with imageAtomicAdd (harness/shaders/work_counters.glsl), so repeated renders of one frame
// (the per-VPL wrapper) sum up. Never used inside a timed frame.
#pragma once
#include <map>
#include <string>
#include <vector>

#include "harness/gl/gl.hpp"

namespace vs {

class WorkCounters {
 public:
  // Names of the counters, in layer order; `visited` (the first) counts 1 per pixel the pass
  // worked on, and the means of the others are over those pixels.
  explicit WorkCounters(std::vector<std::string> names);
  // Allocates (on a size change) and zeroes the counters.
  void begin(int width, int height);
  // Binds the counters to image unit bind::kWorkCounters for an instrumented draw.
  void bind() const;
  // prefix + "_<name>_mean" and "_<name>_max" per counter after the first, prefix + "_pixels" for
  // the visited count.
  std::map<std::string, double> read(const std::string& prefix) const;

 private:
  std::vector<std::string> names_;
  int width_ = 0, height_ = 0;
  gl::Texture counters_;
};

}  // namespace vs
