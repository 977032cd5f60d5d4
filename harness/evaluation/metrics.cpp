// Error metrics of a test image against a reference (see metrics.hpp for the definitions).
#include "harness/evaluation/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace vs {
namespace {

constexpr double kPsnrCap = 200.0;
constexpr int kSsimWindow = 11;
constexpr double kSsimSigma = 1.5;
constexpr double kSsimK1 = 0.01, kSsimK2 = 0.03;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

void requireSameSize(const Image& test, const Image& reference) {
  if (test.width != reference.width || test.height != reference.height)
    throw std::invalid_argument("image sizes differ: " + std::to_string(test.width) + "x" +
                                std::to_string(test.height) + " vs " +
                                std::to_string(reference.width) + "x" +
                                std::to_string(reference.height));
  if (test.rgb.size() != reference.rgb.size() ||
      test.rgb.size() != size_t(test.width) * size_t(test.height) * 3)
    throw std::invalid_argument("image pixel buffer does not match its width*height*3");
}

bool isFinitePixel(const float* c) {
  return std::isfinite(c[0]) && std::isfinite(c[1]) && std::isfinite(c[2]);
}

// Normalised 1-D Gaussian of odd length `size`.
std::vector<double> gaussianKernel(int size, double sigma) {
  std::vector<double> weights(static_cast<size_t>(size));
  const int centre = size / 2;
  double total = 0;
  for (int i = 0; i < size; ++i) {
    const double offset = i - centre;
    weights[size_t(i)] = std::exp(-offset * offset / (2 * sigma * sigma));
    total += weights[size_t(i)];
  }
  for (double& w : weights) w /= total;
  return weights;
}

// Separable filtering with the window kept fully inside the image ("valid" mode):
// the result is (width-k+1) x (height-k+1), entry (x,y) for the window whose top-left is (x,y).
std::vector<double> filterValid(const std::vector<double>& values, int width, int height,
                                const std::vector<double>& kernel) {
  const int k = int(kernel.size());
  const int outWidth = width - k + 1, outHeight = height - k + 1;
  std::vector<double> rows(size_t(outWidth) * size_t(height));
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < outWidth; ++x) {
      const double* source = &values[size_t(y) * size_t(width) + size_t(x)];
      double sum = 0;
      for (int i = 0; i < k; ++i) sum += kernel[size_t(i)] * source[i];
      rows[size_t(y) * size_t(outWidth) + size_t(x)] = sum;
    }
  std::vector<double> result(size_t(outWidth) * size_t(outHeight));
  for (int y = 0; y < outHeight; ++y)
    for (int x = 0; x < outWidth; ++x) {
      double sum = 0;
      for (int i = 0; i < k; ++i) sum += kernel[size_t(i)] * rows[size_t(y + i) * size_t(outWidth) + size_t(x)];
      result[size_t(y) * size_t(outWidth) + size_t(x)] = sum;
    }
  return result;
}

// Summed-area table of flags, (width+1) x (height+1), for counting flagged pixels in any window.
std::vector<size_t> summedAreaTable(const std::vector<char>& flags, int width, int height) {
  const size_t stride = size_t(width) + 1;
  std::vector<size_t> table(stride * (size_t(height) + 1), 0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      table[size_t(y + 1) * stride + size_t(x + 1)] = size_t(flags[size_t(y) * size_t(width) + size_t(x)]) +
                                                      table[size_t(y) * stride + size_t(x + 1)] +
                                                      table[size_t(y + 1) * stride + size_t(x)] -
                                                      table[size_t(y) * stride + size_t(x)];
  return table;
}

struct RampStop {
  float r, g, b;
};
// Inferno-like ramp: black -> purple -> red -> orange -> pale yellow, evenly spaced stops.
constexpr RampStop kErrorRamp[] = {
    {0.001f, 0.000f, 0.014f}, {0.156f, 0.045f, 0.325f}, {0.398f, 0.083f, 0.433f},
    {0.622f, 0.164f, 0.389f}, {0.832f, 0.284f, 0.257f}, {0.961f, 0.489f, 0.084f},
    {0.981f, 0.759f, 0.157f}, {0.988f, 0.998f, 0.645f}};
constexpr int kRampStops = int(sizeof(kErrorRamp) / sizeof(kErrorRamp[0]));

uint8_t toByte(float unit) { return uint8_t(std::lround(std::clamp(unit, 0.0f, 1.0f) * 255.0f)); }

}  // namespace

