#include "scenes/gltf_loader.hpp"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <tiny_gltf.h>
#include <glm/gtc/quaternion.hpp>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include "scenes/json_reader.hpp"
#include "scenes/mesh_utils.hpp"

namespace vs {

namespace {

// tinygltf does not decode images: it hands over each image's encoded bytes, whatever their form
// (a file, a data: URI or a buffer view, as in every .glb), and they are kept by image index. The
// loader decodes only the base-colour textures of BLEND and MASK materials, with OpenImageIO from
// memory, for their alpha channel; the other images are never decoded.
using ImageBytes = std::map<int, std::vector<unsigned char>>;
struct ImageSink {
  ImageBytes kept;
  const tinygltf::Model* model;  // being loaded: its buffers and buffer views are read already
};
bool keepImageBytes(tinygltf::Image* image, const int index, std::string*, std::string*, int, int,
                    const unsigned char* bytes, int size, void* user) {
  auto* sink = static_cast<ImageSink*>(user);
  if (!bytes || size <= 0) return true;
  // tinygltf hands over a buffer view's bytes without checking that the view lies inside its
  // buffer: such an image is left out (an error if a material needs it), never read past its end.
  if (image && image->bufferView >= 0) {
    const tinygltf::Model& m = *sink->model;
    if (size_t(image->bufferView) >= m.bufferViews.size()) return true;
    const tinygltf::BufferView& view = m.bufferViews[size_t(image->bufferView)];
    if (view.buffer < 0 || size_t(view.buffer) >= m.buffers.size()) return true;
    const size_t length = m.buffers[size_t(view.buffer)].data.size();
    if (view.byteOffset > length || view.byteLength > length - view.byteOffset || size_t(size) > view.byteLength)
      return true;
  }
  sink->kept[index].assign(bytes, bytes + size);
  return true;
}

// The OpenImageIO format of encoded image bytes: by their signature, else by the MIME type or the
// file name; "" when neither says PNG or JPEG.
std::string imageFormat(const std::vector<unsigned char>& bytes, const std::string& mimeType, const std::string& uri) {
  static const unsigned char png[8] = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a};
  if (bytes.size() >= 8 && std::equal(png, png + 8, bytes.begin())) return "png";
  if (bytes.size() >= 3 && bytes[0] == 0xff && bytes[1] == 0xd8 && bytes[2] == 0xff) return "jpeg";
  std::string ext = std::filesystem::path(uri).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (mimeType == "image/png" || ext == ".png") return "png";
  if (mimeType == "image/jpeg" || ext == ".jpg" || ext == ".jpeg") return "jpeg";
  return "";
}

// Why PNG bytes are corrupt in their chunk structure ("" when every chunk fits up to IEND): a chunk
// that declares more bytes than the file holds made the decoder ask for what it declared (a
// fuzzed tEXt length: 2 GB for a 2x2 image), so it is refused before decoding.
std::string pngChunkProblem(const std::vector<unsigned char>& bytes) {
  size_t at = 8;  // after the signature
  while (at + 8 <= bytes.size()) {
    uint32_t length = uint32_t(bytes[at]) << 24 | uint32_t(bytes[at + 1]) << 16 | uint32_t(bytes[at + 2]) << 8 |
                      uint32_t(bytes[at + 3]);
    std::string type;
    for (size_t k = at + 4; k < at + 8; ++k) type += std::isalpha(bytes[k]) ? char(bytes[k]) : '?';
    size_t left = bytes.size() - at - 8;  // after the length and type
    if (length > left || left - length < 4)
      return "chunk " + type + " declares " + std::to_string(length) + " bytes where " +
             std::to_string(left < 4 ? 0 : left - 4) + " remain";
    if (type == "IEND") return "";
    at += 12 + size_t(length);  // length, type, data, CRC
  }
  return "it ends before its IEND chunk";
}

bool allFinite(const std::vector<double>& values) {
  for (double v : values)
    if (!std::isfinite(v)) return false;
  return true;
}

// A validated accessor: every element lies inside its buffer view, which lies inside its buffer.
struct AccessorView {
  const unsigned char* data = nullptr;  // first element; nullptr = all zeros (no buffer view)
  size_t stride = 0, count = 0;
};

class GltfReader {
 public:
  GltfReader(const std::string& path, const tinygltf::Model& model, ImageBytes images)
      : path_(path), model_(model), imageBytes_(std::move(images)) {}

  [[noreturn]] void fail(const std::string& problem) const { throwSceneError(path_, "", problem); }

  // Reports the meshes read as `stage`, by the share of the file's vertices (counted over every
  // POSITION accessor; instanced meshes are read more than once, so the share is a guide).
  void reportTo(const LoadProgress& progress, std::string stage) {
    progress_ = progress;
    stage_ = std::move(stage);
    verticesToRead_ = 0;
    for (const tinygltf::Mesh& mesh : model_.meshes)
      for (const tinygltf::Primitive& primitive : mesh.primitives) {
        auto position = primitive.attributes.find("POSITION");
        if (position != primitive.attributes.end() && position->second >= 0 && size_t(position->second) < model_.accessors.size())
          verticesToRead_ += model_.accessors[size_t(position->second)].count;
      }
  }

