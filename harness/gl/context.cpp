#include "harness/gl/context.hpp"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdio>
#include <stdexcept>
#include <vector>

#include "harness/gl/gl.hpp"

#ifdef VS_SANITIZE
#include <dlfcn.h>
#include <link.h>
#endif

namespace vs {

#ifdef VS_SANITIZE
// Sanitizer builds only: keep every module loaded now (the GL driver among them) mapped until exit,
// so LeakSanitizer can name the driver's own allocations instead of addresses in unloaded code.
static void pinLoadedModules() {
  dl_iterate_phdr(
      [](dl_phdr_info* info, size_t, void*) -> int {
        if (info->dlpi_name && info->dlpi_name[0]) dlopen(info->dlpi_name, RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
        return 0;
      },
      nullptr);
}
#endif

static std::string eglErrorName(EGLint e) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "EGL error 0x%04x", e);
  return buf;
}

static bool hasExtension(const char* list, const std::string& name) {
  if (!list) return false;
  std::string s = std::string(" ") + list + " ";
  return s.find(" " + name + " ") != std::string::npos;
}

// Surfaceless Mesa first (no X server, no device node needed), then the first EGL device.
static EGLDisplay openDisplay(std::string& platform) {
  const char* clientExts = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  auto getPlatformDisplay = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (getPlatformDisplay && hasExtension(clientExts, "EGL_MESA_platform_surfaceless")) {
    EGLDisplay d = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    EGLint major = 0, minor = 0;
    if (d != EGL_NO_DISPLAY && eglInitialize(d, &major, &minor)) {
      platform = "surfaceless";
      return d;
    }
  }
  auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  if (getPlatformDisplay && queryDevices && hasExtension(clientExts, "EGL_EXT_platform_device")) {
    EGLDeviceEXT devices[16];
    EGLint count = 0;
    if (queryDevices(16, devices, &count)) {
      for (EGLint i = 0; i < count; ++i) {
        EGLDisplay d = getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
        EGLint major = 0, minor = 0;
        if (d != EGL_NO_DISPLAY && eglInitialize(d, &major, &minor)) {
          platform = "device " + std::to_string(i);
          return d;
        }
      }
    }
  }
  throw std::runtime_error("cannot open a headless EGL display (no surfaceless platform, no EGL device): " +
                           eglErrorName(eglGetError()));
}

GlContext::GlContext(bool debug) {
  EGLDisplay display = openDisplay(info_.platform);
  display_ = display;
  if (!eglBindAPI(EGL_OPENGL_API)) throw std::runtime_error("EGL cannot bind the OpenGL API");
  const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                               4,
                               EGL_CONTEXT_MINOR_VERSION,
                               5,
                               EGL_CONTEXT_OPENGL_PROFILE_MASK,
                               EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                               EGL_CONTEXT_OPENGL_DEBUG,
                               debug ? EGL_TRUE : EGL_FALSE,
                               EGL_NONE};
  EGLContext context = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
  if (context == EGL_NO_CONTEXT) {
    EGLint e = eglGetError();
    eglTerminate(display);
    throw std::runtime_error("cannot create an OpenGL 4.5 core context: " + eglErrorName(e));
  }
  context_ = context;
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
    EGLint e = eglGetError();
    eglDestroyContext(display, context);
    eglTerminate(display);
    throw std::runtime_error("cannot make the OpenGL context current: " + eglErrorName(e));
  }
  auto str = [](GLenum name) {
    const GLubyte* s = glGetString(name);
    return s ? std::string(reinterpret_cast<const char*>(s)) : std::string("unknown");
  };
  info_.glVendor = str(GL_VENDOR);
  info_.glRenderer = str(GL_RENDERER);
  info_.glVersion = str(GL_VERSION);
  const char* eglVendor = eglQueryString(display, EGL_VENDOR);
  const char* eglVersion = eglQueryString(display, EGL_VERSION);
  info_.eglVendor = eglVendor ? eglVendor : "unknown";
#ifdef VS_SANITIZE
  pinLoadedModules();
#endif
  info_.eglVersion = eglVersion ? eglVersion : "unknown";
}

GlContext::~GlContext() {
  gl::releaseSharedObjects();
  auto display = static_cast<EGLDisplay>(display_);
  eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display, static_cast<EGLContext>(context_));
  eglTerminate(display);
}

}  // namespace vs
