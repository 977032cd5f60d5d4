// scene_load_benchmark: how fast large scenes load and upload, by size, so that a load that is not
// linear in the scene's size shows as a falling rate. Generates a terrain-like grid of triangles as
// a Wavefront OBJ (v, vn and v//vn faces, as exporters write them) and as a binary glTF, at each
// size, in a temporary folder; loads each through a scene file ({"obj": ...}, {"gltf": ...}) as
// `vshadow run` does, then uploads it to the GPU (the harness's vertex and index buffers) on a
// headless GL context. Prints a Markdown table of triangles per second; not a test.
// Usage: scene_load_benchmark [--triangles N,N,...] [--formats obj,glb] [--no-upload] [--keep]
// (default 250000,1000000,4000000 triangles, both formats, upload on, files removed).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "harness/cli/scene_load.hpp"
#include "harness/gl/context.hpp"
#include "harness/gl/gl.hpp"
#include "harness/pipeline/frame.hpp"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start) { return std::chrono::duration<double, std::milli>(Clock::now() - start).count(); }

// An n x n grid of quads (2 n^2 triangles) over [-5, 5]^2 with a gentle height field.
struct Grid {
  int n = 1;
  explicit Grid(size_t triangles) : n(std::max(1, int(std::lround(std::sqrt(double(triangles) / 2.0))))) {}
  size_t vertices() const { return size_t(n + 1) * size_t(n + 1); }
  size_t triangles() const { return 2 * size_t(n) * size_t(n); }
  void position(int i, int j, float p[3]) const {
    float x = float(i) / float(n), z = float(j) / float(n);
    p[0] = 10.0f * x - 5.0f;
    p[1] = 0.2f * std::sin(20.0f * x) * std::cos(17.0f * z);
    p[2] = 10.0f * z - 5.0f;
  }
  // The two triangles of quad (i, j), counter-clockwise from above, as 0-based vertex indices.
  void quad(int i, int j, uint32_t t[6]) const {
    uint32_t a = uint32_t(j) * uint32_t(n + 1) + uint32_t(i), b = a + 1, c = a + uint32_t(n + 1), d = c + 1;
    uint32_t out[6] = {a, c, b, b, c, d};
    std::memcpy(t, out, sizeof out);
  }
};

void writeBytes(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), std::streamsize(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

// OBJ text: positions, one normal per vertex (the height field's), faces v//vn.
void writeObj(const Grid& g, const fs::path& path) {
  std::string text;
  text.reserve(g.vertices() * 70 + g.triangles() * 40);
  char line[128];
  text += "# scene_load_benchmark grid\no grid\n";
  for (int j = 0; j <= g.n; ++j)
    for (int i = 0; i <= g.n; ++i) {
      float p[3];
      g.position(i, j, p);
      text.append(line, size_t(std::snprintf(line, sizeof line, "v %.6f %.6f %.6f\n", p[0], p[1], p[2])));
    }
  for (int j = 0; j <= g.n; ++j)
    for (int i = 0; i <= g.n; ++i) text += "vn 0 1 0\n";
  for (int j = 0; j < g.n; ++j)
    for (int i = 0; i < g.n; ++i) {
      uint32_t t[6];
      g.quad(i, j, t);
      for (int k = 0; k < 6; k += 3)
        text.append(line, size_t(std::snprintf(line, sizeof line, "f %u//%u %u//%u %u//%u\n", t[k] + 1, t[k] + 1,
                                               t[k + 1] + 1, t[k + 1] + 1, t[k + 2] + 1, t[k + 2] + 1)));
    }
  writeBytes(path, text);
}

void appendU32(std::string& out, uint32_t v) {
  char b[4];
  std::memcpy(b, &v, 4);  // little endian on every machine this runs on
  out.append(b, 4);
}

// A .glb: one mesh, float positions and uint32 indices in one buffer (normals computed at load).
void writeGlb(const Grid& g, const fs::path& path) {
  std::string bin;
  bin.reserve(g.vertices() * 12 + g.triangles() * 12);
  float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
  for (int j = 0; j <= g.n; ++j)
    for (int i = 0; i <= g.n; ++i) {
      float p[3];
      g.position(i, j, p);
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], p[k]);
        hi[k] = std::max(hi[k], p[k]);
      }
      bin.append(reinterpret_cast<const char*>(p), sizeof p);
    }
  const size_t positionBytes = bin.size();
  for (int j = 0; j < g.n; ++j)
    for (int i = 0; i < g.n; ++i) {
      uint32_t t[6];
      g.quad(i, j, t);
      for (uint32_t v : t) appendU32(bin, v);
    }
  const size_t indexBytes = bin.size() - positionBytes;
  std::ostringstream json;
  json << R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],)"
       << R"( "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],)"
       << R"( "buffers": [{"byteLength": )" << bin.size() << "}],"
       << R"( "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": )" << positionBytes
       << R"(}, {"buffer": 0, "byteOffset": )" << positionBytes << R"(, "byteLength": )" << indexBytes << "}],"
       << R"( "accessors": [{"bufferView": 0, "componentType": 5126, "count": )" << g.vertices()
       << R"(, "type": "VEC3", "min": [)" << lo[0] << ", " << lo[1] << ", " << lo[2] << "], \"max\": [" << hi[0] << ", "
       << hi[1] << ", " << hi[2] << "]},"
       << R"( {"bufferView": 1, "componentType": 5125, "count": )" << g.triangles() * 3 << R"(, "type": "SCALAR"}]})";
  std::string chunk = json.str();
  chunk.resize((chunk.size() + 3) / 4 * 4, ' ');
  bin.resize((bin.size() + 3) / 4 * 4, '\0');
  std::string glb = "glTF";
  appendU32(glb, 2);
  appendU32(glb, uint32_t(12 + 8 + chunk.size() + 8 + bin.size()));
  appendU32(glb, uint32_t(chunk.size()));
  glb += "JSON" + chunk;
  appendU32(glb, uint32_t(bin.size()));
  glb += std::string("BIN\0", 4);
  glb += bin;
  writeBytes(path, glb);
}

