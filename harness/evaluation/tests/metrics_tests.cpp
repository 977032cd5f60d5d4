// Tests for harness/metrics, harness/image and harness/image_cache.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <stdexcept>

#include "harness/io/image.hpp"
#include "harness/evaluation/image_cache.hpp"
#include "harness/evaluation/metrics.hpp"

namespace fs = std::filesystem;
using vs::Image;

namespace {

Image constantImage(int width, int height, float r, float g, float b) {
  Image img(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      float* c = img.at(x, y);
      c[0] = r;
      c[1] = g;
      c[2] = b;
    }
  return img;
}

// Smooth gradients plus a checker-like pattern: structure for SSIM to notice.
Image texturedImage(int width, int height) {
  Image img(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float pattern = 0.5f + 0.4f * std::sin(0.9f * float(x)) * std::cos(0.7f * float(y));
      float* c = img.at(x, y);
      c[0] = pattern;
      c[1] = 0.3f + 0.6f * float(x) / float(width);
      c[2] = 0.2f + 0.6f * float(y) / float(height);
    }
  return img;
}

Image addNoise(const Image& img, float amplitude, unsigned seed) {
  std::mt19937 generator(seed);
  std::normal_distribution<float> noise(0.0f, amplitude);
  Image noisy = img;
  for (float& v : noisy.rgb) v += noise(generator);
  return noisy;
}

Image boxBlur3(const Image& img) {
  Image blurred(img.width, img.height);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      for (int c = 0; c < 3; ++c) {
        float sum = 0;
        int count = 0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int sx = x + dx, sy = y + dy;
            if (sx < 0 || sy < 0 || sx >= img.width || sy >= img.height) continue;
            sum += img.at(sx, sy)[c];
            ++count;
          }
        blurred.at(x, y)[c] = sum / float(count);
      }
  return blurred;
}

// A fresh empty directory per test, removed afterwards.
class TempDirTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = (fs::temp_directory_path() / "vs_metrics_test_XXXXXX").string();
    ASSERT_NE(mkdtemp(pattern.data()), nullptr);
    dir = pattern;
  }
  void TearDown() override { fs::remove_all(dir); }
  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename().string());
    return names;
  }
  fs::path dir;
};

}  // namespace

TEST(Metrics, IdenticalImagesArePerfect) {
  const Image img = texturedImage(40, 30);
  const vs::ErrorMetrics m = vs::compareImages(img, img);
  EXPECT_EQ(m.rmse, 0.0);
  EXPECT_EQ(m.relmse, 0.0);
  EXPECT_EQ(m.maxAbs, 0.0);
  EXPECT_EQ(m.psnr, 200.0);
  EXPECT_DOUBLE_EQ(m.ssim, 1.0);
  EXPECT_EQ(m.nonFinite, 0u);
}

TEST(Metrics, ConstantOffsetGivesExactRmseAndPsnr) {
  const Image reference = constantImage(16, 12, 0.25f, 0.5f, 0.125f);
  const Image test = constantImage(16, 12, 0.5f, 0.75f, 0.375f);  // +0.25 on every channel
  const vs::ErrorMetrics m = vs::compareImages(test, reference);
  EXPECT_DOUBLE_EQ(m.rmse, 0.25);
  EXPECT_DOUBLE_EQ(m.maxAbs, 0.25);
  EXPECT_NEAR(m.psnr, 20.0 * std::log10(4.0), 1e-12);  // 10 log10(1 / 0.0625)
}

TEST(Metrics, PsnrIsCappedForTinyErrors) {
  const Image reference = constantImage(8, 8, 0.5f, 0.5f, 0.5f);
  Image test = reference;
  test.at(3, 3)[0] = std::nextafter(0.5f, 1.0f);
  const vs::ErrorMetrics m = vs::compareImages(test, reference);
  EXPECT_GT(m.rmse, 0.0);
  EXPECT_LE(m.psnr, 200.0);
}

TEST(Metrics, RelMseUsesEpsilonPerChannel) {
  const Image reference = constantImage(4, 4, 0.0f, 0.5f, 1.0f);
  const Image test = constantImage(4, 4, 0.1f, 0.5f, 0.5f);
  const double d0 = double(0.1f), d2 = 0.5;
  const double expected = (d0 * d0 / (0.0 + vs::kRelMseEpsilon) + 0.0 + d2 * d2 / (1.0 + vs::kRelMseEpsilon)) / 3.0;
  EXPECT_NEAR(vs::compareImages(test, reference).relmse, expected, 1e-12);
}

