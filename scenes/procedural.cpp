#include "scenes/procedural.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <stdexcept>
#include <unordered_map>
#include "scenes/json_reader.hpp"
#include "scenes/mesh_utils.hpp"

namespace vs {

uint64_t mix64(uint64_t x) {
  x ^= x >> 31;
  x *= 0x7fb5d329728ea185ull;
  x ^= x >> 27;
  x *= 0x81dadef4bc2dd44dull;
  x ^= x >> 33;
  return x;
}

namespace {

constexpr float kPi = 3.14159265358979323846f;

struct Vertex {
  glm::vec3 position, normal;
};

// Collects vertices and triangles; triangles are wound counter-clockwise around their vertex normals.
class MeshBuilder {
 public:
  explicit MeshBuilder(std::string name) { mesh_.name = std::move(name); }

  uint32_t vertexCount() const { return uint32_t(mesh_.positions.size()); }
  uint32_t vertex(const glm::vec3& position, const glm::vec3& normal) {
    mesh_.positions.push_back(position);
    mesh_.normals.push_back(normal);
    return uint32_t(mesh_.positions.size() - 1);
  }
  uint32_t vertex(const Vertex& v) { return vertex(v.position, v.normal); }
  // A vertex with a texture coordinate: a mesh built with these has one per vertex.
  uint32_t vertex(const glm::vec3& position, const glm::vec3& normal, const glm::vec2& uv) {
    mesh_.uvs.push_back(uv);
    return vertex(position, normal);
  }

  void triangle(uint32_t a, uint32_t b, uint32_t c) {
    const auto& p = mesh_.positions;
    const auto& n = mesh_.normals;
    glm::vec3 face = glm::cross(p[b] - p[a], p[c] - p[a]);
    if (glm::dot(face, n[a] + n[b] + n[c]) < 0.0f) std::swap(b, c);
    mesh_.indices.insert(mesh_.indices.end(), {a, b, c});
  }
  void quad(uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
    triangle(a, b, c);
    triangle(a, c, d);
  }
  void reserve(size_t vertices, size_t triangles) {
    mesh_.positions.reserve(vertices);
    mesh_.normals.reserve(vertices);
    mesh_.indices.reserve(triangles * 3);
  }
  Mesh take() { return std::move(mesh_); }

