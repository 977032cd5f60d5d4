// Binding points, one typed table. GL keeps four separate sets of them (texture units, image
// units, uniform-block and storage-block bindings); a slot carries its set in its type, so a
// texture unit cannot be passed where an image unit is meant.
//
// The shared slots are named here once: C++ binds them by these constants, and every shader sees
// them as VS_* macros (added after #version by gl::buildProgram). Each set keeps a range for the
// method being run. When a program links, its active resources are checked against this table
// (checkProgramInterface): a shared resource must sit on its slot, a program built from methods/
// may put nothing of its own outside the method range, and no two resources of a program may
// share a slot. Its uniform blocks are checked against their C++ std140 mirrors too.
#pragma once
#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <cstddef>
#include <set>
#include <string>
#include <vector>

namespace vs::bind {

enum class Kind { TextureUnit, ImageUnit, UniformBlock, StorageBlock };
const char* kindName(Kind kind);

template <Kind K>
struct Slot {
  GLuint index;
  constexpr operator GLuint() const { return index; }
};
using TextureUnit = Slot<Kind::TextureUnit>;
using ImageUnit = Slot<Kind::ImageUnit>;
using UniformBlock = Slot<Kind::UniformBlock>;
using StorageBlock = Slot<Kind::StorageBlock>;

// Slots [first, end) of one set.
struct Range {
  GLuint first, end;
  constexpr bool contains(GLuint i) const { return i >= first && i < end; }
};

// Texture units (sampler uniforms).
constexpr TextureUnit kShadowMap2D{0};       // sampler2DShadow (spot, directional)
constexpr TextureUnit kShadowMapCube{1};     // samplerCubeShadow (point)
constexpr TextureUnit kLightTexture{2};      // sampler2D, linear RGB
constexpr TextureUnit kGPosition{3};         // xyz world position of the first hit (far plane if none), w distance
constexpr TextureUnit kGNormal{4};           // xyz normal facing the eye, w = 1 on geometry, 0 on sky
constexpr TextureUnit kGAlbedo{5};
constexpr TextureUnit kDirect{6};            // L_surf
constexpr TextureUnit kInscatter{7};         // L_s
constexpr TextureUnit kShadowDepth2D{8};     // the 2D shadow map as plain depth (sampler2D)
constexpr TextureUnit kShadowDepthCube{9};   // the cube shadow map as plain depth (samplerCube)
constexpr TextureUnit kFirstMethodUnit{10};  // units 10-15 belong to the method
constexpr TextureUnit kVolumeDensity0{16};   // sampler3D per volume: units 16 .. 16 + kMaxVolumes - 1
constexpr TextureUnit kVolumeTransmittance{20};  // camera rays' RGB transmittance through volume data
constexpr TextureUnit kAlphaTexture{21};     // sampler2D: the alpha texture of the mesh being drawn
constexpr Range kMethodTextureUnits{10, 16};

// Image units.
constexpr ImageUnit kWorkCounters{6};        // uimage2DArray r32ui: harness/gl/work_counters.hpp
constexpr ImageUnit kTransmittanceHeads{7};  // uimage2DArray: first node per light texel and face
constexpr Range kMethodImageUnits{0, 6};

// Uniform-block bindings.
constexpr UniformBlock kFrameUniforms{0};
constexpr UniformBlock kVolumeUniforms{1};
constexpr UniformBlock kTransmittanceUniforms{2};
constexpr Range kMethodUniformBlocks{3, 8};

// Storage-block bindings.
constexpr StorageBlock kTransmittanceNodes{7};
constexpr StorageBlock kTransmittanceCounter{8};  // the transmittance map's build pass only
constexpr Range kMethodStorageBlocks{0, 7};

Range methodRange(Kind kind);

// A shared slot: its GLSL resource (a sampler or image uniform, or a block's name) and the macro
// shaders use for it.
struct SharedSlot {
  Kind kind;
  GLuint index;
  const char* resource;
  const char* macro;
};
const std::vector<SharedSlot>& sharedSlots();
// "#define VS_... N" per shared slot, one per line.
std::string glslDefines();

}  // namespace vs::bind

namespace vs::gl {

// A C++ struct that mirrors a GLSL std140 uniform block, member by member.
struct Std140Field {
  std::string glsl;  // the member's name in the block
  size_t offset;
  size_t bytes;
};
struct Std140Mirror {
  std::string block;    // the GLSL block name
  std::string cppType;
  std::string source;   // the file that declares the mirror
  size_t bytes;
  std::vector<Std140Field> fields;
};
// Registers a mirror (static initialisation; see VS_STD140_MIRROR). Returns true.
bool registerStd140Mirror(Std140Mirror mirror);
const std::vector<Std140Mirror>& std140Mirrors();
// Blocks whose mirror some linked program of this process was checked against.
std::set<std::string> checkedStd140Blocks();

// Checks a linked program's active resources against the binding table and its uniform blocks
// against their mirrors; throws GlError naming `what` and every problem. `methodProgram`: built
// from a method's shaders, so its own resources must lie in the method ranges.
void checkProgramInterface(GLuint program, const std::string& what, bool methodProgram);

}  // namespace vs::gl

#define VS_STD140_FIELD(Type, member) \
  vs::gl::Std140Field { #member, offsetof(Type, member), sizeof(Type::member) }
#define VS_STD140_FIELD_AS(Type, member, glslName) \
  vs::gl::Std140Field { glslName, offsetof(Type, member), sizeof(Type::member) }
#define VS_STD140_CONCAT2(a, b) a##b
#define VS_STD140_CONCAT(a, b) VS_STD140_CONCAT2(a, b)
// VS_STD140_MIRROR(Type, "BlockName", VS_STD140_FIELD(Type, a), ...): at namespace scope in a .cpp.
#define VS_STD140_MIRROR(Type, blockName, ...)                                           \
  [[maybe_unused]] static const bool VS_STD140_CONCAT(vsStd140Mirror_, __LINE__) =     \
      vs::gl::registerStd140Mirror({blockName, #Type, __FILE__, sizeof(Type), {__VA_ARGS__}})
