// Brute-force ray marching of the single-scattering integral; also the harness's reference.
#pragma once
#include "harness/method.hpp"

namespace vs {

class RaymarchMethod : public Method {
 public:
  std::string name() const override { return "raymarch"; }
  std::string description() const override;
  Capabilities capabilities() const override;
  std::vector<ParamSpec> params() const override;
  std::vector<std::string> qualityLadder() const override;
  std::string referenceParams() const override;
  void setup(const SetupContext& context, const ParamValues& params) override;
  void render(const Frame& frame, PassTimer& timer) override;
  std::map<std::string, double> stats(const std::map<std::string, TimingStats>& passes) const override;

 private:
  gl::Program program_;
  int steps_ = 0;
  bool jitter_ = true;
  bool equiangular_ = false;
  int width_ = 0, height_ = 0;
};

}  // namespace vs