TEST(Metrics, MaxAbsReportsLocation) {
  const Image reference = constantImage(20, 10, 0.2f, 0.2f, 0.2f);
  Image test = reference;
  test.at(7, 3)[1] = 0.5f;    // |diff| 0.3
  test.at(12, 8)[2] = -0.7f;  // |diff| 0.9, the largest
  const vs::ErrorMetrics m = vs::compareImages(test, reference);
  EXPECT_NEAR(m.maxAbs, 0.9, 1e-6);
  EXPECT_EQ(m.maxX, 12);
  EXPECT_EQ(m.maxY, 8);
}

TEST(Metrics, SsimDropsForNoiseAndBlurAndStaysInRange) {
  const Image reference = texturedImage(64, 48);
  const double noisy = vs::ssimLuminance(addNoise(reference, 0.1f, 7), reference);
  const double blurred = vs::ssimLuminance(boxBlur3(reference), reference);
  EXPECT_LT(noisy, 0.9);
  EXPECT_LT(blurred, 0.99);
  for (double s : {noisy, blurred}) {
    EXPECT_GE(s, -1.0);
    EXPECT_LE(s, 1.0);
  }
  // Anti-correlated structure goes negative but not below -1.
  Image inverted = reference;
  for (float& v : inverted.rgb) v = 1.0f - v;
  const double anti = vs::ssimLuminance(inverted, reference);
  EXPECT_LT(anti, 0.0);
  EXPECT_GE(anti, -1.0);
}

TEST(Metrics, SsimOnImagesSmallerThanWindow) {
  const Image small = texturedImage(6, 5);  // falls back to a 5x5 window
  EXPECT_DOUBLE_EQ(vs::ssimLuminance(small, small), 1.0);
  EXPECT_LT(vs::ssimLuminance(addNoise(small, 0.2f, 3), small), 1.0);
  const Image pixel = constantImage(1, 1, 0.5f, 0.5f, 0.5f);
  EXPECT_DOUBLE_EQ(vs::ssimLuminance(pixel, pixel), 1.0);
  EXPECT_DOUBLE_EQ(vs::compareImages(Image(), Image()).ssim, 1.0);
}

TEST(Metrics, NonFinitePixelsAreCountedAndNeverLookGood) {
  const Image reference = texturedImage(32, 32);
  Image test = reference;
  test.at(5, 9)[0] = std::numeric_limits<float>::quiet_NaN();
  test.at(20, 21)[2] = std::numeric_limits<float>::infinity();
  const vs::ErrorMetrics m = vs::compareImages(test, reference);
  EXPECT_EQ(m.nonFinite, 2u);
  EXPECT_TRUE(std::isinf(m.rmse) && m.rmse > 0);
  EXPECT_TRUE(std::isinf(m.maxAbs) && m.maxAbs > 0);
  EXPECT_TRUE(std::isinf(m.relmse) && m.relmse > 0);
  EXPECT_TRUE(std::isinf(m.psnr) && m.psnr < 0);
  EXPECT_EQ(m.maxX, 5);
  EXPECT_EQ(m.maxY, 9);
  EXPECT_FALSE(std::isnan(m.ssim));
  EXPECT_LT(m.ssim, 1.0);
  EXPECT_GE(m.ssim, -1.0);
}

TEST(Metrics, SizeMismatchThrows) {
  const Image a(8, 8), b(8, 9);
  EXPECT_THROW(vs::compareImages(a, b), std::invalid_argument);
  EXPECT_THROW(vs::ssimLuminance(a, b), std::invalid_argument);
  EXPECT_THROW(vs::falseColourError(a, b, 1.0f), std::invalid_argument);
}

