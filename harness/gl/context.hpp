// Headless OpenGL 4.5 core context through EGL (surfaceless platform, then EGL devices).
#pragma once
#include <string>

namespace vs {

struct ContextInfo {
  std::string glVendor, glRenderer, glVersion, eglVendor, eglVersion, platform;
};

class GlContext {
 public:
  // Throws std::runtime_error with one line when no 4.5 core context can be made.
  explicit GlContext(bool debug = true);
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;
  const ContextInfo& info() const { return info_; }

 private:
  void* display_ = nullptr;
  void* context_ = nullptr;
  ContextInfo info_;
};

}  // namespace vs