  GltfContent read(const glm::mat4& transform) {
    std::vector<int> roots;
    if (!model_.scenes.empty()) {
      int sceneIndex = model_.defaultScene >= 0 ? model_.defaultScene : 0;
      if (size_t(sceneIndex) >= model_.scenes.size()) fail("default scene " + std::to_string(sceneIndex) + " does not exist");
      roots = model_.scenes[size_t(sceneIndex)].nodes;
    } else {
      std::vector<bool> isChild(model_.nodes.size(), false);
      for (const tinygltf::Node& node : model_.nodes)
        for (int child : node.children)
          if (child >= 0 && size_t(child) < isChild.size()) isChild[size_t(child)] = true;
      for (size_t n = 0; n < model_.nodes.size(); ++n)
        if (!isChild[n]) roots.push_back(int(n));
    }
    onPath_.assign(model_.nodes.size(), false);
    rigNodes_.assign(model_.nodes.size(), GltfRig::Node{});
    visited_.assign(model_.nodes.size(), false);
    for (int root : roots) visitNode(root, -1, transform);
    if (!model_.animations.empty()) readAnimations(transform);
    return std::move(content_);
  }

 private:
  const tinygltf::Node& nodeAt(int index) const {
    if (index < 0 || size_t(index) >= model_.nodes.size())
      fail("node index " + std::to_string(index) + " out of range (" + std::to_string(model_.nodes.size()) + " nodes)");
    return model_.nodes[size_t(index)];
  }

  glm::mat4 localMatrix(int index, const tinygltf::Node& node) const {
    std::string where = "node " + std::to_string(index) + ": ";
    if (!allFinite(node.matrix) || !allFinite(node.translation) || !allFinite(node.rotation) || !allFinite(node.scale))
      fail(where + "non-finite transform");
    if (!node.matrix.empty()) {
      if (node.matrix.size() != 16) fail(where + "'matrix' must have 16 numbers");
      glm::mat4 m;
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) m[c][r] = float(node.matrix[size_t(c * 4 + r)]);  // column-major, like glTF
      return m;
    }
    glm::mat4 t(1.0f), r(1.0f), s(1.0f);
    if (!node.translation.empty()) {
      if (node.translation.size() != 3) fail(where + "'translation' must have 3 numbers");
      t[3] = glm::vec4(float(node.translation[0]), float(node.translation[1]), float(node.translation[2]), 1.0f);
    }
    if (!node.rotation.empty()) {
      if (node.rotation.size() != 4) fail(where + "'rotation' must have 4 numbers");
      glm::quat q(float(node.rotation[3]), float(node.rotation[0]), float(node.rotation[1]), float(node.rotation[2]));
      if (glm::length(q) == 0.0f) fail(where + "'rotation' is a zero quaternion");
      r = glm::mat4_cast(glm::normalize(q));
    }
    if (!node.scale.empty()) {
      if (node.scale.size() != 3) fail(where + "'scale' must have 3 numbers");
      s[0][0] = float(node.scale[0]);
      s[1][1] = float(node.scale[1]);
      s[2][2] = float(node.scale[2]);
    }
    return t * r * s;
  }

  void visitNode(int index, int parentIndex, const glm::mat4& parent) {
    const tinygltf::Node& node = nodeAt(index);
    if (onPath_[size_t(index)]) fail("node hierarchy has a cycle through node " + std::to_string(index));
    onPath_[size_t(index)] = true;
    const glm::mat4 local = localMatrix(index, node);
    glm::mat4 world = parent * local;
    recordRigNode(index, parentIndex, node, local);
    if (node.mesh >= 0) {
      addMesh(node.mesh, world);
      content_.meshNode.resize(content_.meshes.size(), index);
    }
    else if (node.mesh < -1) fail("node " + std::to_string(index) + ": mesh index " + std::to_string(node.mesh) + " out of range");
    auto lightExtension = node.extensions.find("KHR_lights_punctual");
    if (lightExtension != node.extensions.end() && !content_.hasLight) readNodeLight(index, lightExtension->second, world);
    for (int child : node.children) visitNode(child, index, world);
    onPath_[size_t(index)] = false;
  }

  // The node as the rig keeps it: its parent and rest transform (TRS, or its matrix).
  void recordRigNode(int index, int parentIndex, const tinygltf::Node& node, const glm::mat4& local) {
    GltfRig::Node& r = rigNodes_[size_t(index)];
    if (visited_[size_t(index)] && r.parent != parentIndex) multiParent_ = index;
    visited_[size_t(index)] = true;
    r.parent = parentIndex;
    r.hasMatrix = !node.matrix.empty();
    r.matrix = local;
    if (node.translation.size() == 3)
      r.translation = glm::vec3(float(node.translation[0]), float(node.translation[1]), float(node.translation[2]));
    if (node.scale.size() == 3) r.scale = glm::vec3(float(node.scale[0]), float(node.scale[1]), float(node.scale[2]));
    if (node.rotation.size() == 4)
      r.rotation = glm::normalize(
          glm::quat(float(node.rotation[3]), float(node.rotation[0]), float(node.rotation[1]), float(node.rotation[2])));
  }

