// Built-in scenes: the JSON files in scenes/builtin/, compiled into the binary by the build.
#include <map>

#include "scenes/builtin_scenes.hpp"

namespace vs {

const std::map<std::string, std::string>& embeddedSceneFiles();  // generated at build time

const std::vector<std::pair<std::string, std::string>>& builtinSceneSources() {
  static const std::vector<std::pair<std::string, std::string>> sources = [] {
    std::vector<std::pair<std::string, std::string>> list;
    const std::string prefix = "scenes/builtin/", suffix = ".json";
    for (const auto& [path, text] : embeddedSceneFiles()) {
      if (path.rfind(prefix, 0) != 0 || path.size() <= prefix.size() + suffix.size()) continue;
      list.emplace_back(path.substr(prefix.size(), path.size() - prefix.size() - suffix.size()), text);
    }
    return list;
  }();
  return sources;
}

}  // namespace vs
