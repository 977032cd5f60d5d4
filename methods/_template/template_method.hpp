// TEMPLATE: the smallest complete method, to copy into methods/NAME (README.md says how).
// Shadowed single scattering by a short uniform march against the shared shadow map.
#pragma once
#include "harness/pipeline/method.hpp"

namespace vs {

class TemplateMethod : public Method {
 public:
  std::string name() const override { return "template"; }
  std::string description() const override;
  Capabilities capabilities() const override;
  std::vector<ParamSpec> params() const override;
  std::vector<std::string> passes() const override;
  std::vector<std::string> qualityLadder() const override;
  std::vector<std::string> approximations() const override;
  double declaredRelMseBound() const override { return 0.05; }
  void setup(const SetupContext& context, const ParamValues& params) override;
  void render(const Frame& frame, PassTimer& timer) override;

 private:
  gl::Program program_;
  int steps_ = 32;
};

}  // namespace vs