 private:
  Mesh mesh_;
};

// Adds a grid of columns x rows quads with vertices vertexAt(i, j), i in [0, columns], j in [0, rows].
// A wrapped direction reuses its first line of vertices instead of repeating it (closed surfaces).
void addGrid(MeshBuilder& builder, int columns, int rows, bool wrapColumns, bool wrapRows,
             const std::function<Vertex(int, int)>& vertexAt) {
  const int verticesPerRow = wrapColumns ? columns : columns + 1;
  const int vertexRows = wrapRows ? rows : rows + 1;
  const uint32_t first = builder.vertexCount();
  for (int j = 0; j < vertexRows; ++j)
    for (int i = 0; i < verticesPerRow; ++i) builder.vertex(vertexAt(i, j));
  auto id = [&](int i, int j) {
    return first + uint32_t((j % vertexRows) * verticesPerRow + (i % verticesPerRow));
  };
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < columns; ++i) builder.quad(id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
}

// Rotation by Euler angles in degrees, applied about X, then Y, then Z.
glm::mat3 eulerRotation(const glm::vec3& degrees) {
  glm::vec3 r = glm::radians(degrees);
  float cx = std::cos(r.x), sx = std::sin(r.x), cy = std::cos(r.y), sy = std::sin(r.y);
  float cz = std::cos(r.z), sz = std::sin(r.z);
  glm::mat3 rx(1, 0, 0, 0, cx, sx, 0, -sx, cx);  // columns = images of the basis vectors
  glm::mat3 ry(cy, 0, -sy, 0, 1, 0, sy, 0, cy);
  glm::mat3 rz(cz, sz, 0, -sz, cz, 0, 0, 0, 1);
  return rz * ry * rx;
}

// Two unit vectors perpendicular to `axis` and to each other.
void perpendicularBasis(const glm::vec3& axis, glm::vec3& u, glm::vec3& w) {
  glm::vec3 helper = std::fabs(axis.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
  u = glm::normalize(glm::cross(helper, axis));
  w = glm::cross(axis, u);
}

// Box with orthonormal `axes` (columns) and half extents; flat-shaded, 24 vertices, 12 triangles.
void addOrientedBox(MeshBuilder& builder, const glm::vec3& center, const glm::mat3& axes, const glm::vec3& half) {
  for (int k = 0; k < 3; ++k) {
    for (float side : {-1.0f, 1.0f}) {
      glm::vec3 normal = side * axes[k];
      glm::vec3 faceCenter = center + normal * half[k];
      glm::vec3 u = axes[(k + 1) % 3] * half[(k + 1) % 3];
      glm::vec3 v = axes[(k + 2) % 3] * half[(k + 2) % 3];
      uint32_t a = builder.vertex(faceCenter - u - v, normal);
      uint32_t b = builder.vertex(faceCenter + u - v, normal);
      uint32_t c = builder.vertex(faceCenter + u + v, normal);
      uint32_t d = builder.vertex(faceCenter - u + v, normal);
      builder.quad(a, b, c, d);
    }
  }
}

// Square-section beam from a to b (a thin box), its second axis along `side`.
void addBeam(MeshBuilder& builder, const glm::vec3& a, const glm::vec3& b, const glm::vec3& side, float radius) {
  glm::vec3 along = b - a;
  float length = glm::length(along);
  along /= length;
  glm::vec3 third = glm::normalize(glm::cross(along, side));
  glm::vec3 second = glm::cross(third, along);
  addOrientedBox(builder, 0.5f * (a + b), glm::mat3(along, second, third), glm::vec3(0.5f * length, radius, radius));
}

// Open-ended prism from `start` to `end` whose radius tapers from r0 to r1; smooth side normals.
void addTaperedPrism(MeshBuilder& builder, const glm::vec3& start, const glm::vec3& end, float r0, float r1,
                     int sides) {
  glm::vec3 axis = end - start;
  float length = glm::length(axis);
  axis /= length;
  glm::vec3 u, w;
  perpendicularBasis(axis, u, w);
  const float slope = (r0 - r1) / length;  // the surface normal tilts towards the narrow end
  addGrid(builder, sides, 1, true, false, [&](int i, int j) {
    float angle = 2.0f * kPi * float(i) / float(sides);
    glm::vec3 radial = std::cos(angle) * u + std::sin(angle) * w;
    glm::vec3 position = (j == 0 ? start : end) + radial * (j == 0 ? r0 : r1);
    return Vertex{position, glm::normalize(radial + slope * axis)};
  });
}

void appendMesh(Mesh& target, const Mesh& source) {
  uint32_t offset = uint32_t(target.positions.size());
  target.positions.insert(target.positions.end(), source.positions.begin(), source.positions.end());
  target.normals.insert(target.normals.end(), source.normals.begin(), source.normals.end());
  for (uint32_t i : source.indices) target.indices.push_back(offset + i);
}

// Portable random numbers: std::mt19937 output is fixed by the standard; the mapping to [0, 1) is ours.
class Random {
 public:
  explicit Random(uint32_t seed) : engine_(seed) {}
  float uniform() { return float(double(engine_()) * (1.0 / 4294967296.0)); }
  float symmetric() { return 2.0f * uniform() - 1.0f; }  // [-1, 1)

 private:
  std::mt19937 engine_;
};

uint32_t deriveSeed(uint32_t seed, uint64_t index) {
  return uint32_t(mix64((uint64_t(seed) << 32) ^ (index + 0x9e3779b97f4a7c15ull)));
}

// Value noise in [0, 1) with C2 (quintic) interpolation between hashed lattice values.
double valueNoise(double x, double z, uint32_t octave, uint32_t seed) {
  double fx = std::floor(x), fz = std::floor(z);
  auto lattice = [&](double ix, double iz) {
    uint64_t key = mix64(uint64_t(int64_t(ix)) * 0x9e3779b97f4a7c15ull ^ mix64(uint64_t(int64_t(iz)) + octave) ^
                         (uint64_t(seed) << 20));
    return double(key >> 11) * (1.0 / 9007199254740992.0);
  };
  auto fade = [](double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); };
  double tx = fade(x - fx), tz = fade(z - fz);
  double v00 = lattice(fx, fz), v10 = lattice(fx + 1, fz), v01 = lattice(fx, fz + 1), v11 = lattice(fx + 1, fz + 1);
  double bottom = v00 + (v10 - v00) * tx, top = v01 + (v11 - v01) * tx;
  return bottom + (top - bottom) * tz;
}

uint64_t treeSegmentCount(int branches, int depth) {
  uint64_t total = 0, level = 1;
  for (int d = 0; d < depth; ++d) {
    total += level;
    level *= uint64_t(branches);
  }
  return total;
}

}  // namespace

Mesh makePlane(const PlaneParams& p) {
  MeshBuilder builder("plane");
  int n = p.subdivisions;
  builder.reserve(size_t(n + 1) * size_t(n + 1), size_t(n) * size_t(n) * 2);
  addGrid(builder, n, n, false, false, [&](int i, int j) {
    glm::vec3 offset((float(i) / float(n) - 0.5f) * p.size.x, 0.0f, (float(j) / float(n) - 0.5f) * p.size.y);
    return Vertex{p.center + offset, glm::vec3(0, 1, 0)};
  });
  return builder.take();
}

Mesh makeBox(const BoxParams& p) {
  MeshBuilder builder("box");
  addOrientedBox(builder, p.center, eulerRotation(p.rotateDeg), 0.5f * p.size);
  return builder.take();
}

Mesh makeSphere(const SphereParams& p) {
  MeshBuilder builder("sphere");
  const int segments = p.segments, rings = p.rings;
  builder.reserve(size_t(segments) * size_t(rings - 1) + 2, size_t(segments) * size_t(rings - 1) * 2);
  auto onSphere = [&](float theta, float phi) {
    glm::vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
    return Vertex{p.center + p.radius * n, n};
  };
  // Latitude rings 1 .. rings-1 (the poles are single vertices joined by triangle fans).
  const uint32_t firstRing = builder.vertexCount();
  addGrid(builder, segments, rings - 2, true, false, [&](int i, int j) {
    return onSphere(kPi * float(j + 1) / float(rings), 2.0f * kPi * float(i) / float(segments));
  });
  const uint32_t lastRing = firstRing + uint32_t(segments * (rings - 2));
  const uint32_t north = builder.vertex(p.center + glm::vec3(0, p.radius, 0), glm::vec3(0, 1, 0));
  const uint32_t south = builder.vertex(p.center - glm::vec3(0, p.radius, 0), glm::vec3(0, -1, 0));
  for (int i = 0; i < segments; ++i) {
    uint32_t next = uint32_t((i + 1) % segments);
    builder.triangle(north, firstRing + uint32_t(i), firstRing + next);
    builder.triangle(south, lastRing + uint32_t(i), lastRing + next);
  }
  return builder.take();
}

Mesh makeTorus(const TorusParams& p) {
  MeshBuilder builder("torus");
  builder.reserve(size_t(p.majorSegments) * size_t(p.minorSegments),
                  size_t(p.majorSegments) * size_t(p.minorSegments) * 2);
  glm::mat3 rotation = eulerRotation(p.rotateDeg);
  addGrid(builder, p.majorSegments, p.minorSegments, true, true, [&](int i, int j) {
    float u = 2.0f * kPi * float(i) / float(p.majorSegments), v = 2.0f * kPi * float(j) / float(p.minorSegments);
    glm::vec3 radial(std::cos(u), 0.0f, std::sin(u));
    glm::vec3 normal = std::cos(v) * radial + std::sin(v) * glm::vec3(0, 1, 0);
    glm::vec3 position = p.majorRadius * radial + p.minorRadius * normal;
    return Vertex{p.center + rotation * position, rotation * normal};
  });
  return builder.take();
}

Mesh makeTorusKnot(const TorusKnotParams& p) {
  MeshBuilder builder("torus_knot");
  builder.reserve(size_t(p.segments) * size_t(p.tubeSegments), size_t(p.segments) * size_t(p.tubeSegments) * 2);
  glm::mat3 rotation = eulerRotation(p.rotateDeg);
  const float scale = p.radius / 3.0f;  // the centre line reaches 3 units from the axis before scaling
  const float fp = float(p.p), fq = float(p.q);
  addGrid(builder, p.segments, p.tubeSegments, true, true, [&](int i, int j) {
    float t = 2.0f * kPi * float(i) / float(p.segments);
    float r = 2.0f + std::cos(fq * t), dr = -fq * std::sin(fq * t);
    glm::vec3 centre = scale * glm::vec3(r * std::cos(fp * t), -std::sin(fq * t), r * std::sin(fp * t));
    glm::vec3 tangent = glm::normalize(glm::vec3(dr * std::cos(fp * t) - r * fp * std::sin(fp * t),
                                                 -fq * std::cos(fq * t),
                                                 dr * std::sin(fp * t) + r * fp * std::cos(fp * t)));
    // A frame that depends only on t (so the tube closes without a seam): the centre line never
    // points along its tangent because the tangent always has an azimuthal component.
    glm::vec3 binormal = glm::normalize(glm::cross(tangent, centre));
    glm::vec3 normalDir = glm::cross(binormal, tangent);
    float v = 2.0f * kPi * float(j) / float(p.tubeSegments);
    glm::vec3 normal = std::cos(v) * normalDir + std::sin(v) * binormal;
    return Vertex{p.center + rotation * (centre + p.tubeRadius * normal), rotation * normal};
  });
  return builder.take();
}

Mesh makeRoom(const RoomParams& p) {
  MeshBuilder builder("room");
  const float hw = 0.5f * p.size.x, hh = p.size.y, hd = 0.5f * p.size.z;
  auto addRect = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, glm::vec3 inward) {
    builder.quad(builder.vertex(p.center + a, inward), builder.vertex(p.center + b, inward),
                 builder.vertex(p.center + c, inward), builder.vertex(p.center + d, inward));
  };
  addRect({-hw, 0, -hd}, {hw, 0, -hd}, {hw, 0, hd}, {-hw, 0, hd}, {0, 1, 0});      // floor
  addRect({-hw, hh, -hd}, {hw, hh, -hd}, {hw, hh, hd}, {-hw, hh, hd}, {0, -1, 0});  // ceiling
  for (Wall wall : {Wall::PosX, Wall::NegX, Wall::PosZ, Wall::NegZ}) {
    // (u, v) = (position along the wall, height); u runs along Z for X walls and along X for Z walls.
    bool alongZ = wall == Wall::PosX || wall == Wall::NegX;
    float halfWidth = alongZ ? hd : hw;
    auto at = [&](float u, float v) {
      switch (wall) {
        case Wall::PosX: return glm::vec3(hw, v, u);
        case Wall::NegX: return glm::vec3(-hw, v, u);
        case Wall::PosZ: return glm::vec3(u, v, hd);
        default: return glm::vec3(u, v, -hd);
      }
    };
    glm::vec3 inward = wall == Wall::PosX ? glm::vec3(-1, 0, 0)
                       : wall == Wall::NegX ? glm::vec3(1, 0, 0)
                       : wall == Wall::PosZ ? glm::vec3(0, 0, -1)
                                            : glm::vec3(0, 0, 1);
    auto wallRect = [&](float u0, float u1, float v0, float v1) {
      addRect(at(u0, v0), at(u1, v0), at(u1, v1), at(u0, v1), inward);
    };
    if (!p.hasWindow || wall != p.windowWall) {
      wallRect(-halfWidth, halfWidth, 0.0f, hh);
      continue;
    }
    float u0 = p.windowCenter.x - 0.5f * p.windowSize.x, u1 = p.windowCenter.x + 0.5f * p.windowSize.x;
    float v0 = p.windowCenter.y - 0.5f * p.windowSize.y, v1 = p.windowCenter.y + 0.5f * p.windowSize.y;
    wallRect(-halfWidth, u0, 0.0f, hh);  // left of the window, full height
    wallRect(u1, halfWidth, 0.0f, hh);   // right of the window, full height
    wallRect(u0, u1, 0.0f, v0);          // below
    wallRect(u0, u1, v1, hh);            // above
  }
  return builder.take();
}

