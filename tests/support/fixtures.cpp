#include "fixtures.hpp"

#include <OpenImageIO/imageio.h>

#include <cstring>
#include <fstream>
#include <stdexcept>

namespace vs::testing {

std::string writeAlphaQuadGltf(const std::string& dir, const std::string& name, const std::string& mode, double cutoff,
                               int width, int heightPixels, const std::vector<float>& alpha, double size, double height) {
  std::vector<unsigned char> rgba(size_t(width) * size_t(heightPixels) * 4);
  for (size_t i = 0; i < alpha.size() && i * 4 + 3 < rgba.size(); ++i) {
    rgba[i * 4] = rgba[i * 4 + 1] = rgba[i * 4 + 2] = 200;
    rgba[i * 4 + 3] = (unsigned char)(alpha[i] * 255.0f + 0.5f);
  }
  auto out = OIIO::ImageOutput::create(dir + "/" + name + ".png");
  OIIO::ImageSpec spec(width, heightPixels, 4, OIIO::TypeDesc::UINT8);
  if (!out || !out->open(dir + "/" + name + ".png", spec) || !out->write_image(OIIO::TypeDesc::UINT8, rgba.data()))
    throw std::runtime_error("cannot write the test texture");
  out->close();

  float h = float(size / 2), y = float(height);
  const float positions[12] = {-h, y, -h, h, y, -h, h, y, h, -h, y, h};
  const float uvs[8] = {0, 0, 1, 0, 1, 1, 0, 1};
  const uint32_t indices[6] = {0, 2, 1, 0, 3, 2};
  std::string bin(sizeof positions + sizeof uvs + sizeof indices, '\0');
  std::memcpy(&bin[0], positions, sizeof positions);
  std::memcpy(&bin[sizeof positions], uvs, sizeof uvs);
  std::memcpy(&bin[sizeof positions + sizeof uvs], indices, sizeof indices);
  std::ofstream(dir + "/" + name + ".bin", std::ios::binary) << bin;
  std::string cutoffKey = mode == "MASK" ? ", \"alphaCutoff\": " + std::to_string(cutoff) : "";
  std::string json = R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
    "materials": [{"alphaMode": ")" + mode + "\"" + cutoffKey + R"(, "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
    "textures": [{"source": 0}], "images": [{"uri": ")" + name + R"(.png"}],
    "buffers": [{"uri": ")" + name + R"(.bin", "byteLength": 104}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 32},
                    {"buffer": 0, "byteOffset": 80, "byteLength": 24}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, 0, -1], "max": [1, 1, 1]},
                  {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
                  {"bufferView": 2, "componentType": 5125, "count": 6, "type": "SCALAR"}]})";
  std::string path = dir + "/" + name + ".gltf";
  std::ofstream(path) << json;
  return path;
}

}  // namespace vs::testing
