#version 450 core
// One φ bit into the layer that holds it; the framebuffer ORs it in (glLogicOp(GL_OR)).
#include "common.glsl"
#include "epipolar.glsl"
flat in int vBin;
layout(location = 0) out uvec4 outBits[VSV_LAYERS];
void main() {
  for (int layer = 0; layer < VSV_LAYERS; ++layer) outBits[layer] = layerMask(vBin, vBin, layer);
}