TEST(Metrics, TemporalErrorSeesFlickerAndLagButNotABias) {
  // The reference brightens by 0.1 a frame.
  std::vector<Image> reference = {constantImage(8, 6, 0.5f, 0.5f, 0.5f), constantImage(8, 6, 0.6f, 0.6f, 0.6f),
                                  constantImage(8, 6, 0.7f, 0.7f, 0.7f)};
  auto pointers = [](const std::vector<Image>& images) {
    std::vector<const Image*> out;
    for (const Image& i : images) out.push_back(&i);
    return out;
  };
  // A constant bias follows every change: a per-frame error, no temporal one.
  std::vector<Image> biased = {constantImage(8, 6, 0.55f, 0.55f, 0.55f), constantImage(8, 6, 0.65f, 0.65f, 0.65f),
                               constantImage(8, 6, 0.75f, 0.75f, 0.75f)};
  vs::TemporalError none = vs::temporalError(pointers(biased), pointers(reference));
  EXPECT_NEAR(none.rmse, 0.0, 1e-6);
  EXPECT_EQ(none.pairs, 2);
  // Lag: a sequence that stays at the first frame misses each change of 0.1.
  std::vector<Image> lagging(3, constantImage(8, 6, 0.5f, 0.5f, 0.5f));
  vs::TemporalError lag = vs::temporalError(pointers(lagging), pointers(reference));
  EXPECT_NEAR(lag.rmse, 0.1, 1e-6);
  // relative: over the RMS of the reference's frames 1 and 2, sqrt((0.36 + 0.49) / 2).
  EXPECT_NEAR(lag.relative, 0.1 / std::sqrt((0.36 + 0.49) / 2.0), 1e-6);
  // Flicker: +-0.05 around the reference, alternating: changes of 0.1 the reference does not have.
  std::vector<Image> flicker = {constantImage(8, 6, 0.55f, 0.55f, 0.55f), constantImage(8, 6, 0.55f, 0.55f, 0.55f),
                                constantImage(8, 6, 0.75f, 0.75f, 0.75f)};
  EXPECT_NEAR(vs::temporalError(pointers(flicker), pointers(reference)).rmse, 0.1, 1e-6);
  // One frame has no pair; sizes must agree; non-finite frames never look good.
  EXPECT_EQ(vs::temporalError({&reference[0]}, {&reference[0]}).pairs, 0);
  Image small = constantImage(4, 3, 0.5f, 0.5f, 0.5f);
  EXPECT_THROW(vs::temporalError({&reference[0], &small}, {&reference[0], &reference[1]}), std::invalid_argument);
  Image broken = constantImage(8, 6, 0.5f, 0.5f, 0.5f);
  broken.at(2, 2)[0] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_TRUE(std::isinf(vs::temporalError({&reference[0], &broken}, {&reference[0], &reference[1]}).rmse));
}

TEST(Metrics, FalseColourRampEndsAndNonFinite) {
  const Image reference = constantImage(3, 1, 0.0f, 0.0f, 0.0f);
  Image test = reference;
  test.at(1, 0)[0] = test.at(1, 0)[1] = test.at(1, 0)[2] = 5.0f;  // beyond full scale
  test.at(2, 0)[1] = std::numeric_limits<float>::quiet_NaN();
  const std::vector<uint8_t> colours = vs::falseColourError(test, reference, 1.0f);
  ASSERT_EQ(colours.size(), 9u);
  EXPECT_LT(colours[0] + colours[1] + colours[2], 15);  // zero error: near black
  EXPECT_GT(colours[3], 240);                           // full scale: pale yellow
  EXPECT_GT(colours[4], 240);
  EXPECT_LT(colours[5], 200);
  EXPECT_EQ(colours[6], 255);  // NaN: white
  EXPECT_EQ(colours[7], 255);
  EXPECT_EQ(colours[8], 255);
}

TEST(Image, AutoExposure) {
  EXPECT_EQ(vs::autoExposure(constantImage(10, 10, 0, 0, 0)), 1.0f);
  EXPECT_NEAR(vs::autoExposure(constantImage(10, 10, 0.4f, 0.4f, 0.4f)), 2.0f, 1e-5f);
}

TEST_F(TempDirTest, ExrRoundTripIsExact) {
  Image img(17, 9);
  std::mt19937 generator(42);
  std::uniform_real_distribution<float> values(-1000.0f, 1000.0f);
  for (float& v : img.rgb) v = values(generator);
  img.rgb[0] = 1e-30f;
  img.rgb[1] = 3.0e38f;
  const std::string path = (dir / "round.exr").string();
  vs::writeExr(path, img);
  const Image back = vs::readImage(path);
  ASSERT_EQ(back.width, img.width);
  ASSERT_EQ(back.height, img.height);
  ASSERT_EQ(back.rgb.size(), img.rgb.size());
  EXPECT_EQ(std::memcmp(back.rgb.data(), img.rgb.data(), img.rgb.size() * sizeof(float)), 0);
}

TEST_F(TempDirTest, ReadImageReplicatesGreyAndDropsAlpha) {
  const auto writeRaw = [&](const std::string& name, int channels, const std::vector<float>& data) {
    const std::string path = (dir / name).string();
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open(path, OIIO::ImageSpec(2, 1, channels, OIIO::TypeDesc::FLOAT)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, data.data()));
    ASSERT_TRUE(out->close());
  };
  writeRaw("grey.exr", 1, {0.25f, 2.0f});
  writeRaw("rgba.exr", 4, {0.1f, 0.2f, 0.3f, 0.5f, 1.0f, 2.0f, 3.0f, 1.0f});
  const Image grey = vs::readImage((dir / "grey.exr").string());
  EXPECT_EQ(grey.rgb, (std::vector<float>{0.25f, 0.25f, 0.25f, 2.0f, 2.0f, 2.0f}));
  const Image rgba = vs::readImage((dir / "rgba.exr").string());
  EXPECT_EQ(rgba.rgb, (std::vector<float>{0.1f, 0.2f, 0.3f, 1.0f, 2.0f, 3.0f}));
}

