// The binding table and the std140 mirrors: what checkProgramInterface refuses when a program links.
#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include "harness/gl/bindings.hpp"
#include "harness/gl/gl.hpp"
#include "gl_test.hpp"

namespace vs {
namespace {

struct TestBlockMirror {
  glm::vec3 a;
  float b;
  glm::vec4 c[2];
};
VS_STD140_MIRROR(TestBlockMirror, "TestBlock", VS_STD140_FIELD(TestBlockMirror, a), VS_STD140_FIELD(TestBlockMirror, b),
                 VS_STD140_FIELD(TestBlockMirror, c));
// A mirror that forgot std140's rules: after a vec3, GLSL puts a vec4 on the next 16 bytes, C++ on
// the next 4.
struct WrongBlockMirror {
  glm::vec3 a;
  glm::vec4 c[2];
};
VS_STD140_MIRROR(WrongBlockMirror, "WrongBlock", VS_STD140_FIELD(WrongBlockMirror, a),
                 VS_STD140_FIELD(WrongBlockMirror, c));

class BindingsTest : public testing::GlTest {};

// A compute program from source text, with the table's macros, as buildProgram would make it.
gl::Program compute(const std::string& body) {
  std::string text = "#version 450 core\n" + bind::glslDefines() + "layout(local_size_x = 1) in;\n" + body;
  const char* source = text.c_str();
  GLuint program = glCreateShaderProgramv(GL_COMPUTE_SHADER, 1, &source);
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  EXPECT_EQ(ok, GL_TRUE) << text;
  return gl::Program(program);
}

std::string problems(const std::string& body, bool methodProgram) {
  gl::Program program = compute(body);
  try {
    gl::checkProgramInterface(program.id(), "test", methodProgram);
  } catch (const gl::GlError& e) {
    return e.what();
  }
  return "";
}

TEST_F(BindingsTest, TheTableGivesShadersOneMacroPerSharedSlot) {
  std::string defines = bind::glslDefines();
  for (const bind::SharedSlot& s : bind::sharedSlots())
    EXPECT_NE(defines.find("#define " + std::string(s.macro) + " " + std::to_string(s.index) + "\n"), std::string::npos)
        << s.macro;
  // The shared slots lie outside the method ranges of their kind (the transmittance build pass's
  // counter is the storage range's end).
  for (const bind::SharedSlot& s : bind::sharedSlots()) EXPECT_FALSE(bind::methodRange(s.kind).contains(s.index)) << s.resource;
}

TEST_F(BindingsTest, AMethodResourceOutsideTheMethodRangeIsRefused) {
  const std::string body =
      "layout(std140, binding = 1) uniform TestBlock { vec3 a; float b; vec4 c[2]; } t;\n"
      "layout(std430, binding = 0) buffer Out { vec4 v; } o;\n"
      "void main() { o.v = vec4(t.a, t.b) + t.c[1]; }\n";
  std::string message = problems(body, true);
  EXPECT_NE(message.find("TestBlock is on uniform-block binding 1, outside the method's uniform-block bindings 3-7"),
            std::string::npos)
      << message;
  EXPECT_EQ(problems(body, false), "");  // a harness pass may use any slot the table does not name
}

TEST_F(BindingsTest, TwoResourcesOnOneSlotAreRefused) {
  std::string message = problems(
      "layout(binding = 10) uniform sampler2D first;\n"
      "layout(binding = 10) uniform sampler3D second;\n"
      "layout(std430, binding = 0) buffer Out { vec4 v; } o;\n"
      "void main() { o.v = texture(first, vec2(0.5)) + texture(second, vec3(0.5)); }\n",
      true);
  EXPECT_NE(message.find("share texture unit 10"), std::string::npos) << message;
}

TEST_F(BindingsTest, ASharedResourceOffItsSlotIsRefused) {
  std::string message = problems(
      "layout(binding = 12) uniform sampler2D gPosition;\n"
      "layout(std430, binding = 0) buffer Out { vec4 v; } o;\n"
      "void main() { o.v = texture(gPosition, vec2(0.5)); }\n",
      true);
  EXPECT_NE(message.find("gPosition is on texture unit 12; the table puts it on 3 (VS_UNIT_G_POSITION)"),
            std::string::npos)
      << message;
  EXPECT_EQ(problems("layout(binding = VS_UNIT_G_POSITION) uniform sampler2D gPosition;\n"
                     "layout(std430, binding = 0) buffer Out { vec4 v; } o;\n"
                     "void main() { o.v = texture(gPosition, vec2(0.5)); }\n",
                     true),
            "");
}

TEST_F(BindingsTest, AStd140MirrorMustMatchTheBlockMemberByMember) {
  EXPECT_EQ(problems("layout(std140, binding = 3) uniform TestBlock { vec3 a; float b; vec4 c[2]; } t;\n"
                     "layout(std430, binding = 0) buffer Out { vec4 v; } o;\n"
                     "void main() { o.v = vec4(t.a, t.b) + t.c[1]; }\n",
                     true),
            "");
  EXPECT_TRUE(gl::checkedStd140Blocks().count("TestBlock"));

  std::string message = problems(
      "layout(std140, binding = 3) uniform WrongBlock { vec3 a; float b; vec4 c[2]; } w;\n"
      "layout(std430, binding = 0) buffer Out { vec4 v; } o;\n"
      "void main() { o.v = vec4(w.a, w.b) + w.c[1]; }\n",
      true);
  EXPECT_NE(message.find("WrongBlock.b is not in WrongBlockMirror"), std::string::npos) << message;
  EXPECT_NE(message.find("WrongBlock.c is at offset 16 in GLSL, 12 in WrongBlockMirror"), std::string::npos) << message;

  message = problems(
      "layout(std140, binding = 3) uniform WrongBlock { vec3 a; vec4 c[3]; } w;\n"
      "layout(std430, binding = 0) buffer Out { vec4 v; } o;\n"
      "void main() { o.v = vec4(w.a, 0.0) + w.c[1]; }\n",
      true);
  EXPECT_NE(message.find("WrongBlock.c spans 48 bytes in GLSL, 32 in WrongBlockMirror"), std::string::npos) << message;
  EXPECT_NE(message.find("WrongBlock is 64 bytes in GLSL, WrongBlockMirror"), std::string::npos) << message;
  static_assert(offsetof(WrongBlockMirror, c) == 12);
}

TEST_F(BindingsTest, AUniformBlockWithoutAMirrorIsRefused) {
  std::string message = problems(
      "layout(std140, binding = 3) uniform Unmirrored { vec4 a; } t;\n"
      "layout(std430, binding = 0) buffer Out { vec4 v; } o;\n"
      "void main() { o.v = t.a; }\n",
      true);
  EXPECT_NE(message.find("uniform block Unmirrored has no C++ std140 mirror"), std::string::npos) << message;
}

}  // namespace
}  // namespace vs
