#include "scenes/volume.hpp"

#include "scenes/procedural.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <deque>
#include <mutex>
#include <glm/glm.hpp>
#include <vector>

namespace vs {

namespace {

// Fractal value noise for the cloud: per octave, hashed lattice values in [0, 1) blended with
// quintic weights. Samples lie on a grid, so the lattice hashes, cells and weights are computed
// once per octave and axis.
class CloudNoise {
 public:
  // One octave at `frequency` over a grid of voxel-centre coordinates in (-1, 1) per axis;
  // y is stretched by 1/4 (a flat layer).
  CloudNoise(const Volume& v, double frequency, uint32_t seed) {
    const double axisScale[3] = {frequency, frequency * 0.25, frequency};
    for (int a = 0; a < 3; ++a) {
      int n = v.dims[a];
      cell_[a].resize(size_t(n));
      weight_[a].resize(size_t(n));
      double lo = 1e30;
      for (int i = 0; i < n; ++i) {
        float p = (i + 0.5f) / n * 2.0f - 1.0f;
        double x = p * axisScale[a], f = std::floor(x), t = x - f;
        weight_[a][size_t(i)] = t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
        cell_[a][size_t(i)] = f;
        lo = std::min(lo, f);
      }
      lo_[a] = int64_t(lo);
      size_[a] = int(int64_t(cell_[a].back()) - lo_[a]) + 2;
    }
    values_.resize(size_t(size_[0]) * size_[1] * size_[2]);
    for (int k = 0; k < size_[2]; ++k)
      for (int j = 0; j < size_[1]; ++j)
        for (int i = 0; i < size_[0]; ++i) {
          int64_t ix = lo_[0] + i, iy = lo_[1] + j, iz = lo_[2] + k;
          uint64_t key = mix64(uint64_t(ix) * 0x9e3779b97f4a7c15ull ^ mix64(uint64_t(iy) + 0x632be5ab) ^
                               mix64(uint64_t(iz) * 0xd6e8feb86659fd93ull) ^ (uint64_t(seed) << 17));
          values_[(size_t(k) * size_[1] + j) * size_[0] + i] = double(key >> 11) * (1.0 / 9007199254740992.0);
        }
  }
  // The noise at voxel (i, j, k).
  double operator()(int i, int j, int k) const {
    size_t ci = size_t(int64_t(cell_[0][size_t(i)]) - lo_[0]), cj = size_t(int64_t(cell_[1][size_t(j)]) - lo_[1]),
           ck = size_t(int64_t(cell_[2][size_t(k)]) - lo_[2]);
    double tx = weight_[0][size_t(i)], ty = weight_[1][size_t(j)], tz = weight_[2][size_t(k)];
    auto at = [&](size_t di, size_t dj, size_t dk) { return values_[((ck + dk) * size_[1] + cj + dj) * size_[0] + ci + di]; };
    auto lerp = [](double a, double b, double t) { return a + (b - a) * t; };
    double x00 = lerp(at(0, 0, 0), at(1, 0, 0), tx), x10 = lerp(at(0, 1, 0), at(1, 1, 0), tx);
    double x01 = lerp(at(0, 0, 1), at(1, 0, 1), tx), x11 = lerp(at(0, 1, 1), at(1, 1, 1), tx);
    return lerp(lerp(x00, x10, ty), lerp(x01, x11, ty), tz);
  }