  // Every animation's channels on translation, rotation and scale ("weights": morph targets, left
  // out with a warning). Keys as glTF gives them: times in seconds, strictly increasing.
  void readAnimations(const glm::mat4& placement) {
    if (multiParent_ >= 0)
      fail("node " + std::to_string(multiParent_) + " has more than one parent: its animation would be ambiguous");
    auto rig = std::make_shared<GltfRig>();
    rig->placement = placement;
    rig->nodes = rigNodes_;
    for (size_t a = 0; a < model_.animations.size(); ++a) {
      const tinygltf::Animation& animation = model_.animations[a];
      GltfRig::Clip clip;
      clip.name = animation.name;
      const std::string what = "animation " + std::to_string(a) + (animation.name.empty() ? "" : " ('" + animation.name + "')");
      for (size_t c = 0; c < animation.channels.size(); ++c) {
        const tinygltf::AnimationChannel& channel = animation.channels[c];
        const std::string where = what + " channel " + std::to_string(c);
        if (channel.target_path == "weights") {
          content_.warnings.push_back(path_ + ": " + where + " animates morph-target weights, which are not played");
          continue;
        }
        if (channel.target_path != "translation" && channel.target_path != "rotation" && channel.target_path != "scale")
          fail(where + ": unknown target path '" + channel.target_path + "'");
        if (channel.target_node < 0 || size_t(channel.target_node) >= model_.nodes.size())
          fail(where + ": target node " + std::to_string(channel.target_node) + " out of range");
        if (rig->nodes[size_t(channel.target_node)].hasMatrix)
          fail(where + ": node " + std::to_string(channel.target_node) + " has a 'matrix', which glTF forbids animating");
        if (channel.sampler < 0 || size_t(channel.sampler) >= animation.samplers.size())
          fail(where + ": sampler " + std::to_string(channel.sampler) + " out of range");
        const tinygltf::AnimationSampler& sampler = animation.samplers[size_t(channel.sampler)];
        const bool rotation = channel.target_path == "rotation";
        KeyedChannel keys = readSampler(sampler, rotation, where);
        clip.duration = std::max(clip.duration, keys.times.empty() ? 0.0f : keys.times.back());
        GltfRig::NodeChannels& node = clip.nodes[channel.target_node];
        (rotation ? node.rotation : channel.target_path == "scale" ? node.scale : node.translation) = std::move(keys);
      }
      rig->clips.push_back(std::move(clip));
    }
    content_.rig = std::move(rig);
  }

