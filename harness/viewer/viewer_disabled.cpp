// vshadow view when the build found no GLFW or Dear ImGui (harness/CMakeLists.txt).
#include <cstdio>

#include "harness/viewer/viewer.hpp"

namespace vs {

bool viewerAvailable() { return false; }

int viewCommand(const ViewRequest&, const MethodRegistry&) {
  std::fprintf(stderr,
               "vshadow: error: this vshadow was built without the viewer (GLFW or Dear ImGui missing: "
               "install libglfw3-dev and libimgui-dev, then rebuild)\n");
  return 1;
}

}  // namespace vs
