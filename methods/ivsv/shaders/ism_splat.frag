#version 450 core
in float vDistance;
layout(location = 0) out float outDistance;  // 0 marks a hole (pull-push fills it)
void main() { outDistance = max(vDistance, 1e-7); }