  KeyedChannel readSampler(const tinygltf::AnimationSampler& sampler, bool rotation, const std::string& where) const {
    KeyedChannel keys;
    keys.rotation = rotation;
    const std::string& mode = sampler.interpolation;
    if (mode.empty() || mode == "LINEAR") keys.mode = KeyedChannel::Mode::Linear;
    else if (mode == "STEP") keys.mode = KeyedChannel::Mode::Step;
    else if (mode == "CUBICSPLINE") keys.mode = KeyedChannel::Mode::CubicSpline;
    else fail(where + ": unknown interpolation '" + mode + "' (LINEAR, STEP or CUBICSPLINE)");
    AccessorView input = viewAccessor(sampler.input, TINYGLTF_TYPE_SCALAR, where + " input");
    if (model_.accessors[size_t(sampler.input)].componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
      fail(where + " input accessor " + std::to_string(sampler.input) + ": key times must be floats");
    if (input.count == 0) fail(where + ": no keys");
    for (size_t i = 0; i < input.count; ++i) {
      float t = 0.0f;
      if (input.data) std::memcpy(&t, input.data + i * input.stride, sizeof t);
      if (!std::isfinite(t) || t < 0.0f) fail(where + ": key time " + std::to_string(i) + " is negative or not finite");
      if (i > 0 && !(t > keys.times.back())) fail(where + ": key times must increase strictly (key " + std::to_string(i) + ")");
      keys.times.push_back(t);
    }
    std::vector<glm::vec4> out = readKeyValues(sampler.output, rotation, where + " output");
    const size_t perKey = keys.mode == KeyedChannel::Mode::CubicSpline ? 3 : 1;
    if (out.size() != perKey * keys.times.size())
      fail(where + ": " + std::to_string(out.size()) + " output values for " + std::to_string(keys.times.size()) +
           " key times" + (perKey == 3 ? " (CUBICSPLINE: 3 per key)" : ""));
    for (size_t k = 0; k < keys.times.size(); ++k) {
      if (perKey == 3) {
        keys.inTangents.push_back(out[3 * k]);
        keys.values.push_back(out[3 * k + 1]);
        keys.outTangents.push_back(out[3 * k + 2]);
      } else {
        keys.values.push_back(out[k]);
      }
      if (rotation && !(glm::length(keys.values.back()) > 0.0f)) fail(where + ": key " + std::to_string(k) + " is a zero quaternion");
    }
    if (rotation)
      for (glm::vec4& q : keys.values) q = glm::normalize(q);
    return keys;
  }

  // An animation output: VEC3 floats (translation, scale) or VEC4 (rotation: floats, or normalised
  // signed/unsigned bytes or shorts as glTF allows), every value finite.
  std::vector<glm::vec4> readKeyValues(int index, bool rotation, const std::string& what) const {
    const int type = rotation ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3;
    AccessorView view = viewAccessor(index, type, what);
    const int componentType = model_.accessors[size_t(index)].componentType;
    const int components = rotation ? 4 : 3;
    if (componentType != TINYGLTF_COMPONENT_TYPE_FLOAT && !rotation)
      fail(what + " accessor " + std::to_string(index) + ": components must be floats");
    std::vector<glm::vec4> values(view.count, glm::vec4(0.0f));
    if (!view.data) return values;
    for (size_t i = 0; i < view.count; ++i) {
      const unsigned char* element = view.data + i * view.stride;
      for (int c = 0; c < components; ++c) {
        float v = 0.0f;
        switch (componentType) {
          case TINYGLTF_COMPONENT_TYPE_FLOAT: std::memcpy(&v, element + 4 * c, 4); break;
          case TINYGLTF_COMPONENT_TYPE_BYTE: v = std::max(float(int8_t(element[c])) / 127.0f, -1.0f); break;
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: v = float(element[c]) / 255.0f; break;
          case TINYGLTF_COMPONENT_TYPE_SHORT: {
            int16_t x;
            std::memcpy(&x, element + 2 * c, 2);
            v = std::max(float(x) / 32767.0f, -1.0f);
            break;
          }
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            uint16_t x;
            std::memcpy(&x, element + 2 * c, 2);
            v = float(x) / 65535.0f;
            break;
          }
          default: fail(what + " accessor " + std::to_string(index) + ": unsupported component type");
        }
        if (!std::isfinite(v)) fail(what + " accessor " + std::to_string(index) + ": value " + std::to_string(i) + " is not finite");
        values[i][c] = v;
      }
    }
    return values;
  }

  void readNodeLight(int nodeIndex, const tinygltf::Value& extension, const glm::mat4& world) {
    std::string where = "node " + std::to_string(nodeIndex) + ": KHR_lights_punctual: ";
    if (!extension.IsObject() || !extension.Has("light") || !extension.Get("light").IsNumber())
      fail(where + "expected {\"light\": index}");
    double lightNumber = extension.Get("light").GetNumberAsDouble();
    if (lightNumber < 0 || lightNumber >= double(model_.lights.size()) || lightNumber != std::floor(lightNumber))
      fail(where + "light index " + formatNumber(lightNumber) + " out of range (" + std::to_string(model_.lights.size()) +
           " lights)");
    const tinygltf::Light& source = model_.lights[size_t(lightNumber)];
    where = "light " + formatNumber(lightNumber) + ": ";
    Light light;
    if (source.type == "point") light.type = LightType::Point;
    else if (source.type == "spot") light.type = LightType::Spot;
    else if (source.type == "directional") light.type = LightType::Directional;
    else fail(where + "unknown type '" + source.type + "'");
    if (!source.color.empty()) {
      if (source.color.size() != 3) fail(where + "'color' must have 3 numbers");
      for (int c = 0; c < 3; ++c) {
        double v = source.color[size_t(c)];
        if (!std::isfinite(v) || v < 0.0) fail(where + "'color' components must be finite and >= 0");
        light.color[c] = float(v);
      }
    }
    if (!std::isfinite(source.intensity) || source.intensity < 0.0 || source.intensity > 1e30)
      fail(where + "'intensity' must be finite and >= 0");
    light.intensity = float(source.intensity);
    if (light.type == LightType::Spot) {
      const double degreesPerRadian = 57.295779513082321;
      double inner = source.spot.innerConeAngle * degreesPerRadian, outer = source.spot.outerConeAngle * degreesPerRadian;
      if (!(inner >= 0.0 && inner <= outer && outer > 0.0 && outer < 90.0))
        fail(where + "spot cone angles must satisfy 0 <= innerConeAngle <= outerConeAngle < pi/2 (got " +
             formatNumber(source.spot.innerConeAngle) + ", " + formatNumber(source.spot.outerConeAngle) + ")");
      light.spotInnerDeg = float(inner);
      light.spotOuterDeg = float(outer);
    }
    // glTF lights sit at the node origin and shine along the node's -Z axis.
    light.position = glm::vec3(world * glm::vec4(0, 0, 0, 1));
    glm::vec3 direction = glm::mat3(world) * glm::vec3(0, 0, -1);
    float length = glm::length(direction);
    if (!(length > 0.0f) || !std::isfinite(length) || !std::isfinite(light.position.x + light.position.y + light.position.z))
      fail(where + "the node transform of the light is degenerate");
    light.direction = direction / length;
    content_.light = light;
    content_.hasLight = true;
  }

