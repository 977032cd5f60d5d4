// The froxel grid: tiles of `tile` pixels, `slices` depth slices from the eye (distance along the
// ray) to the camera's far distance, exponential or linear. Slice k spans [boundary(k), boundary(k+1)].
layout(std140, binding = 3) uniform FroxelBlock {
  ivec4 grid;     // width, height, slices, tile (pixels)
  vec4 range;     // unused, exponential (1) or linear (0), samples per froxel, jitter offset
  mat4 previousViewProj;  // temporal reprojection: the previous frame's camera
  vec4 previousEye;       // xyz; w = weight of the reprojected history (0: none)
} fx;

// The grid reaches the far plane in the frustum's corners: the far distance over the cosine of the
// corner ray (read every frame: a moving camera may change its field of view).
float froxelFar() {
  float t = u.cameraForward.w, aspect = float(u.viewport.x) / float(max(u.viewport.y, 1));
  return u.cameraClip.y * sqrt(1.0 + t * t * (1.0 + aspect * aspect));
}

// Boundary ratio of the exponential distribution: the last slice is this many times deeper than the first.
const float kDepthRatio = 256.0;

// Fraction of the far distance at continuous boundary index x in [0, slices].
float froxelBoundaryFraction(float x) {
  float f = clamp(x / float(fx.grid.z), 0.0, 1.0);
  return fx.range.y > 0.5 ? (pow(kDepthRatio, f) - 1.0) / (kDepthRatio - 1.0) : f;
}
float froxelBoundary(float x) { return froxelFar() * froxelBoundaryFraction(x); }
// Continuous boundary index of distance t (the inverse of froxelBoundary).
float froxelIndexOf(float t) {
  float w = clamp(t / max(froxelFar(), 1e-30), 0.0, 1.0);
  float f = fx.range.y > 0.5 ? log(1.0 + (kDepthRatio - 1.0) * w) / log(kDepthRatio) : w;
  return f * float(fx.grid.z);
}

// Unit direction of the camera ray through pixel coordinates `p` (gl_FragCoord convention; may lie
// outside the image for the last, partial tiles).
vec3 froxelRayDir(vec2 p) {
  vec2 ndc = p / vec2(u.viewport.xy) * 2.0 - 1.0;
  vec4 a = u.invViewProj * vec4(ndc, -1.0, 1.0);
  vec4 b = u.invViewProj * vec4(ndc, 1.0, 1.0);
  vec3 d = b.xyz / b.w - a.xyz / a.w;
  float len = length(d);
  return len > 1e-20 ? d / len : u.cameraForward.xyz;
}
