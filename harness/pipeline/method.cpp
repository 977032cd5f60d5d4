#include "harness/pipeline/method.hpp"

namespace vs {

std::string Capabilities::describe() const {
  return joinFlags({{pointLight, "point"},
                    {spotLight, "spot"},
                    {directionalLight, "directional"},
                    {areaLight, "area"},
                    {cosineLobe, "cosine-lobed point"},
                    {texturedLight, "textured light"},
                    {homogeneousMedium, "homogeneous medium"},
                    {henyeyGreenstein, "Henyey-Greenstein"},
                    {volumeData, "volume data"},
                    {semiTransparentOccluders, "semi-transparent occluders"},
                    {coloredShadows, "colored shadows"},
                    {surfaceShadows, "surface shadows"}},
                   ", ");
}

std::string missingCapability(const Capabilities& c, const Effects& e) {
  switch (e.light) {
    case LightType::Point:
      if (!c.pointLight) return "point lights are not supported";
      break;
    case LightType::Spot:
      if (!c.spotLight) return "spot lights are not supported";
      break;
    case LightType::Directional:
      if (!c.directionalLight) return "directional lights are not supported";
      break;
    case LightType::Rect:
    case LightType::Disk:
      if (!c.areaLight) return "area lights are not supported";
      break;
  }
  if (e.cosineLobe && !c.cosineLobe) return "cosine-lobed point lights are not supported";
  if (e.lightTexture && !c.texturedLight) return "textured lights are not supported";
  if (e.anisotropic && !c.henyeyGreenstein) return "the Henyey-Greenstein phase function is not supported";
  if (e.volumeData && !c.volumeData) return "volume data is not supported";
  if (e.semiTransparent && !c.semiTransparentOccluders) return "semi-transparent occluders are not supported";
  if (e.coloredShadows && !c.coloredShadows) return "colored shadows are not supported";
  return "";
}

std::string Method::unsupportedReason(const Scene& scene, const ParamValues&) const {
  return missingCapability(capabilities(), deriveEffects(scene));
}

std::vector<ParamSpec> sharedParams(int maxShadowMapSize) {
  return {ParamSpec::integer("sm", 1024, 64, maxShadowMapSize, "shadow-map resolution (per cube face for point lights)")
              .pow2(),
          ParamSpec::integer("vpls", 0, 0, kMaxVirtualPointLights,
                             "area lights: run the method once per virtual point light and sum L_s (0: off)")};
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

std::unique_ptr<Method> createMethod(const MethodRegistry& registry, const std::string& name) {
  for (const auto& info : registry)
    if (info.name == name) return info.create();
  throw UsageError("unknown method '" + name + "' (methods: " + knownMethodNames(registry) + ")");
}

std::string knownMethodNames(const MethodRegistry& registry) {
  std::string s;
  for (const auto& info : registry) s += (s.empty() ? "" : ", ") + info.name;
  return s;
}

}  // namespace vs
