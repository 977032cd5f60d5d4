// Image files through OpenImageIO, written atomically (temp file + rename).
#include "harness/io/image.hpp"

#include <OpenImageIO/imageio.h>
#include <OpenImageIO/strutil.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <unistd.h>

namespace vs {
namespace {

namespace fs = std::filesystem;

// OIIO error texts can span several lines; keep our messages to one line.
std::string oneLine(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  return text.empty() ? std::string("unknown error") : text;
}

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw std::runtime_error(path + ": " + oneLine(what));
}

// "<dir>/.<stem>.tmp<pid>_<n><ext>": same directory (so rename is atomic), hidden, and the
// real extension last so OIIO picks the right format.
std::string tempPathFor(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  const fs::path target(path);
  const std::string name = "." + target.stem().string() + ".tmp" + std::to_string(::getpid()) +
                           "_" + std::to_string(counter++) + target.extension().string();
  return (target.parent_path() / name).string();
}

// Writes `pixels` (interleaved, `spec.format`) to `path` via a temp file and rename.
void writeAtomically(const std::string& path, const OIIO::ImageSpec& spec, const void* pixels) {
  if (fs::path(path).extension().empty()) fail(path, "no file extension to choose an image format");
  const std::string tempPath = tempPathFor(path);
  auto out = OIIO::ImageOutput::create(tempPath);
  if (!out) fail(path, "cannot create image writer: " + OIIO::geterror());

  bool ok = out->open(tempPath, spec) && out->write_image(spec.format, pixels);
  ok = out->close() && ok;  // close even after a failed write
  if (!ok) {
    const std::string error = out->geterror();
    out.reset();
    std::remove(tempPath.c_str());
    fail(path, error);
  }
  out.reset();
  if (std::rename(tempPath.c_str(), path.c_str()) != 0) {
    const std::string error = std::strerror(errno);
    std::remove(tempPath.c_str());
    fail(path, "cannot rename temp file into place: " + error);
  }
}

void checkShape(const std::string& path, int width, int height, size_t valueCount) {
  if (width <= 0 || height <= 0) fail(path, "image has no pixels");
  if (valueCount != size_t(width) * size_t(height) * 3)
    fail(path, "pixel buffer size does not match width*height*3");
}

float srgbEncode(float linear) {  // sRGB OETF, input in [0,1]
  return linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

float srgbDecode(float encoded) {  // sRGB EOTF
  return encoded <= 0.04045f ? encoded / 12.92f : std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

bool isFloatFormat(OIIO::TypeDesc format) {
  return format.basetype == OIIO::TypeDesc::FLOAT || format.basetype == OIIO::TypeDesc::HALF ||
         format.basetype == OIIO::TypeDesc::DOUBLE;
}

// Integer-encoded files are taken as sRGB unless they say they are linear; float files are linear.
bool storesSrgb(const OIIO::ImageSpec& spec) {
  if (isFloatFormat(spec.format)) return false;
  const std::string colourSpace = spec.get_string_attribute("oiio:ColorSpace");
  return !OIIO::Strutil::iequals(colourSpace, "linear");
}

}  // namespace

void writeExr(const std::string& path, const Image& img) {
  checkShape(path, img.width, img.height, img.rgb.size());
  OIIO::ImageSpec spec(img.width, img.height, 3, OIIO::TypeDesc::FLOAT);
  spec.attribute("compression", "zip");  // lossless
  writeAtomically(path, spec, img.rgb.data());
}

void writePngTonemapped(const std::string& path, const Image& img, float exposure) {
  checkShape(path, img.width, img.height, img.rgb.size());
  std::vector<uint8_t> encoded(img.rgb.size());
  for (size_t pixel = 0; pixel < img.rgb.size(); pixel += 3) {
    const float scaled[3] = {img.rgb[pixel] * exposure, img.rgb[pixel + 1] * exposure,
                             img.rgb[pixel + 2] * exposure};
    const bool finite =
        std::isfinite(scaled[0]) && std::isfinite(scaled[1]) && std::isfinite(scaled[2]);
    for (int c = 0; c < 3; ++c) {
      if (!finite) {
        encoded[pixel + c] = (c == 1) ? 0 : 255;  // magenta flags NaN/Inf
        continue;
      }
      const float value = srgbEncode(std::clamp(scaled[c], 0.0f, 1.0f));
      encoded[pixel + c] = uint8_t(std::lround(value * 255.0f));
    }
  }
  writePng8(path, img.width, img.height, encoded);
}

void writePng8(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb8) {
  checkShape(path, width, height, rgb8.size());
  OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
  writeAtomically(path, spec, rgb8.data());
}

Image readImage(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) fail(path, "cannot open image: " + OIIO::geterror());
  const OIIO::ImageSpec spec = in->spec();
  if (spec.deep) fail(path, "deep images are not supported");
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 || spec.depth > 1)
    fail(path, "unsupported image shape");

  const int channels = spec.nchannels;
  std::vector<float> file(size_t(spec.width) * size_t(spec.height) * size_t(channels));
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, file.data())) fail(path, in->geterror());
  in->close();

  // 1-2 channels: grey (+alpha) -> replicate grey; 3+ channels: first three are RGB, rest dropped.
  const bool grey = channels < 3;
  const bool linearise = storesSrgb(spec);
  Image img(spec.width, spec.height);
  for (size_t pixel = 0; pixel < size_t(spec.width) * size_t(spec.height); ++pixel) {
    const float* source = &file[pixel * size_t(channels)];
    for (int c = 0; c < 3; ++c) {
      const float value = source[grey ? 0 : c];
      img.rgb[pixel * 3 + size_t(c)] = linearise ? srgbDecode(value) : value;
    }
  }
  return img;
}

float autoExposure(const Image& img) {
  std::vector<float> luminances;
  luminances.reserve(img.rgb.size() / 3);
  for (size_t pixel = 0; pixel + 2 < img.rgb.size(); pixel += 3) {
    const float lum = luminance(&img.rgb[pixel]);
    if (std::isfinite(lum)) luminances.push_back(lum);
  }
  if (luminances.empty()) return 1.0f;
  const size_t rank = size_t(0.99 * double(luminances.size() - 1));
  std::nth_element(luminances.begin(), luminances.begin() + long(rank), luminances.end());
  const float percentile99 = luminances[rank];
  if (!(percentile99 > 1e-20f)) return 1.0f;  // black (or negative) image
  return 0.8f / percentile99;
}

}  // namespace vs
