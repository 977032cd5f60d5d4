// Linear float RGB images on the CPU, and their files (OpenImageIO). Row 0 is the top row.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace vs {

struct Image {
  int width = 0, height = 0;
  std::vector<float> rgb;  // width*height*3, linear
  Image() = default;
  Image(int w, int h) : width(w), height(h), rgb(size_t(w) * size_t(h) * 3, 0.0f) {}
  float* at(int x, int y) { return &rgb[(size_t(y) * width + x) * 3]; }
  const float* at(int x, int y) const { return &rgb[(size_t(y) * width + x) * 3]; }
  bool empty() const { return rgb.empty(); }
};

// Rec. 709 luminance.
inline float luminance(const float* c) { return 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2]; }

// All writers are atomic: they write a hidden temp file in the same directory that keeps the
// extension ("<dir>/.<stem>.tmp<pid>_<n><ext>") and rename it over path. On failure the temp file is
// removed and std::runtime_error names the path and the cause. The extension picks the format.
void writeExr(const std::string& path, const Image& img);  // 32-bit float RGB
// Tonemapped PNG: c * exposure, clamp to [0,1], sRGB encoding. Non-finite pixels -> magenta.
void writePngTonemapped(const std::string& path, const Image& img, float exposure);
void writePng8(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb8);
// Reads any format OpenImageIO knows into linear RGB. Grey is replicated, channels past RGB (alpha)
// are dropped; 8/16-bit files are linearised with the sRGB EOTF unless tagged linear, float files are
// taken as linear. Throws std::runtime_error on error.
Image readImage(const std::string& path);

// Exposure that maps the 99th percentile of luminance to 0.8 (1 when the image is black).
// Non-finite pixels are ignored.
float autoExposure(const Image& img);

}  // namespace vs
