#include "scenes/mesh_utils.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace vs {

static bool isFinite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

static bool isUsableNormal(const glm::vec3& n) {
  return isFinite(n) && glm::dot(n, n) > 1e-24f;
}

// Twice the triangle area vector (direction = face normal by counter-clockwise winding), in double.
static glm::dvec3 areaVector(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  return glm::cross(glm::dvec3(b) - glm::dvec3(a), glm::dvec3(c) - glm::dvec3(a));
}

size_t removeDegenerateTriangles(Mesh& mesh) {
  const size_t vertexCount = mesh.positions.size();
  const bool hasNormals = mesh.normals.size() == vertexCount;
  std::vector<uint32_t> keptIndices;
  keptIndices.reserve(mesh.indices.size());
  size_t removed = 0;
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    uint32_t ia = mesh.indices[t], ib = mesh.indices[t + 1], ic = mesh.indices[t + 2];
    if (ia >= vertexCount || ib >= vertexCount || ic >= vertexCount) {
      ++removed;
      continue;
    }
    const glm::vec3 &a = mesh.positions[ia], &b = mesh.positions[ib], &c = mesh.positions[ic];
    if (!isFinite(a) || !isFinite(b) || !isFinite(c)) {
      ++removed;
      continue;
    }
    glm::dvec3 ab = glm::dvec3(b) - glm::dvec3(a), ac = glm::dvec3(c) - glm::dvec3(a),
               bc = glm::dvec3(c) - glm::dvec3(b);
    double longestSq = std::max({glm::dot(ab, ab), glm::dot(ac, ac), glm::dot(bc, bc)});
    double twiceArea = glm::length(glm::cross(ab, ac));
    if (!(twiceArea > 1e-6 * longestSq)) {
      ++removed;
      continue;
    }
    keptIndices.insert(keptIndices.end(), {ia, ib, ic});
  }

  // Compact: keep only referenced vertices, in their original order.
  std::vector<uint32_t> newIndexOf(vertexCount, UINT32_MAX);
  for (uint32_t i : keptIndices) newIndexOf[i] = 0;
  std::vector<glm::vec3> positions, normals;
  std::vector<glm::vec2> uvs;
  const bool hasUvs = mesh.uvs.size() == vertexCount;
  uint32_t next = 0;
  for (size_t v = 0; v < vertexCount; ++v) {
    if (newIndexOf[v] == UINT32_MAX) continue;
    newIndexOf[v] = next++;
    positions.push_back(mesh.positions[v]);
    if (hasNormals) normals.push_back(mesh.normals[v]);
    if (hasUvs) uvs.push_back(mesh.uvs[v]);
  }
  for (uint32_t& i : keptIndices) i = newIndexOf[i];
  mesh.positions = std::move(positions);
  if (hasNormals) mesh.normals = std::move(normals);
  if (hasUvs) mesh.uvs = std::move(uvs);
  mesh.indices = std::move(keptIndices);
  return removed;
}

// Recomputes the normals of the vertices flagged in `needsNormal` from the faces around them.
static void fillNormals(Mesh& mesh, const std::vector<bool>& needsNormal) {
  const size_t vertexCount = mesh.positions.size();
  std::vector<glm::dvec3> sum(vertexCount, glm::dvec3(0.0));
  std::vector<glm::dvec3> firstFace(vertexCount, glm::dvec3(0.0));
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    uint32_t corner[3] = {mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2]};
    if (corner[0] >= vertexCount || corner[1] >= vertexCount || corner[2] >= vertexCount) continue;
    glm::dvec3 area = areaVector(mesh.positions[corner[0]], mesh.positions[corner[1]], mesh.positions[corner[2]]);
    if (!std::isfinite(area.x + area.y + area.z)) continue;
    for (uint32_t v : corner) {
      if (!needsNormal[v]) continue;
      sum[v] += area;
      if (firstFace[v] == glm::dvec3(0.0)) firstFace[v] = area;
    }
  }
  for (size_t v = 0; v < vertexCount; ++v) {
    if (!needsNormal[v]) continue;
    // Opposite faces sharing a vertex can cancel out; fall back to one face, then to +Y.
    glm::dvec3 n = glm::length(sum[v]) > 1e-12 * glm::length(firstFace[v]) ? sum[v] : firstFace[v];
    double length = glm::length(n);
    mesh.normals[v] = length > 0.0 ? glm::vec3(n / length) : glm::vec3(0, 1, 0);
  }
}

void computeSmoothNormals(Mesh& mesh) {
  mesh.normals.assign(mesh.positions.size(), glm::vec3(0.0f));
  fillNormals(mesh, std::vector<bool>(mesh.positions.size(), true));
}

void repairNormals(Mesh& mesh) {
  if (mesh.normals.size() != mesh.positions.size()) {
    computeSmoothNormals(mesh);
    return;
  }
  std::vector<bool> needsNormal(mesh.normals.size(), false);
  bool anyBad = false;
  for (size_t v = 0; v < mesh.normals.size(); ++v) {
    if (isUsableNormal(mesh.normals[v])) {
      mesh.normals[v] = glm::normalize(mesh.normals[v]);
    } else {
      needsNormal[v] = true;
      anyBad = true;
    }
  }
  if (anyBad) fillNormals(mesh, needsNormal);
}

size_t sanitizeMesh(Mesh& mesh) {
  size_t removed = removeDegenerateTriangles(mesh);
  repairNormals(mesh);
  return removed;
}

void transformMesh(Mesh& mesh, const glm::mat4& m) {
  glm::mat3 linear(m);
  glm::mat3 normalMatrix = glm::transpose(glm::inverse(linear));
  for (glm::vec3& p : mesh.positions) p = glm::vec3(m * glm::vec4(p, 1.0f));
  for (glm::vec3& n : mesh.normals) {
    glm::vec3 t = normalMatrix * n;
    float length = glm::length(t);
    n = length > 0.0f ? t / length : t;  // zero stays zero; repairNormals fixes it later
  }
  if (glm::determinant(linear) < 0.0f) {
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
  }
}

}  // namespace vs
