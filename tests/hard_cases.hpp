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

}  // namespace vs::testing
