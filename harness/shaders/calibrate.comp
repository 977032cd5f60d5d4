#version 450 core
// Timer calibration: the same ALU work as calibrate.frag, as a compute dispatch.
layout(local_size_x = 8, local_size_y = 8) in;
layout(location = 0) uniform int iterations;
layout(std430, binding = 0) buffer Sink { float values[]; };
void main() {
  vec2 p = vec2(gl_GlobalInvocationID.xy) * 0.001;
  float a = p.x, b = p.y;
  for (int i = 0; i < iterations; ++i) {
    a = fract(a * 1.0001 + b * 0.37);
    b = fract(b * 0.9999 + a * 0.61);
  }
  values[gl_GlobalInvocationID.y * 256u + gl_GlobalInvocationID.x] = a + b;
}