 private:
  std::vector<double> cell_[3], weight_[3];  // per axis and voxel index: floor of the coordinate, weight
  int64_t lo_[3];
  int size_[3];
  std::vector<double> values_;  // lattice values over the cells' range plus one
};

void allocate(Volume& v, int nx, int ny, int nz) {
  v.dims[0] = std::max(nx, 1);
  v.dims[1] = std::max(ny, 1);
  v.dims[2] = std::max(nz, 1);
  v.density.assign(v.voxelCount(), 0.0f);
}

// Calls f(i, j, k, p) for every voxel with p its centre in [-1, 1]^3.
template <typename F>
void forEachVoxel(Volume& v, F f) {
  for (int k = 0; k < v.dims[2]; ++k)
    for (int j = 0; j < v.dims[1]; ++j)
      for (int i = 0; i < v.dims[0]; ++i) {
        glm::vec3 p((i + 0.5f) / v.dims[0] * 2.0f - 1.0f, (j + 0.5f) / v.dims[1] * 2.0f - 1.0f,
                    (k + 0.5f) / v.dims[2] * 2.0f - 1.0f);
        v.density[(size_t(k) * v.dims[1] + j) * v.dims[0] + i] = f(p);
      }
}

int scaled(int n, float scale) { return std::max(1, int(std::lround(n * scale))); }

}  // namespace

const std::vector<std::string>& volumeGeneratorNames() {
  static const std::vector<std::string> names = {"density_box", "bucky", "rods", "cloud"};
  return names;
}

namespace {
void generateGrid(Volume& v, const std::string& generator, float scale, uint32_t seed) {
  if (generator == "density_box") {
    int n = scaled(64, scale);
    allocate(v, n, n, n);
    forEachVoxel(v, [](glm::vec3 p) {
      float m = std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
      return std::clamp(1.0f - m, 0.0f, 1.0f);
    });
  } else if (generator == "bucky") {
    int n = scaled(32, scale);
    allocate(v, n, n, n);
    // 60 atoms spread evenly over a shell of radius 0.7 (a Fibonacci sphere), each a ball of radius 0.16.
    std::vector<glm::vec3> atoms;
    const float golden = 2.39996322972865332f;
    for (int a = 0; a < 60; ++a) {
      float y = 1.0f - 2.0f * (a + 0.5f) / 60.0f, r = std::sqrt(std::max(0.0f, 1.0f - y * y));
      atoms.push_back(0.7f * glm::vec3(r * std::cos(golden * a), y, r * std::sin(golden * a)));
    }
    forEachVoxel(v, [&](glm::vec3 p) {
      float d = 1e9f;
      for (const glm::vec3& a : atoms) d = std::min(d, glm::length(p - a));
      return std::clamp((0.16f - d) / 0.06f + 0.5f, 0.0f, 1.0f);
    });
  } else if (generator == "rods") {
    int n = scaled(64, scale);
    allocate(v, n, n, n);
    // Rods of radius 0.12 along each axis at offsets (+-0.45, +-0.45) in the other two axes.
    forEachVoxel(v, [](glm::vec3 p) {
      float d = 1e9f;
      for (int axis = 0; axis < 3; ++axis) {
        float a = p[(axis + 1) % 3], b = p[(axis + 2) % 3];
        for (float oa : {-0.45f, 0.45f})
          for (float ob : {-0.45f, 0.45f}) d = std::min(d, std::hypot(a - oa, b - ob));
      }
      return std::clamp((0.12f - d) / 0.04f + 0.5f, 0.0f, 1.0f);
    });
  } else if (generator == "cloud") {
    allocate(v, scaled(512, scale), scaled(32, scale), scaled(512, scale));
    std::vector<CloudNoise> octaves;
    for (int octave = 0; octave < 4; ++octave) octaves.emplace_back(v, 4.0 * (1 << octave), seed + octave);
    for (int k = 0; k < v.dims[2]; ++k)
      for (int j = 0; j < v.dims[1]; ++j) {
        // A vertical profile that fades at the layer's bottom and top.
        float y = (j + 0.5f) / v.dims[1] * 2.0f - 1.0f;
        float profile = std::clamp(1.0f - std::fabs(y), 0.0f, 1.0f);
        for (int i = 0; i < v.dims[0]; ++i) {
          double sum = 0.0, amplitude = 0.5;
          for (const CloudNoise& noise : octaves) {
            sum += amplitude * noise(i, j, k);
            amplitude *= 0.5;
          }
          // Coverage threshold, then the profile.
          v.density[(size_t(k) * v.dims[1] + j) * v.dims[0] + i] = std::clamp(float((sum - 0.45) * 4.0) * profile, 0.0f, 1.0f);
        }
      }
  } else {
    allocate(v, 1, 1, 1);
  }
}
}  // namespace

// A grid depends on (generator, scale, seed) alone, and scenes that differ in box and coefficients
// share it (the stress draws 10,000 of them; the cloud's 8 M voxels take about 0.2 s to make): the
// last few grids made are kept and copied, those of at most kMostVoxelsKept voxels (a scaled-up
// grid of up to 1 GiB is not held twice for the life of the process).
void generateVolume(Volume& v, const std::string& generator, float scale, uint32_t seed) {
  struct Made {
    std::string generator;
    float scale;
    uint32_t seed;
    int dims[3];
    std::vector<float> density;
  };
  constexpr size_t kKept = 4, kMostVoxelsKept = size_t(1) << 24;
  static std::mutex mutex;
  static std::deque<Made> made;
  {
    std::lock_guard<std::mutex> lock(mutex);
    for (const Made& m : made)
      if (m.generator == generator && m.scale == scale && m.seed == seed) {
        std::copy(m.dims, m.dims + 3, v.dims);
        v.density = m.density;
        return;
      }
  }
  generateGrid(v, generator, scale, seed);
  if (v.voxelCount() > kMostVoxelsKept) return;
  std::lock_guard<std::mutex> lock(mutex);
  made.push_front(Made{generator, scale, seed, {v.dims[0], v.dims[1], v.dims[2]}, v.density});
  if (made.size() > kKept) made.pop_back();
}

Volume readVolume(ObjectReader entry, const std::string& baseDir, ContentHasher& hasher) {
  Volume v;
  entry.declare({"name", "raw", "type", "dims", "header_bytes", "generator", "scale", "seed", "density", "box_min",
                 "box_max", "density_scale", "sigma_s", "sigma_a"});
  v.name = entry.string("name", "");
  bool isRaw = entry.has("raw"), isGenerator = entry.has("generator"), isInline = entry.has("density");
  if (int(isRaw) + int(isGenerator) + int(isInline) > 1)
    entry.fail(isGenerator ? "generator" : "density", "a volume has one of 'raw', 'generator' or 'density'");
  if (!isRaw && !isGenerator && !isInline) {
    entry.failOnMisspellingOf("raw");
    entry.failOnMisspellingOf("generator");
    entry.failOnMisspellingOf("density");
    entry.fail("raw", "missing: a volume needs a 'raw' file, a 'generator' or inline 'density' values");
  }
  v.boxLo = entry.vec3("box_min", Range::any());
  v.boxHi = entry.vec3("box_max", Range::any());
  for (int k = 0; k < 3; ++k)
    if (!(v.boxHi[k] > v.boxLo[k])) entry.fail("box_max", "must be greater than box_min on every axis");
  v.densityScale = float(entry.number("density_scale", 1.0, Range::closed(0.0, 1e6)));
  v.sigmaS = entry.rgb("sigma_s", 1.0f, Range::closed(0.0, 1e6));
  v.sigmaA = entry.rgb("sigma_a", 0.0f, Range::closed(0.0, 1e6));
  if (isGenerator) {
    std::string generator = entry.choice("generator", volumeGeneratorNames(), "");
    float scale = float(entry.number("scale", 1.0, Range::openClosed(0.0, 4.0)));
    uint32_t seed = uint32_t(entry.integer("seed", 1, 0, 4294967295LL));
    for (const char* key : {"type", "dims", "header_bytes"}) entry.forbid(key, "only used by raw volumes");
    entry.finish();
    const int base[4][3] = {{64, 64, 64}, {32, 32, 32}, {64, 64, 64}, {512, 32, 512}};
    size_t index = size_t(std::find(volumeGeneratorNames().begin(), volumeGeneratorNames().end(), generator) -
                          volumeGeneratorNames().begin());
    double voxels = 1.0;
    for (int k = 0; k < 3; ++k) {
      int n = scaled(base[index][k], scale);
      if (n > kMaxVolumeDim) entry.fail("scale", "gives " + std::to_string(n) + " voxels along an axis (at most " +
                                                     std::to_string(kMaxVolumeDim) + ")");
      voxels *= n;
    }
    if (voxels > double(kMaxVolumeVoxels)) entry.fail("scale", "gives more than 2^28 voxels");
    generateVolume(v, generator, scale, seed);
    hasher.addBlock(std::string("volume-generators-v1"));
    if (v.name.empty()) v.name = generator;
    return v;
  }
  for (const char* key : {"scale", "seed"}) entry.forbid(key, "only used by generated volumes");
  if (isInline) {
    // Small grids written out in the scene: "dims" and x-fastest "density" values.
    for (const char* key : {"type", "header_bytes"}) entry.forbid(key, "only used by raw volumes");
    const Json& dims = entry.required("dims");
    JsonLocation dimsAt = entry.locationOf("dims");
    if (!dims.is_array() || dims.size() != 3) dimsAt.fail("expected [x, y, z]");
    for (int k = 0; k < 3; ++k) v.dims[k] = int(readInteger(dims[k], dimsAt.item(k), 1, 64));
    const Json& values = entry.required("density");
    JsonLocation valuesAt = entry.locationOf("density");
    if (!values.is_array() || values.size() != v.voxelCount())
      valuesAt.fail("expected an array of dims x * y * z = " + std::to_string(v.voxelCount()) + " densities");
    entry.finish();
    for (size_t i = 0; i < v.voxelCount(); ++i)
      v.density.push_back(float(readNumber(values[i], valuesAt.item(i), Range::closed(0.0, 1e6))));
    if (v.name.empty()) v.name = "inline";
    return v;
  }
  std::string file = entry.string("raw");
  if (file.empty()) entry.fail("raw", "must not be empty");
  std::string type = entry.choice("type", {"u8", "u16", "f32"}, "");
  entry.required("type");
  const Json& dims = entry.required("dims");
  JsonLocation dimsAt = entry.locationOf("dims");
  if (!dims.is_array() || dims.size() != 3) dimsAt.fail("expected [x, y, z]");
  for (int k = 0; k < 3; ++k) v.dims[k] = int(readInteger(dims[k], dimsAt.item(k), 1, kMaxVolumeDim));
  size_t headerBytes = size_t(entry.integer("header_bytes", 0, 0, int64_t(1) << 40));
  entry.finish();
  if (v.voxelCount() > kMaxVolumeVoxels) dimsAt.fail("more than 2^28 voxels");
  if (v.name.empty()) v.name = file;

  std::string path = file;
  if (!baseDir.empty() && path.front() != '/') path = baseDir + "/" + path;
  std::string bytes, error;
  JsonLocation rawAt = entry.locationOf("raw");
  if (!readFile(path, bytes, error)) rawAt.fail("cannot open volume file '" + path + "': " + error);
  hasher.addBlock(bytes);
  size_t typeSize = type == "u8" ? 1 : type == "u16" ? 2 : 4;
  size_t expected = headerBytes + v.voxelCount() * typeSize;
  if (bytes.size() != expected)
    rawAt.fail("volume file '" + path + "' has " + std::to_string(bytes.size()) + " bytes; dims x " + type +
               " + header_bytes need " + std::to_string(expected));
  const unsigned char* data = reinterpret_cast<const unsigned char*>(bytes.data()) + headerBytes;
  v.density.resize(v.voxelCount());
  for (size_t i = 0; i < v.voxelCount(); ++i) {
    if (typeSize == 1) {
      v.density[i] = float(data[i]) / 255.0f;
    } else if (typeSize == 2) {
      v.density[i] = float(uint32_t(data[2 * i]) | (uint32_t(data[2 * i + 1]) << 8)) / 65535.0f;
    } else {
      uint32_t bits = uint32_t(data[4 * i]) | (uint32_t(data[4 * i + 1]) << 8) | (uint32_t(data[4 * i + 2]) << 16) |
                      (uint32_t(data[4 * i + 3]) << 24);
      float d;
      std::memcpy(&d, &bits, 4);
      if (!std::isfinite(d) || d < 0.0f)
        rawAt.fail("volume file '" + path + "': voxel " + std::to_string(i) + " has density " + formatNumber(d) +
                   " (densities must be finite and >= 0)");
      v.density[i] = d;
    }
  }
  return v;
}

}  // namespace vs
