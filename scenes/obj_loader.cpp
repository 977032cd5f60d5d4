#include "scenes/obj_loader.hpp"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>

#include "scenes/json_reader.hpp"
#include "scenes/mesh_utils.hpp"

namespace vs {

namespace {

std::vector<std::string> tokens(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> out;
  for (std::string t; in >> t;) out.push_back(t);
  return out;
}

bool isNumber(const std::string& t) {
  char* end = nullptr;
  double v = std::strtod(t.c_str(), &end);
  return end && *end == '\0' && std::isfinite(v);
}

// The statements that name materials, with their line numbers.
struct MaterialStatements {
  std::vector<std::pair<std::string, size_t>> mtllibs, usemtls;  // (name, line)
};

// Checks the statements tinyobjloader would read leniently, so that a broken file is an error with
// its line number; returns the material libraries and the materials used.
MaterialStatements validate(const std::string& path, const std::string& text) {
  auto fail = [&](size_t line, const std::string& problem) {
    throwSceneError(path + ":" + std::to_string(line), "", problem);
  };
  long vertices = 0, normals = 0, texcoords = 0;
  MaterialStatements statements;
  std::istringstream in(text);
  std::string line;
  for (size_t number = 1; std::getline(in, line); ++number) {
    auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::vector<std::string> t = tokens(line);
    if (t.empty()) continue;
    const std::string& key = t[0];
    auto numbers = [&](size_t lo, size_t hi, const char* what) {
      if (t.size() - 1 < lo || t.size() - 1 > hi)
        fail(number, std::string(what) + " needs " + std::to_string(lo) + (lo == hi ? "" : " to " + std::to_string(hi)) +
                         " numbers, got " + std::to_string(t.size() - 1));
      for (size_t i = 1; i < t.size(); ++i)
        if (!isNumber(t[i])) fail(number, std::string(what) + ": '" + t[i] + "' is not a finite number");
    };
    if (key == "v") {
      numbers(3, 7, "vertex 'v'");
      ++vertices;
    } else if (key == "vn") {
      numbers(3, 3, "normal 'vn'");
      ++normals;
    } else if (key == "vt") {
      numbers(1, 3, "texture coordinate 'vt'");
      ++texcoords;
    } else if (key == "f") {
      if (t.size() < 4) fail(number, "face 'f' needs at least 3 vertices, got " + std::to_string(t.size() - 1));
      for (size_t i = 1; i < t.size(); ++i) {
        const long counts[3] = {vertices, texcoords, normals};
        const char* names[3] = {"vertex", "texture coordinate", "normal"};
        std::string ref = t[i];
        size_t start = 0;
        for (int k = 0; k < 3; ++k) {
          size_t slash = ref.find('/', start);
          std::string part = ref.substr(start, slash == std::string::npos ? std::string::npos : slash - start);
          if (!part.empty() || k == 0) {
            char* end = nullptr;
            long index = std::strtol(part.c_str(), &end, 10);
            if (part.empty() || !end || *end != '\0' || index == 0)
              fail(number, "face 'f': '" + ref + "' is not a valid vertex reference");
            long resolved = index > 0 ? index : counts[k] + index + 1;
            if (resolved < 1 || resolved > counts[k])
              fail(number, "face 'f': " + std::string(names[k]) + " index " + std::to_string(index) + " out of range (" +
                               std::to_string(counts[k]) + " so far)");
          }
          if (slash == std::string::npos) break;
          start = slash + 1;
        }
      }
    } else if (key == "mtllib") {
      if (t.size() < 2) fail(number, "'mtllib' needs a file name");
      for (size_t i = 1; i < t.size(); ++i) statements.mtllibs.emplace_back(t[i], number);
    } else if (key == "usemtl" && t.size() >= 2) {
      statements.usemtls.emplace_back(t[1], number);
    }
  }
  return statements;
}

}  // namespace

std::vector<Mesh> loadObj(const std::string& path, const glm::mat4& transform, ContentHasher* hasher,
                          std::vector<std::string>* warnings) {
  std::string text, error;
  if (!readFile(path, text, error)) throwSceneError(path, "", "cannot open OBJ file: " + error);
  if (hasher) hasher->addBlock(text);
  const MaterialStatements statements = validate(path, text);
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
    if (hasher) hasher->addBlock(contents);
    mtlText += contents + "\n";
  }
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  if (!reader.ParseFromString(text, mtlText, config))
    throwSceneError(path, "", "invalid OBJ: " + oneLine(reader.Error()));
  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  // The line check above and tinyobjloader may read an odd line differently (a line starting with
  // a vertical tab, say): every index is checked again against what tinyobjloader read.
  const size_t vertexCount = attrib.vertices.size() / 3, normalCount = attrib.normals.size() / 3;
  const std::vector<tinyobj::material_t>& materials = reader.GetMaterials();
  // Materials used but defined nowhere: the default albedo, opaque; said once per name.
  std::map<std::string, bool> known;
  for (const tinyobj::material_t& m : materials) known[m.name] = true;
  for (const auto& [name, line] : statements.usemtls)
    if (!known.count(name)) {
      known[name] = true;
      warn(line, "material '" + name + "' (usemtl) is in no material library: opaque, default albedo");
    }
  std::vector<Mesh> meshes;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    // One mesh per material used by the shape; vertices shared by (position, normal) pairs.
    std::map<int, size_t> meshOfMaterial;
    std::vector<std::map<std::pair<int, int>, uint32_t>> vertexMaps;  // per mesh of this shape
    const size_t firstMesh = meshes.size();
    size_t offset = 0;
    for (size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
      size_t count = shape.mesh.num_face_vertices[f];
      int material = f < shape.mesh.material_ids.size() ? shape.mesh.material_ids[f] : -1;
      if (material >= int(materials.size())) material = -1;
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
        vertexMaps.emplace_back();
      }
      Mesh& mesh = meshes[found->second];
      auto& vertexMap = vertexMaps[found->second - firstMesh];
      if (count == 3) {
        for (size_t k = 0; k < 3; ++k) {
          if (offset + k >= shape.mesh.indices.size()) throwSceneError(path, "", "invalid OBJ: a face has too few indices");
          const tinyobj::index_t& idx = shape.mesh.indices[offset + k];
          if (idx.vertex_index < 0 || size_t(idx.vertex_index) >= vertexCount ||
              (idx.normal_index >= 0 && size_t(idx.normal_index) >= normalCount))
            throwSceneError(path, "", "invalid OBJ: a face refers to a vertex or normal that is not in the file");
          auto key = std::make_pair(idx.vertex_index, idx.normal_index);
          auto it = vertexMap.find(key);
          if (it == vertexMap.end()) {
            size_t v = size_t(idx.vertex_index);
            mesh.positions.emplace_back(attrib.vertices[3 * v], attrib.vertices[3 * v + 1], attrib.vertices[3 * v + 2]);
            if (idx.normal_index >= 0) {
              size_t n = size_t(idx.normal_index);
              mesh.normals.emplace_back(attrib.normals[3 * n], attrib.normals[3 * n + 1], attrib.normals[3 * n + 2]);
            } else {
              mesh.normals.emplace_back(0.0f);  // repaired by the scene loader from the faces
            }
            it = vertexMap.emplace(key, uint32_t(mesh.positions.size() - 1)).first;
          }
          mesh.indices.push_back(it->second);
        }
      }
      offset += count;
    }
  }
  for (Mesh& mesh : meshes) {
    bool anyNormal = std::any_of(mesh.normals.begin(), mesh.normals.end(), [](const glm::vec3& n) { return n != glm::vec3(0.0f); });
    transformMesh(mesh, transform);
    if (!anyNormal) computeSmoothNormals(mesh);  // zero normals of partly-normalled meshes: the scene loader repairs them
  }
  return meshes;
}

}  // namespace vs
