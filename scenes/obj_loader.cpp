#include "scenes/obj_loader.hpp"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <istream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <streambuf>
#include <string_view>

#include "scenes/json_reader.hpp"
#include "scenes/mesh_utils.hpp"
#include "scenes/procedural.hpp"

namespace vs {

namespace {

// Lines between progress reports while a file is checked, and faces while meshes are built.
constexpr size_t kReportEvery = size_t(1) << 16;

// A word of a line: [begin, end) inside the file's text, which stays alive while it is checked.
struct Token {
  const char* begin;
  const char* end;
  std::string str() const { return std::string(begin, end); }
  bool is(const char* word) const {
    size_t n = std::strlen(word);
    return size_t(end - begin) == n && std::memcmp(begin, word, n) == 0;
  }
};

// Whitespace as `std::istream >> word` splits words in the C locale.
bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\v' || c == '\f' || c == '\r'; }

// Splits [begin, end) into words; `out` is reused line after line, so that checking a file does
// not allocate per line.
void splitWords(const char* begin, const char* end, std::vector<Token>& out) {
  out.clear();
  for (const char* p = begin; p < end;) {
    while (p < end && isSpace(*p)) ++p;
    if (p == end) break;
    const char* start = p;
    while (p < end && !isSpace(*p)) ++p;
    out.push_back({start, p});
  }
}

// The word, up to a NUL byte in it (words were C strings), is a finite number in strtod's syntax.
// std::from_chars reads the usual forms several times faster, and every word it takes whole strtod
// takes too; the rest (a leading '+', hexadecimal, a value out of range, a NUL) goes to strtod,
// which stops at the whitespace, '#', NUL or end of text (a NUL: std::string) after a number.
bool isNumber(const Token& t) {
  double v = 0.0;
  auto [ptr, ec] = std::from_chars(t.begin, t.end, v);
  if (ec == std::errc() && ptr == t.end) return std::isfinite(v);
  char* end = nullptr;
  v = std::strtod(t.begin, &end);
  return (end == t.end || *end == '\0') && std::isfinite(v);
}

// strtol(begin, &end, 10) for a part of a word (no whitespace in it), without the locale.
long parseIndex(const char* begin, const char* end, const char** stop) {
  const char* p = begin;
  const bool negative = p < end && *p == '-';
  if (p < end && (*p == '-' || *p == '+')) ++p;
  const char* digits = p;
  long value = 0;
  bool overflow = false;
  for (; p < end && *p >= '0' && *p <= '9'; ++p) {
    const int d = *p - '0';
    if (value > (std::numeric_limits<long>::max() - d) / 10) overflow = true;
    else value = value * 10 + d;
  }
  if (p == digits) {  // no digits: nothing read
    *stop = begin;
    return 0;
  }
  *stop = p;
  if (overflow) return negative ? std::numeric_limits<long>::min() : std::numeric_limits<long>::max();
  return negative ? -value : value;
}

// Calls `perLine(number, words)` for every line of `text` (lines end at '\n', '#' starts a
// comment), skipping lines without words, and `progress(fraction of the bytes)` every few lines.
template <typename PerLine>
void forEachLine(const std::string& text, const std::function<void(double)>& progress, PerLine perLine) {
  std::vector<Token> words;
  const char* p = text.data();
  const char* const end = p + text.size();
  for (size_t number = 1; p < end; ++number) {
    const char* newline = static_cast<const char*>(std::memchr(p, '\n', size_t(end - p)));
    const char* lineEnd = newline ? newline : end;
    const char* hash = static_cast<const char*>(std::memchr(p, '#', size_t(lineEnd - p)));
    splitWords(p, hash ? hash : lineEnd, words);
    if (!words.empty()) perLine(number, words);
    p = newline ? newline + 1 : end;
    if (progress && number % kReportEvery == 0) progress(double(p - text.data()) / double(text.size()));
  }
}

// The statements that name materials, with their line numbers.
struct MaterialStatements {
  std::vector<std::pair<std::string, size_t>> mtllibs, usemtls;  // (name, line); usemtls: each name once
};

// Checks the statements tinyobjloader would read leniently, so that a broken file is an error with
// its line number; returns the material libraries and the materials used.
MaterialStatements validate(const std::string& path, const std::string& text, const std::function<void(double)>& progress) {
  auto fail = [&](size_t line, const std::string& problem) {
    throwSceneError(path + ":" + std::to_string(line), "", problem);
  };
  long vertices = 0, normals = 0, texcoords = 0;
  MaterialStatements statements;
  std::set<std::string, std::less<>> used;  // names in usemtls (exporters may say usemtl before every face)
  forEachLine(text, progress, [&](size_t number, const std::vector<Token>& t) {
    const Token& key = t[0];
    auto numbers = [&](size_t lo, size_t hi, const char* what) {
      if (t.size() - 1 < lo || t.size() - 1 > hi)
        fail(number, std::string(what) + " needs " + std::to_string(lo) + (lo == hi ? "" : " to " + std::to_string(hi)) +
                         " numbers, got " + std::to_string(t.size() - 1));
      for (size_t i = 1; i < t.size(); ++i)
        if (!isNumber(t[i])) fail(number, std::string(what) + ": '" + t[i].str() + "' is not a finite number");
    };
    if (key.is("v")) {
      numbers(3, 7, "vertex 'v'");
      ++vertices;
    } else if (key.is("vn")) {
      numbers(3, 3, "normal 'vn'");
      ++normals;
    } else if (key.is("vt")) {
      numbers(1, 3, "texture coordinate 'vt'");
      ++texcoords;
    } else if (key.is("f")) {
      if (t.size() < 4) fail(number, "face 'f' needs at least 3 vertices, got " + std::to_string(t.size() - 1));
      const long counts[3] = {vertices, texcoords, normals};
      const char* names[3] = {"vertex", "texture coordinate", "normal"};
      for (size_t i = 1; i < t.size(); ++i) {
        const Token& ref = t[i];
        const char* start = ref.begin;
        for (int k = 0; k < 3; ++k) {  // vertex/texture/normal; anything after a third '/' is not read
          const char* slash = static_cast<const char*>(std::memchr(start, '/', size_t(ref.end - start)));
          const char* partEnd = slash ? slash : ref.end;
          if (partEnd != start || k == 0) {
            const char* end = nullptr;
            long index = partEnd == start ? 0 : parseIndex(start, partEnd, &end);
            if (partEnd == start || (end != partEnd && *end != '\0') || index == 0)
              fail(number, "face 'f': '" + ref.str() + "' is not a valid vertex reference");
            long resolved = index > 0 ? index : counts[k] + index + 1;
            if (resolved < 1 || resolved > counts[k])
              fail(number, "face 'f': " + std::string(names[k]) + " index " + std::to_string(index) + " out of range (" +
                               std::to_string(counts[k]) + " so far)");
          }
          if (!slash) break;
          start = slash + 1;
        }
      }
    } else if (key.is("mtllib")) {
      if (t.size() < 2) fail(number, "'mtllib' needs a file name");
      for (size_t i = 1; i < t.size(); ++i) statements.mtllibs.emplace_back(t[i].str(), number);
    } else if (key.is("usemtl") && t.size() >= 2) {
      const std::string_view name(t[1].begin, size_t(t[1].end - t[1].begin));
      if (used.find(name) == used.end()) {
        used.emplace(name);
        statements.usemtls.emplace_back(std::string(name), number);
      }
    }
  });
  return statements;
}

// Checks the material statements the loader uses: tinyobjloader reads a value that is not a number
// as 0, which would make an unreadable `d` an invisible surface and an unreadable `Kd` black.
void validateMtl(const std::string& path, const std::string& text) {
  forEachLine(text, {}, [&](size_t number, const std::vector<Token>& t) {
    const char* what = t[0].is("Kd") ? "diffuse colour 'Kd'" : t[0].is("d") ? "dissolve 'd'" : t[0].is("Tr") ? "transparency 'Tr'" : nullptr;
    if (!what) return;
    const size_t wanted = t[0].is("Kd") ? 3 : 1;
    auto fail = [&](const std::string& problem) { throwSceneError(path + ":" + std::to_string(number), "", problem); };
    if (t.size() - 1 != wanted)
      fail(std::string(what) + " needs " + std::to_string(wanted) + (wanted == 1 ? " number" : " numbers") + ", got " +
           std::to_string(t.size() - 1));
    for (size_t i = 1; i < t.size(); ++i)
      if (!isNumber(t[i])) fail(std::string(what) + ": '" + t[i].str() + "' is not a finite number");
  });
}

// The OBJ text as a stream for tinyobjloader without a copy, handed over in windows so that each
// refill reports how far the parse has come.
class WindowedText : public std::streambuf {
 public:
  WindowedText(const std::string& text, const std::function<void(double)>& progress) : text_(text), progress_(progress) {
    char* base = const_cast<char*>(text_.data());  // read only: a get area never writes
    setg(base, base, base);
  }

