#include "method.hpp"

namespace vs {

std::string Capabilities::describe() const {
  std::string s;
  auto add = [&](bool on, const char* name) {
    if (on) s += (s.empty() ? "" : ", ") + std::string(name);
  };
  add(pointLight, "point");
  add(spotLight, "spot");
  add(directionalLight, "directional");
  add(areaLight, "area");
  add(texturedLight, "textured light");
  add(homogeneousMedium, "homogeneous medium");
  add(henyeyGreenstein, "Henyey-Greenstein");
  add(volumeData, "volume data");
  add(semiTransparentOccluders, "semi-transparent occluders");
  add(surfaceShadows, "surface shadows");
  return s;
}

std::string Method::unsupportedReason(const Scene& scene, const ParamValues&) const {
  Capabilities c = capabilities();
  switch (scene.light.type) {
    case LightType::Point:
      if (!c.pointLight) return "point lights are not supported";
      break;
    case LightType::Spot:
      if (!c.spotLight) return "spot lights are not supported";
      break;
    case LightType::Directional:
      if (!c.directionalLight) return "directional lights are not supported";
      break;
  }
  if (scene.light.hasTexture() && !c.texturedLight) return "textured lights are not supported";
  if (scene.medium.phase == Phase::HenyeyGreenstein && scene.medium.g != 0.0f && !c.henyeyGreenstein)
    return "the Henyey-Greenstein phase function is not supported";
  return "";
}

std::vector<ParamSpec> sharedParams(int maxShadowMapSize) {
  return {ParamSpec::integer("sm", 1024, 64, maxShadowMapSize, "shadow-map resolution (per cube face for point lights)")
              .pow2()};
}

std::vector<ParamSpec> allParams(const Method& method, int maxShadowMapSize) {
  std::vector<ParamSpec> all = method.params();
  for (auto& p : sharedParams(maxShadowMapSize)) {
    bool overridden = false;
    for (auto& own : all) overridden = overridden || own.name == p.name;
    if (!overridden) all.push_back(p);
  }
  return all;
}

std::unique_ptr<Method> createMethod(const std::string& name) {
  for (const auto& info : registeredMethods())
    if (info.name == name) return info.create();
  throw UsageError("unknown method '" + name + "' (methods: " + knownMethodNames() + ")");
}

std::string knownMethodNames() {
  std::string s;
  for (const auto& info : registeredMethods()) s += (s.empty() ? "" : ", ") + info.name;
  return s;
}

}  // namespace vs