double ssimLuminance(const Image& a, const Image& b) {
  requireSameSize(a, b);
  const int width = a.width, height = a.height;
  if (width <= 0 || height <= 0) return 1.0;

  // Largest odd window up to 11 that fits the image.
  int window = std::min(width, height);
  if (window % 2 == 0) --window;
  window = std::min(window, kSsimWindow);
  const std::vector<double> kernel = gaussianKernel(window, kSsimSigma);

  // Luminance planes and their products; non-finite pixels enter as 0 and are flagged so
  // that they cannot spread NaN through the filter.
  const size_t pixels = size_t(width) * size_t(height);
  std::vector<double> x(pixels), y(pixels), xx(pixels), yy(pixels), xy(pixels);
  std::vector<char> nonFinite(pixels, 0);
  for (size_t i = 0; i < pixels; ++i) {
    double la = luminance(&a.rgb[i * 3]), lb = luminance(&b.rgb[i * 3]);
    if (!std::isfinite(la) || !std::isfinite(lb)) {
      nonFinite[i] = 1;
      la = lb = 0;
    }
    x[i] = la;
    y[i] = lb;
    xx[i] = la * la;
    yy[i] = lb * lb;
    xy[i] = la * lb;
  }
  const std::vector<double> meanX = filterValid(x, width, height, kernel);
  const std::vector<double> meanY = filterValid(y, width, height, kernel);
  const std::vector<double> meanXX = filterValid(xx, width, height, kernel);
  const std::vector<double> meanYY = filterValid(yy, width, height, kernel);
  const std::vector<double> meanXY = filterValid(xy, width, height, kernel);
  const std::vector<size_t> badCount = summedAreaTable(nonFinite, width, height);

  const double c1 = (kSsimK1 * kPsnrPeak) * (kSsimK1 * kPsnrPeak);
  const double c2 = (kSsimK2 * kPsnrPeak) * (kSsimK2 * kPsnrPeak);
  const int outWidth = width - window + 1, outHeight = height - window + 1;
  const size_t stride = size_t(width) + 1;
  double sum = 0;
  for (int wy = 0; wy < outHeight; ++wy)
    for (int wx = 0; wx < outWidth; ++wx) {
      const size_t bad = badCount[size_t(wy + window) * stride + size_t(wx + window)] -
                         badCount[size_t(wy) * stride + size_t(wx + window)] -
                         badCount[size_t(wy + window) * stride + size_t(wx)] +
                         badCount[size_t(wy) * stride + size_t(wx)];
      if (bad > 0) {  // a window touching NaN/Inf scores the SSIM minimum
        sum += -1.0;
        continue;
      }
      const size_t i = size_t(wy) * size_t(outWidth) + size_t(wx);
      const double mx = meanX[i], my = meanY[i];
      const double varX = meanXX[i] - mx * mx, varY = meanYY[i] - my * my;
      const double covariance = meanXY[i] - mx * my;
      const double numerator = (2 * mx * my + c1) * (2 * covariance + c2);
      const double denominator = (mx * mx + my * my + c1) * (varX + varY + c2);
      // c1, c2 > 0 keep the denominator positive; clamp away rounding outside [-1,1].
      sum += std::clamp(numerator / denominator, -1.0, 1.0);
    }
  return sum / (double(outWidth) * double(outHeight));
}

