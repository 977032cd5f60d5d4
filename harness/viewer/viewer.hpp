// vshadow view: an interactive window over the same frame pipeline, runner and timer as
// `vshadow run` (GLFW + Dear ImGui; README "Viewer"). Optional at build time: without GLFW or
// Dear ImGui the command says so and exits 1.
#pragma once
#include <string>
#include <vector>

#include "harness/pipeline/method.hpp"

namespace vs {

struct ViewRequest {
  std::string scene;
  std::vector<std::string> methods;  // specs; empty: every registered method at its defaults
  std::string size = "512x512";
  long long seed = 1;
  std::string timer = "auto";        // auto | gpu | wall
  std::string cacheDir;              // reference cache (empty: defaultCacheDir())
  std::string out = ".";             // folder for screenshots and scene files saved by key
  int frames = 0;                    // > 0: render this many frames, then exit (after --script)
  std::string screenshot;            // written after the frames (FILE.png and FILE.exr)
  std::string script;                // scripted input (viewer_input.hpp)
  bool strictGl = false;
};

// False when the program was built without GLFW or Dear ImGui.
bool viewerAvailable();
int viewCommand(const ViewRequest& request, const MethodRegistry& registry);

}  // namespace vs
