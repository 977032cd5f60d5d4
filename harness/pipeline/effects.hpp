// The effects a scene calls for; passes that no effect needs are neither built nor run, and a
// method runs a scene only when its Capabilities cover every effect (method.hpp, missingCapability).
#pragma once
#include <string>
#include <vector>

#include "scenes/scene.hpp"

namespace vs {

struct Effects {
  bool scattering = false;       // sigma_s > 0, or volume data: the method's passes run
  bool extinction = false;       // sigma_t > 0: surfaces are attenuated along view and light rays
  bool lightTexture = false;     // the light carries a texture: light-texture work runs
  bool anisotropic = false;      // Henyey-Greenstein phase with g != 0
  bool areaLight = false;        // rect or disk light: integrated over the light's surface
  bool cosineLobe = false;       // point light with cosine emission (an area light's virtual point light)
  bool volumeData = false;       // density grids: heterogeneous sigma_t, 3D textures
  bool semiTransparent = false;  // occluders with opacity < 1: light transmittance through layers
  bool coloredShadows = false;   // occluders with a transmittance colour, or volumes with per-channel sigma
  bool coloredOccluders = false;  // ...from occluders with a transmittance colour
  bool coloredVolumes = false;    // ...from volumes with per-channel sigma
  LightType light = LightType::Point;
  int volumeCount = 0;
  std::string describe() const;  // "scattering+extinction+point"
};

Effects deriveEffects(const Scene& scene);

// Joins the names whose flag is set: the one helper behind Effects and Capabilities descriptions.
std::string joinFlags(const std::vector<std::pair<bool, const char*>>& flags, const char* separator);

}  // namespace vs