std::string format1(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

[[noreturn]] void usage(const std::string& problem) {
  std::fprintf(stderr, "scene_load_benchmark: %s\nusage: scene_load_benchmark [--triangles N,N,...] "
                       "[--formats obj,glb] [--no-upload] [--keep]\n", problem.c_str());
  std::exit(2);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<size_t> sizes = {250000, 1000000, 4000000};
  std::vector<std::string> formats = {"obj", "glb"};
  bool upload = true, keep = false;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--triangles" && i + 1 < argc) {
      sizes.clear();
      for (const std::string& s : split(argv[++i])) {
        char* end = nullptr;
        unsigned long long n = std::strtoull(s.c_str(), &end, 10);
        if (!end || *end || n < 2 || n > 40000000) usage("--triangles: '" + s + "' is not a count in [2, 40000000]");
        sizes.push_back(size_t(n));
      }
    } else if (a == "--formats" && i + 1 < argc) {
      formats = split(argv[++i]);
      for (const std::string& f : formats)
        if (f != "obj" && f != "glb") usage("--formats: '" + f + "' is not obj or glb");
    } else if (a == "--no-upload") {
      upload = false;
    } else if (a == "--keep") {
      keep = true;
    } else {
      usage("unknown argument '" + a + "'");
    }
  }
  try {
    std::unique_ptr<vs::GlContext> context;
    if (upload) context = std::make_unique<vs::GlContext>(false);
    const fs::path dir = fs::temp_directory_path() / ("vshadow-scene-load-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    std::printf("# Scene loading and upload by size\n\n");
    if (context) std::printf("GL: %s\n\n", context->info().glRenderer.c_str());
    std::printf("Files in %s. Load: loadScene on a scene file naming the model (read, check, parse, "
                "build meshes, clean them); upload: the harness's vertex and index buffers (SceneGpu) to glFinish.\n\n",
                keep ? dir.string().c_str() : "a temporary folder");
    std::printf("| format | triangles | file MB | write s | load ms | load Mtri/s | peak RSS growth MB | scene MB | upload ms | upload Mtri/s |\n");
    std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (const std::string& format : formats)
      for (size_t requested : sizes) {
        const Grid grid(requested);
        const std::string stem = "grid-" + std::to_string(grid.triangles());
        const fs::path model = dir / (stem + "." + format), sceneFile = dir / (stem + "-" + format + ".json");
        auto written = Clock::now();
        if (format == "obj") writeObj(grid, model);
        else writeGlb(grid, model);
        const double writeMs = msSince(written);
        writeBytes(sceneFile, std::string(R"({"geometry": [{")") + (format == "obj" ? "obj" : "gltf") + R"(": ")" +
                                  model.filename().string() + R"("}], "camera": {"position": [0, 6, 9], "target": [0, 0, 0]},)" +
                                  R"( "light": {"type": "directional", "direction": [0.3, -1, 0.2], "intensity": 3}})");
        vs::SceneLoad figures;
        vs::Scene scene = vs::loadSceneMeasured(sceneFile.string(), figures);
        if (figures.triangles != grid.triangles())
          throw std::runtime_error(model.string() + ": loaded " + std::to_string(figures.triangles) + " triangles of " +
                                   std::to_string(grid.triangles()));
        double uploadMs = 0.0;
        if (context) {
          glFinish();
          auto start = Clock::now();
          {
            vs::SceneGpu gpu(scene);
            glFinish();
            uploadMs = msSince(start);
          }
          glFinish();
        }
        const double mb = 1.0 / (1024.0 * 1024.0);
        const std::string rss = figures.peakRssDeltaBytes >= 0 ? format1("%.0f", double(figures.peakRssDeltaBytes) * mb) : "-";
        std::printf("| %s | %zu | %.1f | %.2f | %.0f | %.2f | %s | %.1f | %s | %s |\n", format.c_str(), figures.triangles,
                    double(fs::file_size(model)) * mb, writeMs / 1000.0, figures.ms,
                    double(figures.triangles) / figures.ms / 1000.0, rss.c_str(), double(figures.bytes) * mb,
                    context ? format1("%.0f", uploadMs).c_str() : "-",
                    context ? format1("%.2f", double(figures.triangles) / uploadMs / 1000.0).c_str() : "-");
        std::fflush(stdout);
        if (!keep) {
          fs::remove(model);
          fs::remove(sceneFile);
        }
      }
    if (!keep) fs::remove_all(dir);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "scene_load_benchmark: %s\n", e.what());
    return 1;
  }
  return 0;
}
