#version 450 core
// Timer calibration: a fixed amount of ALU work per fragment.
layout(location = 0) uniform int iterations;
layout(location = 0) out vec4 color;
void main() {
  vec2 p = gl_FragCoord.xy * 0.001;
  float a = p.x, b = p.y;
  for (int i = 0; i < iterations; ++i) {
    a = fract(a * 1.0001 + b * 0.37);
    b = fract(b * 0.9999 + a * 0.61);
  }
  color = vec4(a, b, 0.0, 1.0);
}
