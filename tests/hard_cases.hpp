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
  // The image the stability test renders it at (the report keeps 64x48 for every case). Smaller
  // for a case whose every pixel is dear (1,000 stacked layers: a list walk of 1,000 nodes per
  // sample), where more pixels test nothing more.
  int width = 64, height = 48;
};

const std::vector<HardCase>& hardCases();
const HardCase& hardCase(const std::string& name);
// Hard cases in time: scenes whose animation drives a hard moment through the frames (the epipole
// crossing the screen border, the light passing through an occluder, the camera crossing a
// volume's boundary, keys a hair apart). Frames at 4 fps over 1 s: 5 frames.
const std::vector<HardCase>& temporalHardCases();
const HardCase& temporalHardCase(const std::string& name);

}  // namespace vs::testing