Mesh makeChainlinkFence(const FenceParams& p) {
  MeshBuilder builder("chainlink_fence");
  const float hw = 0.5f * p.width, h = p.height, step = p.mesh;
  const glm::vec3 facing(0, 0, 1);
  // Two families of 45-degree wires, x - y = c and x + y = c, offset in Z so that they touch
  // instead of intersecting; each is clipped to the rectangle [-hw, hw] x [0, h].
  auto addWire = [&](float x0, float y0, float x1, float y1, float z) {
    if (std::hypot(x1 - x0, y1 - y0) <= p.wireRadius) return;  // corner stubs
    addBeam(builder, {x0, y0, z}, {x1, y1, z}, facing, p.wireRadius);
  };
  for (int k = int(std::ceil((-hw - h) / step)); float(k) * step < hw; ++k) {
    float c = float(k) * step;
    if (c <= -hw - h) continue;
    float x0 = std::max(-hw, c), x1 = std::min(hw, c + h);
    addWire(x0, x0 - c, x1, x1 - c, p.wireRadius);
  }
  for (int k = int(std::ceil(-hw / step)); float(k) * step < hw + h; ++k) {
    float c = float(k) * step;
    if (c <= -hw) continue;
    float x0 = std::max(-hw, c - h), x1 = std::min(hw, c);
    addWire(x0, c - x0, x1, c - x1, -p.wireRadius);
  }
  if (p.frame) {
    float r = p.frameRadius, top = h + r;
    for (float x : {-hw, hw}) addOrientedBox(builder, {x, 0.5f * top, 0}, glm::mat3(1.0f), {r, 0.5f * top, r});
    addOrientedBox(builder, {0, h, 0}, glm::mat3(1.0f), {hw, r, r});
  }
  Mesh mesh = builder.take();
  glm::mat4 placement(eulerRotation({0.0f, p.rotateYDeg, 0.0f}));
  placement[3] = glm::vec4(p.center, 1.0f);
  transformMesh(mesh, placement);
  return mesh;
}

