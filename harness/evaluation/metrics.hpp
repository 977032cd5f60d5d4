// Image error metrics against a reference, on linear float RGB images of equal size.
#pragma once
#include <cstdint>
#include <string>
#include <vector>
#include "harness/io/image.hpp"

namespace vs {

constexpr double kRelMseEpsilon = 1e-2;  // relMSE = mean((x - r)^2 / (r^2 + eps)), per channel
constexpr double kPsnrPeak = 1.0;        // PSNR = 10 log10(peak^2 / MSE), fixed peak, linear units
// SSIM: Wang et al. 2004 on Rec.709 luminance, 11x11 Gaussian window sigma 1.5, K1 0.01, K2 0.03,
// dynamic range L = kPsnrPeak; the image border where the window does not fit is skipped.

struct ErrorMetrics {
  double rmse = 0, relmse = 0, psnr = 0, ssim = 1, maxAbs = 0;
  int maxX = 0, maxY = 0;   // where maxAbs was found (row 0 = top)
  size_t nonFinite = 0;     // NaN/Inf pixels in the test image (or the reference): see below
};
// Non-finite pixels: when nonFinite > 0, rmse, relmse and maxAbs are +inf and psnr is -inf (never
// NaN), and (maxX, maxY) is the first such pixel in row order. In ssimLuminance every window that
// touches a non-finite pixel scores -1, the SSIM minimum, so ssim stays finite in [-1, 1].
// SSIM on images smaller than 11x11 uses the largest odd window that fits (at least 1x1).

// Throws std::invalid_argument when sizes differ. PSNR is capped at 200 dB for identical images.
ErrorMetrics compareImages(const Image& test, const Image& reference);
double ssimLuminance(const Image& a, const Image& b);

// Temporal error of a sequence (frames in order, each with the reference of the same frame): the
// change between consecutive frames that the reference does not have (flicker, lag, ghosting),
// RMS over pixels, channels and consecutive pairs of ((L_t - L_{t-1}) - (R_t - R_{t-1})). `relative`
// divides it by the RMS of the reference over the same frames. A constant bias, which a per-frame
// error sees, gives 0. Fewer than two frames: 0. Throws like compareImages; non-finite: +inf.
struct TemporalError {
  double rmse = 0, relative = 0;
  int pairs = 0;
};
TemporalError temporalError(const std::vector<const Image*>& frames, const std::vector<const Image*>& references);

// False-colour map of per-pixel absolute luminance error (inferno-like ramp), scaled so that
// `fullScale` maps to the top of the ramp (clamped; fullScale <= 0 puts any error there).
// Non-finite errors are white. Returns 8-bit RGB, width*height*3. Throws like compareImages.
std::vector<uint8_t> falseColourError(const Image& test, const Image& reference, float fullScale);

}  // namespace vs
