// The hard cases of the stability suite (README "Stability"), as scenes built in code. Shared by the
// stability tests, the stress tool and the stability report.
#pragma once
#include <string>
#include <vector>

#include "scenes/scene.hpp"

namespace vs::testing {

struct HardCase {
  std::string name;
  std::string json;       // scene JSON
  bool singular = false;  // the integral diverges (light on the camera ray origin): no reference bound
};

const std::vector<HardCase>& hardCases();
const HardCase& hardCase(const std::string& name);
// Hard cases in time: scenes whose animation drives a hard moment through the frames (the epipole
// crossing the screen border, the light passing through an occluder, the camera crossing a
// volume's boundary, keys a hair apart). Frames at 4 fps over 1 s: 5 frames.
const std::vector<HardCase>& temporalHardCases();
const HardCase& temporalHardCase(const std::string& name);

}  // namespace vs::testing
