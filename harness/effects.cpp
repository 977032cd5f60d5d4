#include "effects.hpp"

namespace vs {

Effects deriveEffects(const Scene& scene) {
  Effects e;
  e.scattering = scene.medium.sigmaS > 0.0f;
  e.extinction = scene.medium.sigmaT() > 0.0f;
  e.lightTexture = scene.light.hasTexture();
  e.anisotropic = scene.medium.phase == Phase::HenyeyGreenstein && scene.medium.g != 0.0f;
  e.light = scene.light.type;
  return e;
}

std::string Effects::describe() const {
  std::string s;
  auto add = [&](bool on, const char* name) {
    if (on) s += (s.empty() ? "" : "+") + std::string(name);
  };
  add(scattering, "scattering");
  add(extinction, "extinction");
  add(lightTexture, "light-texture");
  add(anisotropic, "hg-phase");
  add(true, light == LightType::Point ? "point" : light == LightType::Spot ? "spot" : "directional");
  return s;
}

}  // namespace vs
