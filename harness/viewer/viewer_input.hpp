// Scripted input for vshadow view (--script FILE): one command per line, '#' starts a comment.
//   frame N            render N frames (also "frames N")
//   key NAME...        press keys, as on the keyboard: 1-9, A-Z, F1-F12, ESCAPE, SPACE, TAB,
//                      COMMA, PERIOD, LEFT, RIGHT, UP, DOWN, HOME, END (the viewer's key table,
//                      README "Viewer")
//   look DX DY         turn the camera as a mouse drag of DX, DY pixels would
//   light DX DY        move the light as a right-button drag of DX, DY pixels would
//   move F R U         fly the camera F forward, R right, U up (scene units)
//   param KEY VALUE    set a parameter of the current method (validated as on the command line)
//   seek FRAME         show frame FRAME of a moving scene's sequence, paused
//   screenshot FILE    FILE.png (what the view shows) and FILE.exr (its linear image)
//   scene FILE         the scene with the current camera and light, as scene JSON
//   quit               stop here
#pragma once
#include <string>
#include <vector>

namespace vs {

struct ScriptCommand {
  enum class Op { Frames, Key, Look, Light, Move, Param, Seek, Screenshot, Scene, Quit };
  Op op = Op::Frames;
  int count = 0;                   // Frames; Seek: the frame
  std::vector<int> keys;           // Key: GLFW key codes
  double x = 0, y = 0, z = 0;      // Look, Light (x, y), Move (x, y, z)
  std::string key, value;          // Param; Screenshot and Scene: value = the file
  int line = 0;
  std::string where;               // "FILE:LINE", for messages
};

// Throws UsageError "FILE:LINE: ..." for an unknown command, key or a malformed argument.
std::vector<ScriptCommand> parseScript(const std::string& text, const std::string& origin);
std::vector<ScriptCommand> readScript(const std::string& path);
// GLFW key code for a key name ("L", "2", "F1", "ESCAPE"); -1 when unknown.
int keyFromName(const std::string& name);

}  // namespace vs