TEST_F(TempDirTest, PngIsWrittenAndReadsBackLinear) {
  Image img = constantImage(4, 2, 0.5f, 0.0f, 0.18f);
  img.at(1, 1)[0] = std::numeric_limits<float>::quiet_NaN();
  const std::string path = (dir / "tonemapped.png").string();
  vs::writePngTonemapped(path, img, 1.0f);
  ASSERT_TRUE(fs::exists(path));
  EXPECT_GT(fs::file_size(path), 0u);
  const Image back = vs::readImage(path);  // 8-bit sRGB -> linear
  ASSERT_EQ(back.width, 4);
  EXPECT_NEAR(back.at(0, 0)[0], 0.5f, 0.005f);
  EXPECT_NEAR(back.at(0, 0)[1], 0.0f, 1e-6f);
  EXPECT_NEAR(back.at(0, 0)[2], 0.18f, 0.003f);
  EXPECT_FLOAT_EQ(back.at(1, 1)[0], 1.0f);  // magenta for NaN
  EXPECT_FLOAT_EQ(back.at(1, 1)[1], 0.0f);
  EXPECT_FLOAT_EQ(back.at(1, 1)[2], 1.0f);
}

TEST_F(TempDirTest, AtomicWriteLeavesOnlyTheTarget) {
  const Image img = texturedImage(8, 8);
  vs::writeExr((dir / "a.exr").string(), img);
  vs::writeExr((dir / "a.exr").string(), img);  // overwrite in place
  vs::writePng8((dir / "b.png").string(), 1, 1, {1, 2, 3});
  auto names = entries();
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"a.exr", "b.png"}));
}

TEST_F(TempDirTest, FailedWritesThrowAndLeaveNothing) {
  const Image img = texturedImage(8, 8);
  const fs::path missingDir = dir / "does_not_exist";
  EXPECT_THROW(vs::writeExr((missingDir / "x.exr").string(), img), std::runtime_error);
  EXPECT_THROW(vs::writePngTonemapped((missingDir / "x.png").string(), img, 1.0f), std::runtime_error);
  EXPECT_FALSE(fs::exists(missingDir));

  // The rename fails (target is a directory): the written temp file must be removed again.
  fs::create_directory(dir / "occupied.exr");
  EXPECT_THROW(vs::writeExr((dir / "occupied.exr").string(), img), std::runtime_error);
  // Unknown format and wrong buffer size.
  EXPECT_THROW(vs::writeExr((dir / "noextension").string(), img), std::runtime_error);
  EXPECT_THROW(vs::writePng8((dir / "short.png").string(), 2, 2, {1, 2, 3}), std::runtime_error);
  EXPECT_EQ(entries(), (std::vector<std::string>{"occupied.exr"}));

  try {
    vs::writeExr((missingDir / "x.exr").string(), img);
  } catch (const std::runtime_error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("x.exr"), std::string::npos);
    EXPECT_EQ(message.find('\n'), std::string::npos);
  }
}

TEST_F(TempDirTest, ReadingAMissingFileThrows) {
  EXPECT_THROW(vs::readImage((dir / "missing.exr").string()), std::runtime_error);
}

// The image cache reads back what it wrote, and only for the same key and size: another key (a hash
// collision), another size, a missing or broken JSON are misses, never someone else's images.
TEST_F(TempDirTest, ImageCacheHitsOnlyItsOwnKeyAndSize) {
  const Image ls = texturedImage(8, 6), final = constantImage(8, 6, 0.5f, 0.25f, 1.0f);
  const std::string base = (dir / "cache" / "scene-0123").string();
  vs::writeCachedImages(base, "key one", ls, final, {{"compute_ms", 12.5}});
  auto hit = vs::readCachedImages(base, "key one", 8, 6);
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(vs::compareImages(hit->inscatter, ls).maxAbs, 0.0);
  EXPECT_EQ(vs::compareImages(hit->final, final).maxAbs, 0.0);
  EXPECT_EQ(hit->meta.value("compute_ms", 0.0), 12.5);
  EXPECT_FALSE(vs::readCachedImages(base, "key two", 8, 6).has_value());
  EXPECT_FALSE(vs::readCachedImages(base, "key one", 8, 5).has_value());
  std::ofstream(base + ".json") << "{ not json";
  EXPECT_FALSE(vs::readCachedImages(base, "key one", 8, 6).has_value());
  fs::remove(base + ".json");
  EXPECT_FALSE(vs::readCachedImages(base, "key one", 8, 6).has_value());
}
