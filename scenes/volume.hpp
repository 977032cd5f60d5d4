// Volume data: density grids from raw files and procedural stand-ins for the four data sets of
// Shook's deep-shadow-map paper (format: scenes/README.md, "volumes").
#pragma once
#include <string>

#include "scenes/content_hash.hpp"
#include "scenes/json_reader.hpp"
#include "scenes/scene.hpp"

namespace vs {

// Largest voxel count per axis a scene may ask for (GL 4.5 guarantees 3D textures of 2048; the
// harness checks the driver's real GL_MAX_3D_TEXTURE_SIZE before it writes anything).
constexpr int kMaxVolumeDim = 2048;
// Largest voxel count of one volume (2^28 floats = 1 GiB).
constexpr size_t kMaxVolumeVoxels = size_t(1) << 28;

// Reads a volume entry of a scene file (raw file or generator, box, coefficients) into `volume`.
Volume readVolume(ObjectReader entry, const std::string& baseDir, ContentHasher& hasher);

// Procedural density grids (values in [0, 1]); `scale` multiplies the default resolution.
//  density_box: 64^3, density rising linearly from 0 at the faces to 1 at the centre;
//  bucky:       32^3, 60 small spheres on a shell (a buckyball's atoms);
//  rods:        64^3, three families of crossed rods along x, y and z;
//  cloud:       512 x 32 x 512 (x, y up, z), a layer of fractal-noise clouds.
void generateVolume(Volume& volume, const std::string& generator, float scale, uint32_t seed);
const std::vector<std::string>& volumeGeneratorNames();

}  // namespace vs
