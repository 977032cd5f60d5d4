#version 450 core
// "Voxelize: Geometry": world positions pass through; the geometry shader goes to epipolar space.
layout(location = 0) in vec3 position;
out vec3 vWorld;
void main() {
  vWorld = position;
  gl_Position = vec4(0.0, 0.0, 0.0, 1.0);
}