Mesh makeTree(const TreeParams& p) {
  MeshBuilder builder("tree");
  uint64_t segments = treeSegmentCount(p.branches, p.depth);
  builder.reserve(size_t(segments) * size_t(p.sides) * 2, size_t(segments) * size_t(p.sides) * 2);
  Random random(p.seed);
  const glm::vec3 up(0, 1, 0);
  const float tropism = 0.15f;  // gentle pull upwards so that deep branches do not droop below the crown
  std::function<void(glm::vec3, glm::vec3, float, float, int)> grow = [&](glm::vec3 start, glm::vec3 direction,
                                                                           float length, float radius, int level) {
    glm::vec3 end = start + direction * length;
    float tipRadius = radius * p.radiusRatio;
    addTaperedPrism(builder, start, end, radius, tipRadius, p.sides);
    if (level + 1 >= p.depth) return;
    glm::vec3 u, w;
    perpendicularBasis(direction, u, w);
    float firstAzimuth = 2.0f * kPi * random.uniform();
    for (int k = 0; k < p.branches; ++k) {
      float azimuth = firstAzimuth + 2.0f * kPi * (float(k) + 0.25f * p.jitter * random.symmetric()) / float(p.branches);
      float angle = glm::radians(p.branchAngleDeg) * (1.0f + 0.5f * p.jitter * random.symmetric());
      glm::vec3 side = std::cos(azimuth) * u + std::sin(azimuth) * w;
      glm::vec3 child = glm::normalize(std::cos(angle) * direction + std::sin(angle) * side + tropism * up);
      float childLength = length * p.lengthRatio * (1.0f + 0.3f * p.jitter * random.symmetric());
      grow(end, child, childLength, tipRadius, level + 1);
    }
  };
  float lean = glm::radians(5.0f) * p.jitter * random.uniform(), leanAzimuth = 2.0f * kPi * random.uniform();
  glm::vec3 trunk(std::sin(lean) * std::cos(leanAzimuth), std::cos(lean), std::sin(lean) * std::sin(leanAzimuth));
  grow(p.base, trunk, p.height, p.trunkRadius, 0);
  return builder.take();
}

// The trees placed so far, by cells of side min_spacing: a new spot is compared with the trees of
// the cells around it only, so that placing n trees costs n, not n^2 (100,000 trees took
// seconds). The cells two away are looked at too, so that no rounding of a coordinate to its cell
// can hide a neighbour closer than min_spacing: the answer is exactly that of comparing with
// every tree.
class PlacedTrees {
 public:
  explicit PlacedTrees(float minSpacing) : spacing_(minSpacing) {}
  bool farFromAll(const glm::vec2& spot) const {
    if (!(spacing_ > 0.0f)) return true;  // every distance is >= 0
    const int64_t cx = cell(spot.x), cy = cell(spot.y);
    for (int64_t dy = -2; dy <= 2; ++dy)
      for (int64_t dx = -2; dx <= 2; ++dx) {
        auto found = cells_.find(key(cx + dx, cy + dy));
        if (found == cells_.end()) continue;
        for (const glm::vec2& other : found->second)
          if (!(glm::distance(spot, other) >= spacing_)) return false;
      }
    return true;
  }
  void add(const glm::vec2& spot) {
    if (spacing_ > 0.0f) cells_[key(cell(spot.x), cell(spot.y))].push_back(spot);
  }

