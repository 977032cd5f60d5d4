#include "harness/shootout/request.hpp"

#include <regex>

#include "harness/pipeline/params.hpp"

namespace vs {

void parseSize(const std::string& text, int& w, int& h) {
  std::smatch m;
  static const std::regex re(R"(^(\d{1,6})x(\d{1,6})$)");
  if (!std::regex_match(text, m, re)) throw UsageError("--size '" + text + "': expected WxH, e.g. 512x512");
  w = std::stoi(m[1]);
  h = std::stoi(m[2]);
  if (w < 1 || h < 1) throw UsageError("--size '" + text + "': width and height must be at least 1");
}

}  // namespace vs
