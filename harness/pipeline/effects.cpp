#include "harness/pipeline/effects.hpp"

#include <algorithm>

namespace vs {

Effects deriveEffects(const Scene& scene) {
  Effects e;
  e.scattering = scene.medium.sigmaS > 0.0f;
  e.extinction = scene.medium.sigmaT() > 0.0f;
  for (const Volume& v : scene.volumes) {
    e.volumeData = true;
    // A volume that only absorbs still needs the method's pass: it outputs the camera ray's
    // transmittance through the volume with L_s.
    glm::vec3 t = v.sigmaT();
    bool present = std::max({t.x, t.y, t.z}) > 0.0f && v.densityScale > 0.0f && v.maxDensity() > 0.0f;
    e.scattering = e.scattering || present;
    e.extinction = e.extinction || present;
    // Per-channel coefficients: the light through the volume is tinted.
    if (present && v.chromatic()) e.coloredShadows = e.coloredVolumes = true;
  }
  e.lightTexture = scene.light.hasTexture();
  e.anisotropic = scene.medium.phase == Phase::HenyeyGreenstein && scene.medium.g != 0.0f;
  e.areaLight = isAreaLight(scene.light.type);
  e.cosineLobe = scene.light.type == LightType::Point && scene.light.cosineLobe;
  for (const Mesh& m : scene.meshes) {
    if (!m.isOpaque()) e.semiTransparent = true;
    if (!m.isOpaque() && m.hasTransmittanceColor()) e.coloredShadows = e.coloredOccluders = true;
  }
  e.light = scene.light.type;
  e.volumeCount = int(scene.volumes.size());
  return e;
}

std::string joinFlags(const std::vector<std::pair<bool, const char*>>& flags, const char* separator) {
  std::string s;
  for (const auto& [on, name] : flags)
    if (on) s += (s.empty() ? "" : separator) + std::string(name);
  return s;
}

std::string Effects::describe() const {
  return joinFlags({{scattering, "scattering"},
                    {extinction, "extinction"},
                    {lightTexture, "light-texture"},
                    {anisotropic, "hg-phase"},
                    {volumeData, "volume-data"},
                    {semiTransparent, "semi-transparent"},
                    {coloredShadows, "colored-shadows"},
                    {areaLight, "area-light"},
                    {cosineLobe, "cosine-lobe"},
                    {true, lightTypeName(light)}},
                   "+");
}

}  // namespace vs