  AccessorView viewAccessor(int index, int wantedType, const std::string& what) const {
    std::string where = what + " accessor " + std::to_string(index) + ": ";
    if (index < 0 || size_t(index) >= model_.accessors.size())
      fail(what + ": accessor index " + std::to_string(index) + " out of range (" +
           std::to_string(model_.accessors.size()) + " accessors)");
    const tinygltf::Accessor& accessor = model_.accessors[size_t(index)];
    if (accessor.sparse.isSparse) fail(where + "sparse accessors are not supported");
    if (accessor.type != wantedType) fail(where + "unexpected element type");
    size_t componentSize = 0;
    switch (accessor.componentType) {
      case TINYGLTF_COMPONENT_TYPE_BYTE:
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: componentSize = 1; break;
      case TINYGLTF_COMPONENT_TYPE_SHORT:
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: componentSize = 2; break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      case TINYGLTF_COMPONENT_TYPE_FLOAT: componentSize = 4; break;
      default: fail(where + "unsupported component type " + std::to_string(accessor.componentType));
    }
    const size_t elementSize =
        componentSize * (wantedType == TINYGLTF_TYPE_VEC4   ? 4
                         : wantedType == TINYGLTF_TYPE_VEC3 ? 3
                         : wantedType == TINYGLTF_TYPE_VEC2 ? 2
                                                            : 1);
    AccessorView view;
    view.count = accessor.count;
    view.stride = elementSize;
    if (accessor.bufferView < 0) {  // glTF: an accessor without a buffer view reads as zeros
      if (accessor.count > (size_t(1) << 28)) fail(where + "count too large");
      return view;
    }
    if (size_t(accessor.bufferView) >= model_.bufferViews.size())
      fail(where + "bufferView index " + std::to_string(accessor.bufferView) + " out of range");
    const tinygltf::BufferView& bufferView = model_.bufferViews[size_t(accessor.bufferView)];
    if (bufferView.buffer < 0 || size_t(bufferView.buffer) >= model_.buffers.size())
      fail(where + "buffer index " + std::to_string(bufferView.buffer) + " out of range");
    const std::vector<unsigned char>& buffer = model_.buffers[size_t(bufferView.buffer)].data;
    if (bufferView.byteOffset > buffer.size() || bufferView.byteLength > buffer.size() - bufferView.byteOffset)
      fail(where + "buffer view " + std::to_string(accessor.bufferView) + " (offset " +
           std::to_string(bufferView.byteOffset) + ", length " + std::to_string(bufferView.byteLength) +
           ") exceeds its buffer of " + std::to_string(buffer.size()) + " bytes");
    if (bufferView.byteStride != 0) {
      if (bufferView.byteStride < elementSize) fail(where + "byteStride smaller than the element size");
      view.stride = bufferView.byteStride;
    }
    if (accessor.count > 0) {
      // Last byte needed: byteOffset + stride * (count - 1) + elementSize, computed without overflow.
      size_t available = bufferView.byteLength;
      bool fits = accessor.byteOffset <= available && elementSize <= available - accessor.byteOffset &&
                  (accessor.count - 1) <= (available - accessor.byteOffset - elementSize) / view.stride;
      if (!fits)
        fail(where + std::to_string(accessor.count) + " elements at offset " + std::to_string(accessor.byteOffset) +
             " exceed buffer view " + std::to_string(accessor.bufferView) + " (" + std::to_string(available) + " bytes)");
    }
    view.data = buffer.data() + bufferView.byteOffset + accessor.byteOffset;
    return view;
  }

