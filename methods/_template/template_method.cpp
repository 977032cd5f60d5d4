#include "template_method.hpp"
#include "registry.hpp"

namespace vs {

// Pass names as the paper's tables print them: they become the rows' pass columns.
static constexpr const char* kMarchPass = "Template March";
static constexpr int kMaxSteps = 256;  // one fullscreen pass stays under gl::kShaderLoopBudget

std::string TemplateMethod::description() const {
  return "template: uniform march of L_s against the shared shadow map (copy this folder to add a method)";
}

// Declare only what render() handles: a scene with any other effect becomes an Unsupported row.
Capabilities TemplateMethod::capabilities() const {
  Capabilities c;
  c.pointLight = c.spotLight = c.directionalLight = true;
  c.texturedLight = true;
  c.homogeneousMedium = true;
  c.henyeyGreenstein = true;
  return c;
}

// Every parameter is read by setup() and changes the image within its range, or is declared
// .sameImage(); the conformance test checks both.
std::vector<ParamSpec> TemplateMethod::params() const {
  return {ParamSpec::integer("steps", 32, 1, kMaxSteps, "uniform samples along each camera ray")};
}

// Every pass render() times: the row's pass columns (a pass timed but not listed fails the run).
std::vector<std::string> TemplateMethod::passes() const { return {kMarchPass}; }

std::vector<std::string> TemplateMethod::qualityLadder() const { return {"steps=8", "steps=32", "steps=128"}; }

std::vector<std::string> TemplateMethod::approximations() const { return {"uniform steps without jitter"}; }

void TemplateMethod::setup(const SetupContext& context, const ParamValues& params) {
  steps_ = params.getInt("steps");
  // Shaders are named by their path from the source root; sceneDefines() turns the scene's
  // effects into the defines common.glsl expects.
  program_ = gl::buildFullscreen("methods/_template/shaders/template.frag", sceneDefines(context.effects));
}

void TemplateMethod::render(const Frame& frame, PassTimer& timer) {
  auto scope = timer.scope(kMarchPass);
  frame.bindShared();
  glBindFramebuffer(GL_FRAMEBUFFER, frame.inscatterFbo);
  glViewport(0, 0, frame.width, frame.height);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glUseProgram(program_.id());
  glUniform1i(0, steps_);
  gl::drawFullscreenTriangle();
}

// The number is the method's place in listings (registry.hpp); new methods go after the papers'.
VS_REGISTER_METHOD(TemplateMethod, 1000);

}  // namespace vs