 private:
  int64_t cell(float x) const {
    return int64_t(std::clamp(std::floor(double(x) / double(spacing_)), -4e18, 4e18));  // within int64
  }
  static uint64_t key(int64_t x, int64_t y) { return uint64_t(x) * 0x9E3779B97F4A7C15ull ^ uint64_t(y); }
  float spacing_;
  std::unordered_map<uint64_t, std::vector<glm::vec2>> cells_;
};

Mesh makeForest(const ForestParams& p) {
  Random random(p.seed);
  PlacedTrees placed(p.minSpacing);
  Mesh forest;
  forest.name = "forest";
  for (int t = 0; t < p.count; ++t) {
    glm::vec2 spot;
    bool found = false;
    for (int attempt = 0; attempt < 1000 && !found; ++attempt) {
      spot = glm::vec2(p.center.x, p.center.z) + (glm::vec2(random.uniform(), random.uniform()) - 0.5f) * p.size;
      found = placed.farFromAll(spot);
    }
    if (!found)
      throw std::runtime_error("could not place tree " + std::to_string(t + 1) + " of " + std::to_string(p.count) +
                               " with min_spacing " + formatNumber(p.minSpacing) + "; enlarge size or lower count");
    placed.add(spot);
    TreeParams tree = p.tree;
    float scale = 1.0f + p.scaleJitter * random.symmetric();
    tree.base = glm::vec3(spot.x, p.center.y, spot.y);
    tree.height *= scale;
    tree.trunkRadius *= scale;
    tree.seed = deriveSeed(p.seed, uint64_t(t));
    appendMesh(forest, makeTree(tree));
  }
  return forest;
}

Mesh makeTerrain(const TerrainParams& p) {
  MeshBuilder builder("terrain");
  const int n = p.resolution;
  const size_t side = size_t(n) + 1;
  std::vector<float> heights(side * side);
  auto localX = [&](int i) { return (double(i) / n - 0.5) * p.size.x; };
  auto localZ = [&](int j) { return (double(j) / n - 0.5) * p.size.y; };
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      double frequency = 1.0 / p.featureSize, amplitude = 1.0, sum = 0.0, norm = 0.0;
      for (int o = 0; o < p.octaves; ++o) {
        sum += amplitude * valueNoise(localX(i) * frequency, localZ(j) * frequency, uint32_t(o), p.seed);
        norm += amplitude;
        amplitude *= p.persistence;
        frequency *= p.lacunarity;
      }
      heights[size_t(j) * side + size_t(i)] = float(p.height * sum / norm);
    }
  }
  auto heightAt = [&](int i, int j) { return heights[size_t(j) * side + size_t(i)]; };
  builder.reserve(side * side, size_t(n) * size_t(n) * 2);
  addGrid(builder, n, n, false, false, [&](int i, int j) {
    // Central differences (one-sided at the border) of the sampled heights.
    int i0 = std::max(i - 1, 0), i1 = std::min(i + 1, n), j0 = std::max(j - 1, 0), j1 = std::min(j + 1, n);
    float slopeX = (heightAt(i1, j) - heightAt(i0, j)) / float(localX(i1) - localX(i0));
    float slopeZ = (heightAt(i, j1) - heightAt(i, j0)) / float(localZ(j1) - localZ(j0));
    glm::vec3 position = p.center + glm::vec3(float(localX(i)), heightAt(i, j), float(localZ(j)));
    return Vertex{position, glm::normalize(glm::vec3(-slopeX, 1.0f, -slopeZ))};
  });
  return builder.take();
}

Mesh makeLeafCards(const LeafCardsParams& p) {
  MeshBuilder builder("leaf_cards");
  builder.reserve(size_t(p.count) * 4, size_t(p.count) * 2);
  Random random(p.seed);
  for (int i = 0; i < p.count; ++i) {
    // A point inside the unit ball by rejection, scaled to the crown.
    glm::vec3 q;
    do {
      q = glm::vec3(random.symmetric(), random.symmetric(), random.symmetric());
    } while (glm::dot(q, q) > 1.0f);
    glm::vec3 c = p.center + q * p.radius;
    glm::vec3 n;
    do {
      n = glm::vec3(random.symmetric(), random.symmetric(), random.symmetric());
    } while (glm::dot(n, n) > 1.0f || glm::dot(n, n) < 1e-4f);
    n = glm::normalize(n);
    glm::vec3 t = glm::normalize(glm::cross(n, std::fabs(n.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0)));
    glm::vec3 b = glm::cross(n, t);
    float h = 0.5f * p.size;
    uint32_t a = builder.vertex(c - h * t - h * b, n, {0, 1}), bb = builder.vertex(c + h * t - h * b, n, {1, 1});
    uint32_t cc = builder.vertex(c + h * t + h * b, n, {1, 0}), d = builder.vertex(c - h * t + h * b, n, {0, 0});
    builder.quad(a, bb, cc, d);
  }
  return builder.take();
}

AlphaTexture makeLeafAlphaTexture(int size) {
  AlphaTexture t;
  t.width = t.height = std::max(size, 4);
  t.alpha.resize(size_t(t.width) * size_t(t.height));
  const float texel = 2.0f / float(t.width);  // in the blade's [-1, 1] coordinates
  for (int j = 0; j < t.height; ++j)
    for (int i = 0; i < t.width; ++i) {
      // Along the blade y (tip at +1, stalk at -1), across it x.
      float x = (float(i) + 0.5f) * texel - 1.0f, y = 1.0f - (float(j) + 0.5f) * texel;
      float halfWidth = 0.6f * std::pow(std::max(1.0f - y * y, 0.0f), 0.75f) * (1.0f - 0.25f * y);
      float inside = std::clamp((halfWidth - std::fabs(x)) / (2.0f * texel), 0.0f, 1.0f);
      // The midrib and three pairs of side veins running to the rim, thinner than the blade.
      float vein = std::fabs(x) < 0.6f * texel ? 1.0f : 0.0f;
      for (float start : {-0.5f, 0.0f, 0.5f}) {
        float along = y - start - 0.8f * std::fabs(x);
        vein = std::max(vein, std::fabs(along) < 0.7f * texel && std::fabs(x) < 0.8f * halfWidth ? 1.0f : 0.0f);
      }
      t.alpha[size_t(j) * size_t(t.width) + size_t(i)] = inside * (vein > 0.0f ? 0.3f : 0.6f);
    }
  return t;
}