  std::vector<glm::vec2> readVec2(int index, const std::string& what) const {
    AccessorView view = viewAccessor(index, TINYGLTF_TYPE_VEC2, what);
    if (model_.accessors[size_t(index)].componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
      fail(what + " accessor " + std::to_string(index) + ": components must be floats");
    std::vector<glm::vec2> values(view.count, glm::vec2(0.0f));
    if (view.data)
      for (size_t i = 0; i < view.count; ++i) std::memcpy(&values[i], view.data + i * view.stride, sizeof(glm::vec2));
    return values;
  }

  // The alpha channel of image `imageIndex` (decoded once), as an index into content_.alphaTextures;
  // -1 when the image has no alpha channel (then it cannot change the opacity).
  int alphaTexture(int imageIndex, const std::string& what) {
    auto cached = decoded_.find(imageIndex);
    if (cached != decoded_.end()) return cached->second;
    if (imageIndex < 0 || size_t(imageIndex) >= model_.images.size())
      fail(what + ": image index " + std::to_string(imageIndex) + " out of range");
    const tinygltf::Image& image = model_.images[size_t(imageIndex)];
    std::string where = what + ": image " + std::to_string(imageIndex);
    const bool file = !image.uri.empty();  // tinygltf keeps the uri of file images only
    if (file) where += " ('" + image.uri + "')";
    auto found = imageBytes_.find(imageIndex);
    if (found == imageBytes_.end())
      fail(where + (file ? ": cannot open '" + (std::filesystem::path(path_).parent_path() / image.uri).string() + "'"
                         : ": no image data"));
    const std::vector<unsigned char>& bytes = found->second;
    if (file) imageFiles_.emplace_back(bytes.begin(), bytes.end());
    const std::string format = imageFormat(bytes, image.mimeType, image.uri);
    if (format.empty()) fail(where + ": not a PNG or JPEG image");
    if (format == "png" && bytes.size() >= 8 && bytes[0] == 0x89) {
      std::string problem = pngChunkProblem(bytes);
      if (!problem.empty()) fail(where + ": corrupt PNG: " + problem);
    }
    // One path for every form: decoded from memory through an IOProxy, which OpenImageIO 2.x takes
    // as the "oiio:ioproxy" open hint.
    OIIO::Filesystem::IOMemReader reader(const_cast<unsigned char*>(bytes.data()), bytes.size());
    std::unique_ptr<OIIO::ImageInput> input = OIIO::ImageInput::create(format, false, nullptr, &reader);
    OIIO::ImageSpec spec, config;
    void* proxy = &reader;
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
    if (!input || !input->open("memory." + format, spec, config))
      fail(where + ": cannot decode (" + oneLine(input ? input->geterror() : OIIO::geterror()) + ")");
    return decodeAlpha(*input, imageIndex, where);
  }

  int decodeAlpha(OIIO::ImageInput& input, int imageIndex, const std::string& where) {
    const OIIO::ImageSpec& spec = input.spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.depth > 1 || size_t(spec.width) * size_t(spec.height) > (size_t(1) << 24))
      fail(where + ": not a 2D image of at most 16M pixels");
    int index = -1;
    if (spec.alpha_channel >= 0 || spec.nchannels == 4 || spec.nchannels == 2) {
      int channel = spec.alpha_channel >= 0 ? spec.alpha_channel : spec.nchannels - 1;
      AlphaTexture t;
      t.width = spec.width;
      t.height = spec.height;
      t.alpha.resize(size_t(t.width) * size_t(t.height));
      if (!input.read_image(0, 0, channel, channel + 1, OIIO::TypeDesc::FLOAT, t.alpha.data()))
        fail(where + ": cannot decode (" + oneLine(input.geterror()) + ")");
      for (float& a : t.alpha) a = std::isfinite(a) ? std::clamp(a, 0.0f, 1.0f) : 1.0f;
      index = int(content_.alphaTextures.size());
      content_.alphaTextures.push_back(std::move(t));
    }
    decoded_[imageIndex] = index;
    return index;
  }

  // Texture alpha of a BLEND/MASK material: sets mesh.alphaTexture and mesh.uvs.
  void readAlphaTexture(int materialIndex, const tinygltf::Primitive& primitive, Mesh& mesh, const std::string& what) {
    if (materialIndex < 0 || size_t(materialIndex) >= model_.materials.size()) return;
    const tinygltf::Material& m = model_.materials[size_t(materialIndex)];
    if (m.alphaMode != "BLEND" && m.alphaMode != "MASK") return;
    if (m.alphaMode == "MASK") mesh.alphaCutoff = float(m.alphaCutoff);
    const tinygltf::TextureInfo& info = m.pbrMetallicRoughness.baseColorTexture;
    if (info.index < 0) return;
    if (size_t(info.index) >= model_.textures.size()) fail(what + ": texture index " + std::to_string(info.index) + " out of range");
    int source = model_.textures[size_t(info.index)].source;
    if (source < 0) return;
    auto uvAttribute = primitive.attributes.find("TEXCOORD_" + std::to_string(std::max(info.texCoord, 0)));
    if (uvAttribute == primitive.attributes.end())
      fail(what + ": the base-colour texture needs TEXCOORD_" + std::to_string(std::max(info.texCoord, 0)));
    int texture = alphaTexture(source, what);
    if (texture < 0) return;
    mesh.uvs = readVec2(uvAttribute->second, what + " TEXCOORD");
    if (mesh.uvs.size() != mesh.positions.size()) fail(what + ": TEXCOORD and POSITION counts differ");
    mesh.alphaTexture = texture;
  }

 public:
  const std::vector<std::string>& imageFiles() const { return imageFiles_; }

