#include "harness/pipeline/method.hpp"

#include <cstdio>

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
                    {alphaTestedOccluders && !semiTransparentOccluders, "semi-transparent occluders alpha-tested"},
                    {coloredShadows, "colored shadows"},
                    {surfaceShadows, "surface shadows"}},
                   ", ");
}

std::vector<Capabilities::EffectSupport> Capabilities::effectSupport() const {
  auto native = [](bool on) { return std::string(on ? "native" : "no"); };
  std::vector<EffectSupport> rows = {
      {"point light", native(pointLight)},
      {"spot light", native(spotLight)},
      {"directional light", native(directionalLight)},
      {"area light", areaLight   ? "native"
                     : cosineLobe ? "approximated: vpls=N virtual point lights, the per-VPL wrapper"
                                  : "no"},
      {"textured light", native(texturedLight)},
      {"Henyey-Greenstein phase", native(henyeyGreenstein)},
      {"volume data", native(volumeData)},
      {"semi-transparent occluders", semiTransparentOccluders ? "native"
                                     : alphaTestedOccluders   ? "approximated: alpha-tested into the shadow map at alpha_test"
                                                              : "no"},
      {"colored shadows", coloredShadows         ? "native"
                          : alphaTestedOccluders ? "approximated: occluders alpha-tested, colour dropped; volumes no"
                                                 : "no"}};
  return rows;
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
  const bool alphaTested = e.semiTransparent && !c.semiTransparentOccluders;
  if (alphaTested && !c.alphaTestedOccluders) return "semi-transparent occluders are not supported";
  // Alpha-tested occluders cast binary shadows: their colour is part of the declared approximation.
  if (e.coloredShadows && !c.coloredShadows && (e.coloredVolumes || !alphaTested))
    return "colored shadows are not supported";
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

static constexpr double kDefaultAlphaTest = 0.5;

static ParamSpec alphaTestParam() {
  return ParamSpec::real("alpha_test", kDefaultAlphaTest, 0.01, 1.0,
                         "semi-transparent occluders block the light where their opacity is at least this (alpha-tested "
                         "into the shadow map: a declared approximation)");
}

std::vector<ParamSpec> allParams(const Method& method, int maxShadowMapSize) {
  std::vector<ParamSpec> all = method.params();
  std::vector<ParamSpec> shared = sharedParams(maxShadowMapSize);
  const Capabilities c = method.capabilities();
  if (c.alphaTestedOccluders && !c.semiTransparentOccluders) shared.push_back(alphaTestParam());
  for (auto& p : shared) {
    bool overridden = false;
    for (auto& own : all) overridden = overridden || own.name == p.name;
    if (!overridden) all.push_back(p);
  }
  return all;
}

float alphaTestThreshold(const Method& method, const Effects& effects, const ParamValues& params) {
  const Capabilities c = method.capabilities();
  if (!effects.semiTransparent || c.semiTransparentOccluders || !c.alphaTestedOccluders) return -1.0f;
  return params.has("alpha_test") ? float(params.getFloat("alpha_test")) : float(kDefaultAlphaTest);
}

std::string alphaTestApproximation(const Scene& scene, float threshold) {
  if (threshold < 0.0f) return "";
  bool blend = false;
  for (const Mesh& m : scene.meshes) blend = blend || (!m.isOpaque() && m.opacity > 0.0f && m.alphaCutoff < 0.0f);
  if (!blend) return "";
  char text[160];
  std::snprintf(text, sizeof text,
                "semi-transparent occluders alpha-tested into the shadow map (opacity >= %g blocks, below it none)",
                double(threshold));
  return text;
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