Mesh makeLayers(const LayersParams& p) {
  MeshBuilder builder("layers");
  builder.reserve(size_t(p.count) * 4, size_t(p.count) * 2);
  float h = 0.5f * p.size;
  for (int i = 0; i < p.count; ++i) {
    glm::vec3 c = p.center + glm::vec3(0.0f, float(i) * p.spacing, 0.0f), n(0, 1, 0);
    uint32_t a = builder.vertex(c + glm::vec3(-h, 0, -h), n), b = builder.vertex(c + glm::vec3(-h, 0, h), n);
    uint32_t cc = builder.vertex(c + glm::vec3(h, 0, h), n), d = builder.vertex(c + glm::vec3(h, 0, -h), n);
    builder.quad(a, b, cc, d);
  }
  return builder.take();
}

Mesh makeTriangle(const TriangleParams& p) {
  Mesh mesh;
  mesh.name = "triangle";
  glm::vec3 face = glm::normalize(glm::cross(p.vertices[1] - p.vertices[0], p.vertices[2] - p.vertices[0]));
  for (int k = 0; k < 3; ++k) {
    mesh.positions.push_back(p.vertices[k]);
    mesh.normals.push_back(p.hasNormals ? p.normals[k] : face);
  }
  mesh.indices = {0, 1, 2};
  return mesh;
}

// ---------------------------------------------------------------------------------------------
// JSON parameters

namespace {
uint64_t g_triangleLimit = kMaxGeneratedTriangles;
}  // namespace

uint64_t generatedTriangleLimit() { return g_triangleLimit; }
void setGeneratedTriangleLimit(uint64_t limit) { g_triangleLimit = std::min(limit, kMaxGeneratedTriangles); }