 protected:
  int_type underflow() override {
    if (gptr() < egptr()) return traits_type::to_int_type(*gptr());
    const size_t at = size_t(egptr() - text_.data());
    if (at >= text_.size()) return traits_type::eof();
    if (progress_) progress_(double(at) / double(text_.size()));
    char* base = const_cast<char*>(text_.data());
    setg(base + at, base + at, base + at + std::min(kWindow, text_.size() - at));
    return traits_type::to_int_type(*gptr());
  }

 private:
  static constexpr size_t kWindow = size_t(1) << 20;
  const std::string& text_;
  const std::function<void(double)>& progress_;
};

// The vertices of one mesh by (position, normal) index pair: open addressing with linear probing,
// so that building a mesh costs the same per face however large it is (an ordered map cost a
// logarithm per face corner).
class VertexIndex {
 public:
  // The vertex stored for `key`; when there is none, stores `fresh` and sets `inserted`.
  uint32_t findOrAdd(uint64_t key, uint32_t fresh, bool& inserted) {
    if (2 * (size_ + 1) > keys_.size()) grow();
    const size_t mask = keys_.size() - 1;
    for (size_t slot = size_t(mix64(key)) & mask;; slot = (slot + 1) & mask) {
      if (keys_[slot] == kEmpty) {
        keys_[slot] = key;
        values_[slot] = fresh;
        ++size_;
        inserted = true;
        return fresh;
      }
      if (keys_[slot] == key) {
        inserted = false;
        return values_[slot];
      }
    }
  }

