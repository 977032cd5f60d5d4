// The effects a scene calls for; passes that no effect needs are neither built nor run.
#pragma once
#include <string>
#include <vector>

#include "scenes/scene.hpp"

namespace vs {

struct Effects {
  bool scattering = false;    // sigma_s > 0: in-scattering passes run
  bool extinction = false;    // sigma_t > 0: surfaces are attenuated along view and light rays
  bool lightTexture = false;  // the light carries a texture: light-texture work runs
  bool anisotropic = false;   // Henyey-Greenstein phase with g != 0
  LightType light = LightType::Point;
  std::string describe() const;  // "scattering+extinction+point"
};

Effects deriveEffects(const Scene& scene);

}  // namespace vs