namespace {

constexpr int64_t kMaxSeed = 4294967295;
const Range kAny = Range::any();
const Range kPositive = Range::above(0.0);

void checkBudget(const ObjectReader& params, uint64_t triangles) {
  if (triangles > g_triangleLimit)
    params.location().fail("these parameters would produce " + std::to_string(triangles) +
                           " triangles, more than the limit of " + std::to_string(g_triangleLimit));
}

int readInt(ObjectReader& params, const std::string& key, int fallback, int lo, int hi) {
  return int(params.integer(key, fallback, lo, hi));
}

float readFloat(ObjectReader& params, const std::string& key, float fallback, Range range) {
  return float(params.number(key, fallback, range));
}

Mesh planeFromJson(ObjectReader& params) {
  PlaneParams p;
  p.center = params.vec3("center", p.center, kAny);
  p.size = params.vec2("size", p.size, kPositive);
  p.subdivisions = readInt(params, "subdivisions", p.subdivisions, 1, 4096);
  params.finish();
  return makePlane(p);
}

Mesh boxFromJson(ObjectReader& params) {
  BoxParams p;
  p.center = params.vec3("center", p.center, kAny);
  p.size = params.vec3("size", p.size, kPositive);
  p.rotateDeg = params.vec3("rotate_deg", p.rotateDeg, kAny);
  params.finish();
  return makeBox(p);
}

Mesh sphereFromJson(ObjectReader& params) {
  SphereParams p;
  p.center = params.vec3("center", p.center, kAny);
  p.radius = readFloat(params, "radius", p.radius, kPositive);
  p.segments = readInt(params, "segments", p.segments, 3, 8192);
  p.rings = readInt(params, "rings", std::max(2, p.segments / 2), 2, 8192);
  params.finish();
  checkBudget(params, 2ull * uint64_t(p.segments) * uint64_t(p.rings - 1));
  return makeSphere(p);
}

Mesh torusFromJson(ObjectReader& params) {
  TorusParams p;
  p.center = params.vec3("center", p.center, kAny);
  p.majorRadius = readFloat(params, "major_radius", p.majorRadius, kPositive);
  p.minorRadius = readFloat(params, "minor_radius", p.minorRadius, Range::open(0.0, p.majorRadius));
  p.majorSegments = readInt(params, "major_segments", p.majorSegments, 3, 65536);
  p.minorSegments = readInt(params, "minor_segments", p.minorSegments, 3, 65536);
  p.rotateDeg = params.vec3("rotate_deg", p.rotateDeg, kAny);
  params.finish();
  checkBudget(params, 2ull * uint64_t(p.majorSegments) * uint64_t(p.minorSegments));
  return makeTorus(p);
}

Mesh torusKnotFromJson(ObjectReader& params) {
  TorusKnotParams p;
  p.center = params.vec3("center", p.center, kAny);
  p.radius = readFloat(params, "radius", p.radius, kPositive);
  p.tubeRadius = readFloat(params, "tube_radius", p.radius / 10.0f, Range::openClosed(0.0, p.radius / 3.0));
  p.p = readInt(params, "p", p.p, 1, 64);
  p.q = readInt(params, "q", p.q, 1, 64);
  p.segments = readInt(params, "segments", p.segments, 8, 1 << 20);
  p.tubeSegments = readInt(params, "tube_segments", p.tubeSegments, 3, 1024);
  p.rotateDeg = params.vec3("rotate_deg", p.rotateDeg, kAny);
  params.finish();
  checkBudget(params, 2ull * uint64_t(p.segments) * uint64_t(p.tubeSegments));
  return makeTorusKnot(p);
}

Mesh roomFromJson(ObjectReader& params) {
  RoomParams p;
  p.center = params.vec3("center", p.center, kAny);
  p.size = params.vec3("size", p.size, kPositive);
  if (const Json* windowJson = params.optional("window")) {
    ObjectReader window(*windowJson, params.locationOf("window"));
    std::string wall = window.choice("wall", {"+x", "-x", "+z", "-z"}, "-z");
    p.windowWall = wall == "+x" ? Wall::PosX : wall == "-x" ? Wall::NegX : wall == "+z" ? Wall::PosZ : Wall::NegZ;
    float wallWidth = (p.windowWall == Wall::PosX || p.windowWall == Wall::NegX) ? p.size.z : p.size.x;
    p.windowSize = window.vec2("size", p.windowSize, kPositive);
    p.windowCenter = window.vec2("center", glm::vec2(0.0f, 0.5f * p.size.y), kAny);
    window.finish();
    // The opening must leave wall on every side.
    glm::vec2 lo = p.windowCenter - 0.5f * p.windowSize, hi = p.windowCenter + 0.5f * p.windowSize;
    if (!(lo.x > -0.5f * wallWidth && hi.x < 0.5f * wallWidth && lo.y > 0.0f && hi.y < p.size.y))
      window.location().fail("the window must lie strictly inside its wall (wall width " + formatNumber(wallWidth) +
                             ", height " + formatNumber(p.size.y) + ")");
    p.hasWindow = true;
  }
  params.finish();
  return makeRoom(p);
}

Mesh fenceFromJson(ObjectReader& params) {
  FenceParams p;
  p.center = params.vec3("center", p.center, kAny);
  p.width = readFloat(params, "width", p.width, kPositive);
  p.height = readFloat(params, "height", p.height, kPositive);
  p.mesh = readFloat(params, "mesh", p.mesh, kPositive);
  p.wireRadius = readFloat(params, "wire_radius", p.mesh / 20.0f, Range::open(0.0, p.mesh / 4.0));
  p.frame = params.boolean("frame", p.frame);
  p.frameRadius = readFloat(params, "frame_radius", 3.0f * p.wireRadius, kPositive);
  p.rotateYDeg = readFloat(params, "rotate_y_deg", p.rotateYDeg, kAny);
  params.finish();
  double wires = 2.0 * (double(p.width) + double(p.height)) / double(p.mesh) + 4.0;
  checkBudget(params, uint64_t(std::min(wires * 12.0 + 36.0, 1e18)));
  return makeChainlinkFence(p);
}

// Shape parameters shared by `tree` and `forest` (everything except base and seed).
void readTreeShape(ObjectReader& params, TreeParams& p) {
  p.height = readFloat(params, "height", p.height, kPositive);
  p.trunkRadius = readFloat(params, "trunk_radius", p.trunkRadius, kPositive);
  p.depth = readInt(params, "depth", p.depth, 1, 16);
  p.branches = readInt(params, "branches", p.branches, 1, 8);
  p.branchAngleDeg = readFloat(params, "branch_angle_deg", p.branchAngleDeg, Range::closed(0.0, 90.0));
  p.lengthRatio = readFloat(params, "length_ratio", p.lengthRatio, Range::openClosed(0.0, 1.0));
  p.radiusRatio = readFloat(params, "radius_ratio", p.radiusRatio, Range::openClosed(0.0, 1.0));
  p.jitter = readFloat(params, "jitter", p.jitter, Range::closed(0.0, 1.0));
  p.sides = readInt(params, "sides", p.sides, 3, 32);
}

uint64_t treeTriangles(const TreeParams& p) {
  return std::min<uint64_t>(treeSegmentCount(p.branches, p.depth), kMaxGeneratedTriangles) * uint64_t(p.sides) * 2;
}

Mesh treeFromJson(ObjectReader& params) {
  TreeParams p;
  p.base = params.vec3("base", p.base, kAny);
  readTreeShape(params, p);
  p.seed = uint32_t(params.integer("seed", p.seed, 0, kMaxSeed));
  params.finish();
  checkBudget(params, treeTriangles(p));
  return makeTree(p);
}

Mesh forestFromJson(ObjectReader& params) {
  ForestParams p;
  p.center = params.vec3("center", p.center, kAny);
  p.size = params.vec2("size", p.size, kPositive);
  p.count = readInt(params, "count", p.count, 1, 100000);
  p.seed = uint32_t(params.integer("seed", p.seed, 0, kMaxSeed));
  p.minSpacing = readFloat(params, "min_spacing", p.minSpacing, Range::atLeast(0.0));
  p.scaleJitter = readFloat(params, "scale_jitter", p.scaleJitter, Range::closedOpen(0.0, 1.0));
  if (const Json* treeJson = params.optional("tree")) {
    ObjectReader tree(*treeJson, params.locationOf("tree"));
    readTreeShape(tree, p.tree);
    tree.forbid("base", "not allowed here: forest places its trees itself");
    tree.forbid("seed", "not allowed here: each tree's seed is derived from the forest's seed");
    tree.finish();
  }
  params.finish();
  checkBudget(params, std::min<uint64_t>(treeTriangles(p.tree), kMaxGeneratedTriangles) * uint64_t(p.count));
  return makeForest(p);
}

Mesh terrainFromJson(ObjectReader& params) {
  TerrainParams p;
  p.center = params.vec3("center", p.center, kAny);
  p.size = params.vec2("size", p.size, kPositive);
  p.resolution = readInt(params, "resolution", p.resolution, 1, 4096);
  p.height = readFloat(params, "height", p.height, Range::atLeast(0.0));
  p.featureSize = readFloat(params, "feature_size", p.featureSize, kPositive);
  p.octaves = readInt(params, "octaves", p.octaves, 1, 16);
  p.persistence = readFloat(params, "persistence", p.persistence, Range::openClosed(0.0, 1.0));
  p.lacunarity = readFloat(params, "lacunarity", p.lacunarity, Range::closed(1.0, 8.0));
  p.seed = uint32_t(params.integer("seed", p.seed, 0, kMaxSeed));
  params.finish();
  checkBudget(params, 2ull * uint64_t(p.resolution) * uint64_t(p.resolution));
  return makeTerrain(p);
}

// A coordinate of the `triangle` generator: any number, or "nan" / "inf" / "-inf" (JSON has no
// literal for them) so that tests can feed non-finite vertices to the degenerate-triangle filter.
float readLenientCoordinate(const Json& value, const JsonLocation& at) {
  if (value.is_string()) {
    std::string text = value.get<std::string>();
    if (text == "nan") return std::numeric_limits<float>::quiet_NaN();
    if (text == "inf") return std::numeric_limits<float>::infinity();
    if (text == "-inf") return -std::numeric_limits<float>::infinity();
    at.fail("expected a number, \"nan\", \"inf\" or \"-inf\", got \"" + text + "\"");
  }
  return float(readNumber(value, at, kAny));
}

void readTriangleCorners(const Json& value, const JsonLocation& at, glm::vec3 (&corners)[3]) {
  if (!value.is_array() || value.size() != 3) at.fail("expected an array of 3 points [x, y, z]");
  for (size_t k = 0; k < 3; ++k) {
    JsonLocation cornerAt = at.item(k);
    if (!value[k].is_array() || value[k].size() != 3) cornerAt.fail("expected an array of 3 numbers");
    for (size_t c = 0; c < 3; ++c) corners[k][int(c)] = readLenientCoordinate(value[k][c], cornerAt.item(c));
  }
}

Mesh triangleFromJson(ObjectReader& params) {
  TriangleParams p;
  readTriangleCorners(params.required("vertices"), params.locationOf("vertices"), p.vertices);
  if (const Json* normals = params.optional("normals")) {
    readTriangleCorners(*normals, params.locationOf("normals"), p.normals);
    p.hasNormals = true;
  }
  params.finish();
  return makeTriangle(p);
}

Mesh leafCardsFromJson(ObjectReader& params) {
  LeafCardsParams p;
  p.center = params.vec3("center", p.center, kAny);
  p.radius = params.vec3("radius", p.radius, kPositive);
  p.count = readInt(params, "count", p.count, 1, 1000000);
  p.size = readFloat(params, "size", p.size, kPositive);
  p.seed = uint32_t(params.integer("seed", p.seed, 0, kMaxSeed));
  params.finish();
  return makeLeafCards(p);
}

Mesh layersFromJson(ObjectReader& params) {
  LayersParams p;
  p.center = params.vec3("center", p.center, kAny);
  p.size = readFloat(params, "size", p.size, kPositive);
  p.count = readInt(params, "count", p.count, 1, 100000);
  p.spacing = readFloat(params, "spacing", p.spacing, Range::atLeast(0.0));
  params.finish();
  return makeLayers(p);
}

struct GeneratorEntry {
  const char* name;
  Mesh (*build)(ObjectReader&);
};

const GeneratorEntry kGenerators[] = {
    {"plane", planeFromJson},       {"box", boxFromJson},
    {"sphere", sphereFromJson},     {"torus", torusFromJson},
    {"torus_knot", torusKnotFromJson}, {"room", roomFromJson},
    {"chainlink_fence", fenceFromJson}, {"tree", treeFromJson},
    {"forest", forestFromJson},     {"terrain", terrainFromJson},
    {"triangle", triangleFromJson}, {"leaf_cards", leafCardsFromJson},
    {"layers", layersFromJson},
};

}  // namespace

const std::vector<std::string>& generatorNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> list;
    for (const GeneratorEntry& entry : kGenerators) list.push_back(entry.name);
    return list;
  }();
  return names;
}

std::vector<Mesh> generateMeshes(const std::string& name, const nlohmann::json& params, const std::string& origin,
                                 const std::string& generatorPath, const std::string& paramsPath) {
  for (const GeneratorEntry& entry : kGenerators) {
    if (name != entry.name) continue;
    ObjectReader reader(params, JsonLocation{origin, paramsPath});
    try {
      std::vector<Mesh> meshes;
      meshes.push_back(entry.build(reader));
      return meshes;
    } catch (const SceneError&) {
      throw;
    } catch (const std::exception& e) {  // a generator's own failure (e.g. forest placement)
      throwSceneError(origin, paramsPath, e.what());
    }
  }
  std::string list;
  for (const std::string& known : generatorNames()) list += (list.empty() ? "" : ", ") + known;
  throwSceneError(origin, generatorPath,
                  "unknown generator '" + name + "'" + didYouMean(name, generatorNames()) + ", expected one of: " + list);
}

}  // namespace vs
