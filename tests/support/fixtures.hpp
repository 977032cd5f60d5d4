// Scene files written by tests: a glTF quad whose material takes its alpha from a texture.
#pragma once
#include <string>
#include <vector>

namespace vs::testing {

// Writes `name`.gltf, `name`.bin and `name`.png into `dir`: a horizontal square of side `size`
// centred at (0, height, 0), texture coordinates (0, 0)..(1, 1), material alphaMode `mode`
// ("BLEND" or "MASK", with `cutoff`) whose baseColorTexture is a width x height RGBA PNG with the
// given alpha values (row 0 = top). Returns the .gltf path.
std::string writeAlphaQuadGltf(const std::string& dir, const std::string& name, const std::string& mode, double cutoff,
                               int width, int heightPixels, const std::vector<float>& alpha, double size, double height);

}  // namespace vs::testing
