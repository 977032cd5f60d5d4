// Layout of the 1D min-max tree of one rectified row of d texels (d a power of two, >= 16): one row
// of 3d/4 RGBA32F texels per slice, so that a store or a fetch carries two nodes or four leaves.
// Inner node k (1 <= k < d; root 1, children 2k and 2k+1) is (min, max) in texel k/2: xy for even k,
// zw for odd (texel 0 holds the root in zw). Leaf j (node d + j, the rectified texel j: min = max)
// is component j % 4 of texel d/2 + j/4. Mirrored by vs::minmax::gpuTreeFloat (traversal.hpp).
int innerTexel(uint node) { return int(node >> 1); }
int leafTexel(int d, uint leaf) { return (d >> 1) + int(leaf >> 2); }
