// Mesh clean-up and transforms shared by the procedural generators and the glTF loader.
#pragma once
#include <glm/glm.hpp>
#include <cstddef>
#include "scenes/scene.hpp"

namespace vs {

// Removes triangles with an out-of-range index, a non-finite vertex or (numerically) zero area
// (|e1 x e2| <= 1e-6 * longest edge^2), then drops vertices no triangle uses. Normals are kept
// in step with positions when both arrays have the same size. Returns the number of triangles removed.
size_t removeDegenerateTriangles(Mesh& mesh);

// Area-weighted smooth vertex normals from the triangles (flat for unshared vertices).
void computeSmoothNormals(Mesh& mesh);

// Makes every normal unit length: computes smooth normals when the normal array does not match
// the positions, and replaces zero/non-finite normals by the normal of the faces that use the vertex.
void repairNormals(Mesh& mesh);

// removeDegenerateTriangles + repairNormals; returns the number of triangles removed.
size_t sanitizeMesh(Mesh& mesh);

// Applies an affine transform: positions by m, normals by its inverse transpose (renormalised).
// A mirroring transform (negative determinant) also reverses the winding to keep it consistent.
void transformMesh(Mesh& mesh, const glm::mat4& m);

}  // namespace vs