ErrorMetrics compareImages(const Image& test, const Image& reference) {
  requireSameSize(test, reference);
  ErrorMetrics metrics;
  metrics.psnr = kPsnrCap;
  const size_t pixels = size_t(test.width) * size_t(test.height);
  if (pixels == 0) return metrics;

  double sumSquared = 0, sumRelative = 0;
  for (int y = 0; y < test.height; ++y)
    for (int x = 0; x < test.width; ++x) {
      const float* t = test.at(x, y);
      const float* r = reference.at(x, y);
      if (!isFinitePixel(t) || !isFinitePixel(r)) {
        if (metrics.nonFinite++ == 0) {  // report the first bad pixel as the max-error location
          metrics.maxX = x;
          metrics.maxY = y;
        }
        continue;
      }
      for (int c = 0; c < 3; ++c) {
        const double diff = double(t[c]) - double(r[c]);
        const double squared = diff * diff;
        sumSquared += squared;
        sumRelative += squared / (double(r[c]) * double(r[c]) + kRelMseEpsilon);
        if (metrics.nonFinite == 0 && std::abs(diff) > metrics.maxAbs) {
          metrics.maxAbs = std::abs(diff);
          metrics.maxX = x;
          metrics.maxY = y;
        }
      }
    }

  metrics.ssim = ssimLuminance(test, reference);
  if (metrics.nonFinite > 0) {  // an image with NaN/Inf is as wrong as it gets
    metrics.rmse = metrics.relmse = metrics.maxAbs = kInfinity;
    metrics.psnr = -kInfinity;
    return metrics;
  }
  const double samples = double(pixels) * 3.0;
  const double mse = sumSquared / samples;
  metrics.rmse = std::sqrt(mse);
  metrics.relmse = sumRelative / samples;
  if (mse > 0) metrics.psnr = std::min(kPsnrCap, 10.0 * std::log10(kPsnrPeak * kPsnrPeak / mse));
  return metrics;
}

TemporalError temporalError(const std::vector<const Image*>& frames, const std::vector<const Image*>& references) {
  if (frames.size() != references.size()) throw std::invalid_argument("temporalError: one reference per frame");
  TemporalError out;
  for (size_t k = 0; k < frames.size(); ++k)
    if (frames[k]->width != references[k]->width || frames[k]->height != references[k]->height ||
        frames[k]->width != frames[0]->width || frames[k]->height != frames[0]->height)
      throw std::invalid_argument("temporalError: image sizes differ");
  if (frames.size() < 2) return out;
  double sum = 0.0, reference = 0.0;
  size_t count = 0;
  for (size_t k = 1; k < frames.size(); ++k) {
    const auto &l1 = frames[k]->rgb, &l0 = frames[k - 1]->rgb, &r1 = references[k]->rgb, &r0 = references[k - 1]->rgb;
    for (size_t i = 0; i < l1.size(); ++i) {
      double d = (double(l1[i]) - double(l0[i])) - (double(r1[i]) - double(r0[i]));
      sum += d * d;
      reference += double(r1[i]) * double(r1[i]);
    }
    count += l1.size();
  }
  out.pairs = int(frames.size() - 1);
  if (count == 0) return out;
  out.rmse = std::isfinite(sum) ? std::sqrt(sum / double(count)) : std::numeric_limits<double>::infinity();
  const double referenceRms = std::sqrt(reference / double(count));
  out.relative = referenceRms > 0.0 ? out.rmse / referenceRms : (out.rmse > 0.0 ? std::numeric_limits<double>::infinity() : 0.0);
  return out;
}

std::vector<uint8_t> falseColourError(const Image& test, const Image& reference, float fullScale) {
  requireSameSize(test, reference);
  const size_t pixels = size_t(test.width) * size_t(test.height);
  std::vector<uint8_t> rgb8(pixels * 3);
  for (size_t i = 0; i < pixels; ++i) {
    const float error = std::abs(luminance(&test.rgb[i * 3]) - luminance(&reference.rgb[i * 3]));
    uint8_t* out = &rgb8[i * 3];
    if (!std::isfinite(error)) {  // NaN/Inf -> white, outside the ramp
      out[0] = out[1] = out[2] = 255;
      continue;
    }
    // A non-positive scale shows every non-zero error at the top of the ramp.
    float position = fullScale > 0 ? error / fullScale : (error > 0 ? 1.0f : 0.0f);
    position = std::clamp(position, 0.0f, 1.0f) * float(kRampStops - 1);
    const int lower = std::min(int(position), kRampStops - 2);
    const float blend = position - float(lower);
    const RampStop& from = kErrorRamp[lower];
    const RampStop& to = kErrorRamp[lower + 1];
    out[0] = toByte(from.r + (to.r - from.r) * blend);
    out[1] = toByte(from.g + (to.g - from.g) * blend);
    out[2] = toByte(from.b + (to.b - from.b) * blend);
  }
  return rgb8;
}

}  // namespace vs