 private:
  std::vector<glm::vec3> readVec3(int index, const std::string& what) const {
    AccessorView view = viewAccessor(index, TINYGLTF_TYPE_VEC3, what);
    if (model_.accessors[size_t(index)].componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
      fail(what + " accessor " + std::to_string(index) + ": components must be floats");
    std::vector<glm::vec3> values(view.count, glm::vec3(0.0f));
    if (view.data)
      for (size_t i = 0; i < view.count; ++i) std::memcpy(&values[i], view.data + i * view.stride, sizeof(glm::vec3));
    return values;
  }

  std::vector<uint32_t> readIndices(int index, const std::string& what) const {
    AccessorView view = viewAccessor(index, TINYGLTF_TYPE_SCALAR, what);
    int componentType = model_.accessors[size_t(index)].componentType;
    if (componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
      fail(what + " accessor " + std::to_string(index) + ": indices must be unsigned integers");
    std::vector<uint32_t> values(view.count, 0);
    if (!view.data) return values;
    for (size_t i = 0; i < view.count; ++i) {
      const unsigned char* element = view.data + i * view.stride;
      if (componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
        values[i] = element[0];
      } else if (componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
        uint16_t v;
        std::memcpy(&v, element, sizeof v);
        values[i] = v;
      } else {
        std::memcpy(&values[i], element, sizeof(uint32_t));
      }
    }
    return values;
  }

  glm::vec3 materialAlbedo(int materialIndex, const std::string& what) const {
    if (materialIndex < 0) return Mesh().albedo;
    if (size_t(materialIndex) >= model_.materials.size())
      fail(what + ": material index " + std::to_string(materialIndex) + " out of range");
    const std::vector<double>& factor = model_.materials[size_t(materialIndex)].pbrMetallicRoughness.baseColorFactor;
    if (factor.size() != 4) fail("material " + std::to_string(materialIndex) + ": baseColorFactor must have 4 numbers");
    glm::vec3 albedo;
    for (int c = 0; c < 3; ++c) {
      double v = factor[size_t(c)];
      if (!(v >= 0.0 && v <= 1.0))
        fail("material " + std::to_string(materialIndex) + ": baseColorFactor components must be in [0, 1]");
      albedo[c] = float(v);
    }
    return albedo;
  }

  // alphaMode BLEND: opacity = baseColorFactor alpha (times the texture's alpha per texel); MASK
  // without a texture: alpha below alphaCutoff cuts the primitive out (opacity 0), else opaque
  // (with a texture: per texel, Mesh::opacityAt); OPAQUE (default): 1.
  float materialOpacity(int materialIndex) const {
    if (materialIndex < 0 || size_t(materialIndex) >= model_.materials.size()) return 1.0f;
    const tinygltf::Material& m = model_.materials[size_t(materialIndex)];
    const std::vector<double>& factor = m.pbrMetallicRoughness.baseColorFactor;
    double alpha = factor.size() == 4 ? factor[3] : 1.0;
    if (!(alpha >= 0.0 && alpha <= 1.0))
      fail("material " + std::to_string(materialIndex) + ": baseColorFactor alpha must be in [0, 1]");
    if (m.alphaMode == "BLEND") return float(alpha);
    if (m.alphaMode == "MASK") {
      if (!(m.alphaCutoff >= 0.0 && m.alphaCutoff <= 1.0))
        fail("material " + std::to_string(materialIndex) + ": alphaCutoff must be in [0, 1]");
      if (m.pbrMetallicRoughness.baseColorTexture.index >= 0) return float(alpha);
      return alpha < m.alphaCutoff ? 0.0f : 1.0f;
    }
    if (!m.alphaMode.empty() && m.alphaMode != "OPAQUE")
      fail("material " + std::to_string(materialIndex) + ": unknown alphaMode '" + m.alphaMode + "'");
    return 1.0f;
  }

  void addMesh(int meshIndex, const glm::mat4& world) {
    if (size_t(meshIndex) >= model_.meshes.size())
      fail("mesh index " + std::to_string(meshIndex) + " out of range (" + std::to_string(model_.meshes.size()) + " meshes)");
    const tinygltf::Mesh& source = model_.meshes[size_t(meshIndex)];
    for (size_t p = 0; p < source.primitives.size(); ++p) {
      if (progress_) progress_(stage_, double(verticesRead_) / double(std::max<size_t>(verticesToRead_, 1)));
      const tinygltf::Primitive& primitive = source.primitives[p];
      std::string what = "mesh " + std::to_string(meshIndex) + " primitive " + std::to_string(p);
      int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
      if (mode < TINYGLTF_MODE_TRIANGLES) continue;  // points and lines have no surface
      if (mode > TINYGLTF_MODE_TRIANGLE_FAN) fail(what + ": unknown mode " + std::to_string(mode));
      auto positionAttribute = primitive.attributes.find("POSITION");
      if (positionAttribute == primitive.attributes.end()) fail(what + ": no POSITION attribute");

      Mesh mesh;
      mesh.name = (source.name.empty() ? "mesh" + std::to_string(meshIndex) : source.name) + "/" + std::to_string(p);
      mesh.albedo = materialAlbedo(primitive.material, what);
      mesh.opacity = materialOpacity(primitive.material);
      mesh.positions = readVec3(positionAttribute->second, what + " POSITION");
      verticesRead_ += mesh.positions.size();
      auto normalAttribute = primitive.attributes.find("NORMAL");
      if (normalAttribute != primitive.attributes.end()) {
        mesh.normals = readVec3(normalAttribute->second, what + " NORMAL");
        if (mesh.normals.size() != mesh.positions.size()) fail(what + ": NORMAL and POSITION counts differ");
      }
      readAlphaTexture(primitive.material, primitive, mesh, what);
      std::vector<uint32_t> order;
      if (primitive.indices >= 0) {
        order = readIndices(primitive.indices, what + " indices");
        for (uint32_t i : order)
          if (i >= mesh.positions.size())
            fail(what + ": index " + std::to_string(i) + " out of range (" + std::to_string(mesh.positions.size()) +
                 " vertices)");
      } else {
        order.resize(mesh.positions.size());
        for (size_t i = 0; i < order.size(); ++i) order[i] = uint32_t(i);
      }
      mesh.indices = assembleTriangles(std::move(order), mode);
      transformMesh(mesh, world);
      if (mesh.normals.empty()) computeSmoothNormals(mesh);
      content_.meshes.push_back(std::move(mesh));
    }
  }

  // Triangle list from a vertex order (glTF 2.0 spec, section 3.7.2.1).
  static std::vector<uint32_t> assembleTriangles(std::vector<uint32_t> v, int mode) {
    std::vector<uint32_t> triangles;
    if (mode == TINYGLTF_MODE_TRIANGLES) {
      v.resize(v.size() / 3 * 3);
      triangles = std::move(v);  // the list as it is: no copy of a large index buffer
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
      for (size_t i = 0; i + 2 < v.size(); ++i)
        triangles.insert(triangles.end(), {v[i], v[i + 1 + i % 2], v[i + 2 - i % 2]});
    } else {  // fan
      for (size_t i = 0; i + 2 < v.size(); ++i) triangles.insert(triangles.end(), {v[i + 1], v[i + 2], v[0]});
    }
    return triangles;
  }

  std::string path_;
  const tinygltf::Model& model_;
  LoadProgress progress_;
  std::string stage_;
  size_t verticesToRead_ = 0, verticesRead_ = 0;
  std::vector<bool> onPath_;
  std::vector<GltfRig::Node> rigNodes_;  // per node: parent and rest transform
  std::vector<bool> visited_;
  int multiParent_ = -1;                 // a node met under two parents (-1: none)
  GltfContent content_;
  std::map<int, int> decoded_;            // image index -> alpha texture index (-1: no alpha)
  ImageBytes imageBytes_;                 // image index -> encoded bytes (filled by tinygltf)
  std::vector<std::string> imageFiles_;   // external image files read (for the content hash)
};

bool isDataUri(const std::string& uri) { return uri.rfind("data:", 0) == 0; }

}  // namespace

GltfContent loadGltf(const std::string& path, const glm::mat4& transform, ContentHasher* hasher,
                     const LoadProgress& progress) {
  auto fail = [&](const std::string& problem) { throwSceneError(path, "", problem); };
  const std::string file = std::filesystem::path(path).filename().string();
  if (progress) progress(file + ": parsing", 0.0);
  std::string bytes, error;
  if (!readFile(path, bytes, error)) fail("cannot open glTF file: " + error);
  if (bytes.size() > size_t(std::numeric_limits<unsigned int>::max())) fail("file too large");
  if (hasher) hasher->addBlock(bytes);

  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  ImageSink images{{}, &model};
  loader.SetImageLoader(keepImageBytes, &images);
  std::string loadError, warning;
  std::string baseDir = std::filesystem::path(path).parent_path().string();
  bool isBinary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  bool loaded = false;
  try {
    loaded = isBinary ? loader.LoadBinaryFromMemory(&model, &loadError, &warning,
                                                    reinterpret_cast<const unsigned char*>(bytes.data()),
                                                    unsigned(bytes.size()), baseDir)
                      : loader.LoadASCIIFromString(&model, &loadError, &warning, bytes.data(), unsigned(bytes.size()),
                                                   baseDir);
  } catch (const std::exception& e) {
    loadError = e.what();
  }
  if (!loaded) fail(std::string(isBinary ? "invalid glTF binary: " : "invalid glTF: ") +
                    (loadError.empty() ? "unknown error" : oneLine(withoutExceptionTags(loadError))));
  std::string().swap(bytes);  // tinygltf copied the buffers out: the file's bytes need not wait for the meshes

  if (hasher) {
    for (const tinygltf::Buffer& buffer : model.buffers)
      if (!buffer.uri.empty() && !isDataUri(buffer.uri)) hasher->addBlock(buffer.data.data(), buffer.data.size());
  }
  GltfReader reader(path, model, std::move(images.kept));
  if (progress) reader.reportTo(progress, file + ": reading meshes");
  GltfContent content = reader.read(transform);
  if (hasher)
    for (const std::string& image : reader.imageFiles()) hasher->addBlock(image);
  return content;
}

}  // namespace vs
