#include "harness/viewer/viewer_input.hpp"

#include <GLFW/glfw3.h>

#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "harness/pipeline/params.hpp"

namespace vs {

int keyFromName(const std::string& name) {
  std::string n;
  for (char c : name) n += char(std::toupper(static_cast<unsigned char>(c)));
  if (n.size() == 1 && n[0] >= 'A' && n[0] <= 'Z') return GLFW_KEY_A + (n[0] - 'A');
  if (n.size() == 1 && n[0] >= '0' && n[0] <= '9') return GLFW_KEY_0 + (n[0] - '0');
  if (n.size() >= 2 && n.size() <= 3 && n[0] == 'F' && std::isdigit(static_cast<unsigned char>(n[1]))) {
    int f = std::stoi(n.substr(1));
    if (f >= 1 && f <= 12) return GLFW_KEY_F1 + f - 1;
  }
  static const std::map<std::string, int> named = {
      {"ESCAPE", GLFW_KEY_ESCAPE}, {"ESC", GLFW_KEY_ESCAPE}, {"SPACE", GLFW_KEY_SPACE}, {"TAB", GLFW_KEY_TAB},
      {"COMMA", GLFW_KEY_COMMA},   {",", GLFW_KEY_COMMA},    {"PERIOD", GLFW_KEY_PERIOD}, {".", GLFW_KEY_PERIOD},
      {"LEFT", GLFW_KEY_LEFT},     {"RIGHT", GLFW_KEY_RIGHT}, {"UP", GLFW_KEY_UP},          {"DOWN", GLFW_KEY_DOWN},
      {"HOME", GLFW_KEY_HOME},     {"END", GLFW_KEY_END}};
  auto it = named.find(n);
  return it == named.end() ? -1 : it->second;
}

static double number(const std::string& text, const std::string& where, const char* what) {
  try {
    size_t used = 0;
    double v = std::stod(text, &used);
    if (used == text.size() && std::isfinite(v)) return v;
  } catch (const std::exception&) {
  }
  throw UsageError(where + ": " + what + " '" + text + "' is not a finite number");
}

std::vector<ScriptCommand> parseScript(const std::string& text, const std::string& origin) {
  std::vector<ScriptCommand> commands;
  std::istringstream in(text);
  std::string line;
  int lineNo = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    if (auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    std::istringstream words(line);
    std::vector<std::string> w;
    for (std::string word; words >> word;) w.push_back(word);
    if (w.empty()) continue;
    ScriptCommand c;
    c.line = lineNo;
    c.where = origin + ":" + std::to_string(lineNo);
    const std::string& op = w[0];
    auto expect = [&](size_t n, const char* usage) {
      if (w.size() != n + 1) throw UsageError(c.where + ": expected '" + usage + "'");
    };
    if (op == "frame" || op == "frames") {
      expect(1, "frame N");
      double n = number(w[1], c.where, "frame count");
      if (n < 1 || n > 1e6 || n != std::floor(n)) throw UsageError(c.where + ": frame count must be 1..1000000");
      c.op = ScriptCommand::Op::Frames;
      c.count = int(n);
    } else if (op == "key") {
      if (w.size() < 2) throw UsageError(c.where + ": expected 'key NAME...'");
      c.op = ScriptCommand::Op::Key;
      for (size_t i = 1; i < w.size(); ++i) {
        int key = keyFromName(w[i]);
        if (key < 0) throw UsageError(c.where + ": unknown key '" + w[i] + "'");
        c.keys.push_back(key);
      }
    } else if (op == "look" || op == "light") {
      expect(2, op == "look" ? "look DX DY" : "light DX DY");
      c.op = op == "look" ? ScriptCommand::Op::Look : ScriptCommand::Op::Light;
      c.x = number(w[1], c.where, "DX");
      c.y = number(w[2], c.where, "DY");
    } else if (op == "move") {
      expect(3, "move FORWARD RIGHT UP");
      c.op = ScriptCommand::Op::Move;
      c.x = number(w[1], c.where, "FORWARD");
      c.y = number(w[2], c.where, "RIGHT");
      c.z = number(w[3], c.where, "UP");
    } else if (op == "param") {
      expect(2, "param KEY VALUE");
      c.op = ScriptCommand::Op::Param;
      c.key = w[1];
      c.value = w[2];
    } else if (op == "screenshot" || op == "scene") {
      expect(1, op == "scene" ? "scene FILE.json" : "screenshot FILE.png");
      c.op = op == "scene" ? ScriptCommand::Op::Scene : ScriptCommand::Op::Screenshot;
      c.value = w[1];
    } else if (op == "seek") {
      expect(1, "seek FRAME");
      double n = number(w[1], c.where, "frame");
      if (n < 0 || n > 1e9 || n != std::floor(n)) throw UsageError(c.where + ": seek takes a frame number 0, 1, 2, ...");
      c.op = ScriptCommand::Op::Seek;
      c.count = int(n);
    } else if (op == "quit") {
      expect(0, "quit");
      c.op = ScriptCommand::Op::Quit;
    } else {
      throw UsageError(c.where + ": unknown command '" + op +
                       "' (frame, key, look, light, move, param, seek, screenshot, scene, quit)");
    }
    commands.push_back(std::move(c));
  }
  return commands;
}

std::vector<ScriptCommand> readScript(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw UsageError("--script " + path + ": cannot read the file");
  std::ostringstream text;
  text << in.rdbuf();
  return parseScript(text.str(), path);
}

}  // namespace vs