 private:
  static constexpr uint64_t kEmpty = ~uint64_t(0);  // no key: vertex indices are below 2^31
  void grow() {
    std::vector<uint64_t> keys = std::move(keys_);
    std::vector<uint32_t> values = std::move(values_);
    keys_.assign(std::max<size_t>(64, keys.size() * 2), kEmpty);
    values_.assign(keys_.size(), 0);
    size_ = 0;
    bool inserted = false;
    for (size_t i = 0; i < keys.size(); ++i)
      if (keys[i] != kEmpty) findOrAdd(keys[i], values[i], inserted);
  }
  std::vector<uint64_t> keys_;
  std::vector<uint32_t> values_;
  size_t size_ = 0;
};

}  // namespace

std::vector<Mesh> loadObj(const std::string& path, const glm::mat4& transform, ContentHasher* hasher,
                          std::vector<std::string>* warnings, const LoadProgress& progress) {
  const std::string file = std::filesystem::path(path).filename().string();
  auto stage = [&](const std::string& what) -> std::function<void(double)> {
    if (!progress) return {};
    std::string name = file + ": " + what;
    return [&progress, name](double fraction) { progress(name, fraction); };
  };
  std::string text, error;
  if (!readFile(path, text, error)) throwSceneError(path, "", "cannot open OBJ file: " + error);
  if (hasher) hasher->addBlock(text);
  const std::function<void(double)> checking = stage("checking"), parsing = stage("parsing"), building = stage("building meshes");
  if (checking) checking(0.0);
  const MaterialStatements statements = validate(path, text, checking);
  auto warn = [&](size_t line, const std::string& problem) {
    if (warnings) warnings->push_back(path + ":" + std::to_string(line) + ": " + problem);
  };
  std::string mtlText;
  std::filesystem::path dir = std::filesystem::path(path).parent_path();
  for (const auto& [name, line] : statements.mtllibs) {
    std::string mtlPath = (dir / name).string(), contents;
    if (!readFile(mtlPath, contents, error)) {
      warn(line, "material library '" + mtlPath + "' (mtllib) cannot be read (" + error +
                     "): its materials are opaque with the default albedo");
      continue;
    }
    validateMtl(mtlPath, contents);
    if (hasher) hasher->addBlock(contents);
    mtlText += contents + "\n";
  }
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  {
    std::string parseWarning, parseError;
    WindowedText objBuffer(text, parsing);
    std::istream objStream(&objBuffer);
    std::istringstream mtlStream(mtlText);
    tinyobj::MaterialStreamReader mtlReader(mtlStream);
    if (!tinyobj::LoadObj(&attrib, &shapes, &materials, &parseWarning, &parseError, &objStream, &mtlReader,
                          /*triangulate=*/true, /*default_vcols_fallback=*/false))
      throwSceneError(path, "", "invalid OBJ: " + oneLine(parseError));
  }
  std::string().swap(text);  // the text is read: free it before the meshes grow
  // The line check above and tinyobjloader may read an odd line differently (a line starting with
  // a vertical tab, say): every index is checked again against what tinyobjloader read.
  const size_t vertexCount = attrib.vertices.size() / 3, normalCount = attrib.normals.size() / 3;
  // Materials used but defined nowhere: the default albedo, opaque; said once per name.
  std::map<std::string, bool> known;
  for (const tinyobj::material_t& m : materials) known[m.name] = true;
  for (const auto& [name, line] : statements.usemtls)
    if (!known.count(name)) {
      known[name] = true;
      warn(line, "material '" + name + "' (usemtl) is in no material library: opaque, default albedo");
    }
  // Each position's first use: the mesh and normal it came with and the vertex made for them. Most
  // files use a position with one normal in one mesh, and then this array, read in file order, is
  // all the lookup there is; other (position, normal) pairs of a mesh go to its VertexIndex.
  struct FirstUse {
    uint32_t mesh = ~uint32_t(0);  // none yet
    int normal = -1;
    uint32_t vertex = 0;
  };
  std::vector<FirstUse> firstUse(vertexCount);
  size_t totalFaces = 0, facesDone = 0;
  for (const tinyobj::shape_t& shape : shapes) totalFaces += shape.mesh.num_face_vertices.size();
  if (building) building(0.0);
  std::vector<Mesh> meshes;
  for (const tinyobj::shape_t& shape : shapes) {
    // One mesh per material used by the shape; vertices shared by (position, normal) pairs.
    std::map<int, size_t> meshOfMaterial;
    std::vector<VertexIndex> vertexIndices;  // per mesh of this shape
    const size_t firstMesh = meshes.size();
    int lastMaterial = -2;     // the material of the previous face, and its mesh
    size_t lastMesh = 0;
    size_t offset = 0;
    for (size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
      if (building && ++facesDone % kReportEvery == 0) building(double(facesDone) / double(totalFaces));
      size_t count = shape.mesh.num_face_vertices[f];
      int material = f < shape.mesh.material_ids.size() ? shape.mesh.material_ids[f] : -1;
      if (material >= int(materials.size())) material = -1;
      if (material != lastMaterial) {
        auto found = meshOfMaterial.find(material);
        if (found == meshOfMaterial.end()) {
          Mesh mesh;
          mesh.name = (shape.name.empty() ? "obj" : shape.name) + (material >= 0 ? "/" + materials[size_t(material)].name : "");
          if (material >= 0) {
            const tinyobj::material_t& m = materials[size_t(material)];
            for (int c = 0; c < 3; ++c) mesh.albedo[c] = std::isfinite(m.diffuse[c]) ? std::clamp(float(m.diffuse[c]), 0.0f, 1.0f) : 0.8f;
            mesh.opacity = std::isfinite(m.dissolve) ? std::clamp(float(m.dissolve), 0.0f, 1.0f) : 1.0f;
          }
          found = meshOfMaterial.emplace(material, meshes.size()).first;
          meshes.push_back(std::move(mesh));
          vertexIndices.emplace_back();
        }
        lastMaterial = material;
        lastMesh = found->second;
      }
      Mesh& mesh = meshes[lastMesh];
      VertexIndex& vertexIndex = vertexIndices[lastMesh - firstMesh];
      if (count == 3) {
        for (size_t k = 0; k < 3; ++k) {
          if (offset + k >= shape.mesh.indices.size()) throwSceneError(path, "", "invalid OBJ: a face has too few indices");
          const tinyobj::index_t& idx = shape.mesh.indices[offset + k];
          if (idx.vertex_index < 0 || size_t(idx.vertex_index) >= vertexCount ||
              (idx.normal_index >= 0 && size_t(idx.normal_index) >= normalCount))
            throwSceneError(path, "", "invalid OBJ: a face refers to a vertex or normal that is not in the file");
          FirstUse& first = firstUse[size_t(idx.vertex_index)];
          const uint32_t fresh = uint32_t(mesh.positions.size());
          uint32_t vertex = fresh;
          bool inserted = false;
          if (first.mesh == uint32_t(lastMesh) && first.normal == idx.normal_index) {
            vertex = first.vertex;
          } else if (first.mesh == ~uint32_t(0)) {
            first = {uint32_t(lastMesh), idx.normal_index, fresh};
            inserted = true;
          } else {
            // normal_index -1 (none) and up: the key never takes the empty slot's value.
            const uint64_t key = uint64_t(uint32_t(idx.vertex_index)) << 32 | uint32_t(idx.normal_index + 1);
            vertex = vertexIndex.findOrAdd(key, fresh, inserted);
          }
          if (inserted) {
            size_t v = size_t(idx.vertex_index);
            mesh.positions.emplace_back(attrib.vertices[3 * v], attrib.vertices[3 * v + 1], attrib.vertices[3 * v + 2]);
            if (idx.normal_index >= 0) {
              size_t n = size_t(idx.normal_index);
              mesh.normals.emplace_back(attrib.normals[3 * n], attrib.normals[3 * n + 1], attrib.normals[3 * n + 2]);
            } else {
              mesh.normals.emplace_back(0.0f);  // repaired by the scene loader from the faces
            }
          }
          mesh.indices.push_back(vertex);
        }
      }
      offset += count;
    }
  }
  if (building) building(1.0);
  for (Mesh& mesh : meshes) {
    bool anyNormal = std::any_of(mesh.normals.begin(), mesh.normals.end(), [](const glm::vec3& n) { return n != glm::vec3(0.0f); });
    transformMesh(mesh, transform);
    if (!anyNormal) computeSmoothNormals(mesh);  // zero normals of partly-normalled meshes: the scene loader repairs them
  }
  return meshes;
}

}  // namespace vs
