// Scene files written by tests: a glTF quad whose material takes its alpha from a texture.
#pragma once
#include <string>
#include <vector>

namespace vs::testing {

// Writes `name`.gltf, `name`.bin and `name`.png into `dir`: a horizontal square of side `size`
// centred at (0, height, 0), texture coordinates (0, 0)..(1, 1), material alphaMode `mode`
// ("BLEND" or "MASK", with `cutoff`) whose baseColorTexture is a width x height RGBA PNG with the
// given alpha values (row 0 = top). Returns the .gltf path.
// `form` says where the PNG and the buffer live: "file" (the files above), "data-uri" (.gltf whose
// buffer and image are base64 data: URIs), "buffer-view" (.gltf with a base64 buffer holding the
// PNG in a buffer view) or "glb" (`name`.glb, the PNG in a buffer view of the binary chunk; the
// path returned is the .glb). Only "file" leaves a .png and a .bin beside it.
std::string writeAlphaQuadGltf(const std::string& dir, const std::string& name, const std::string& mode, double cutoff,
                               int width, int heightPixels, const std::vector<float>& alpha, double size, double height,
                               const std::string& form = "file");

// Base64 (RFC 4648, with padding) and a binary glTF (.glb) of a JSON chunk and a BIN chunk.
std::string base64(const std::vector<unsigned char>& bytes);
std::vector<unsigned char> makeGlb(std::string json, std::vector<unsigned char> bin);

}  // namespace vs::testing
