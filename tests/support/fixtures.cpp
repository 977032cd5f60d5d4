#include "fixtures.hpp"

#include <OpenImageIO/imageio.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>

namespace vs::testing {

std::string base64(const std::vector<unsigned char>& bytes) {
  static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    size_t available = std::min<size_t>(3, bytes.size() - i);
    uint32_t chunk = uint32_t(bytes[i]) << 16;
    if (available > 1) chunk |= uint32_t(bytes[i + 1]) << 8;
    if (available > 2) chunk |= bytes[i + 2];
    out += alphabet[(chunk >> 18) & 63];
    out += alphabet[(chunk >> 12) & 63];
    out += available > 1 ? alphabet[(chunk >> 6) & 63] : '=';
    out += available > 2 ? alphabet[chunk & 63] : '=';
  }
  return out;
}

std::vector<unsigned char> makeGlb(std::string json, std::vector<unsigned char> bin) {
  while (json.size() % 4) json += ' ';
  while (bin.size() % 4) bin.push_back(0);
  std::vector<unsigned char> out;
  auto put32 = [&](uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back((unsigned char)(v >> (8 * i)));
  };
  put32(0x46546C67);  // "glTF"
  put32(2);
  put32(uint32_t(12 + 8 + json.size() + 8 + bin.size()));
  put32(uint32_t(json.size()));
  put32(0x4E4F534A);  // "JSON"
  out.insert(out.end(), json.begin(), json.end());
  put32(uint32_t(bin.size()));
  put32(0x004E4942);  // "BIN\0"
  out.insert(out.end(), bin.begin(), bin.end());
  return out;
}

namespace {

std::vector<unsigned char> readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<unsigned char>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

}  // namespace

std::string writeAlphaQuadGltf(const std::string& dir, const std::string& name, const std::string& mode, double cutoff,
                               int width, int heightPixels, const std::vector<float>& alpha, double size, double height,
                               const std::string& form) {
  if (form != "file" && form != "data-uri" && form != "buffer-view" && form != "glb")
    throw std::invalid_argument("writeAlphaQuadGltf: unknown form " + form);
  std::vector<unsigned char> rgba(size_t(width) * size_t(heightPixels) * 4);
  for (size_t i = 0; i < alpha.size() && i * 4 + 3 < rgba.size(); ++i) {
    rgba[i * 4] = rgba[i * 4 + 1] = rgba[i * 4 + 2] = 200;
    rgba[i * 4 + 3] = (unsigned char)(alpha[i] * 255.0f + 0.5f);
  }
  const std::string pngPath = dir + "/" + name + ".png";
  auto out = OIIO::ImageOutput::create(pngPath);
  OIIO::ImageSpec spec(width, heightPixels, 4, OIIO::TypeDesc::UINT8);
  if (!out || !out->open(pngPath, spec) || !out->write_image(OIIO::TypeDesc::UINT8, rgba.data()))
    throw std::runtime_error("cannot write the test texture");
  out->close();

  float h = float(size / 2), y = float(height);
  const float positions[12] = {-h, y, -h, h, y, -h, h, y, h, -h, y, h};
  const float uvs[8] = {0, 0, 1, 0, 1, 1, 0, 1};
  const uint32_t indices[6] = {0, 2, 1, 0, 3, 2};
  std::vector<unsigned char> bin(sizeof positions + sizeof uvs + sizeof indices);
  std::memcpy(&bin[0], positions, sizeof positions);
  std::memcpy(&bin[sizeof positions], uvs, sizeof uvs);
  std::memcpy(&bin[sizeof positions + sizeof uvs], indices, sizeof indices);
  const size_t geometryBytes = bin.size();  // 104

  std::string image, bufferUri, imageView;
  if (form == "file") {
    std::ofstream(dir + "/" + name + ".bin", std::ios::binary).write(reinterpret_cast<const char*>(bin.data()), long(bin.size()));
    image = R"({"uri": ")" + name + R"(.png"})";
    bufferUri = R"("uri": ")" + name + R"(.bin", )";
  } else {
    std::vector<unsigned char> png = readBytes(pngPath);
    std::filesystem::remove(pngPath);  // the loader must find the image where the file says
    if (form == "data-uri") {
      image = R"({"uri": "data:image/png;base64,)" + base64(png) + R"("})";
    } else {
      bin.insert(bin.end(), png.begin(), png.end());
      image = R"({"bufferView": 3, "mimeType": "image/png"})";
      imageView = R"(, {"buffer": 0, "byteOffset": )" + std::to_string(geometryBytes) + R"(, "byteLength": )" +
                  std::to_string(png.size()) + "}";
    }
    if (form != "glb") bufferUri = R"("uri": "data:application/octet-stream;base64,)" + base64(bin) + R"(", )";
  }
  std::string cutoffKey = mode == "MASK" ? ", \"alphaCutoff\": " + std::to_string(cutoff) : "";
  std::string json = R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
    "materials": [{"alphaMode": ")" + mode + "\"" + cutoffKey + R"(, "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
    "textures": [{"source": 0}], "images": [)" + image + R"(],
    "buffers": [{)" + bufferUri + R"("byteLength": )" + std::to_string(bin.size()) + R"(}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 32},
                    {"buffer": 0, "byteOffset": 80, "byteLength": 24})" + imageView + R"(],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, 0, -1], "max": [1, 1, 1]},
                  {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
                  {"bufferView": 2, "componentType": 5125, "count": 6, "type": "SCALAR"}]})";
  if (form == "glb") {
    std::vector<unsigned char> glb = makeGlb(json, bin);
    std::string path = dir + "/" + name + ".glb";
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(glb.data()), long(glb.size()));
    return path;
  }
  std::string path = dir + "/" + name + ".gltf";
  std::ofstream(path) << json;
  return path;
}

}  // namespace vs::testing
