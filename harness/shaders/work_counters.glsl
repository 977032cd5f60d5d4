// Per-pixel work counters (harness/gl/work_counters.hpp): built with VS_WORK_COUNTERS 1 the
// instrumented variant of a pass adds to layer `counter` of its pixel; otherwise countWork()
// compiles to nothing. Layer 0 is the pixel's visited flag (add 1 once).
#if defined(VS_WORK_COUNTERS) && VS_WORK_COUNTERS != 0
layout(binding = VS_IMAGE_WORK_COUNTERS, r32ui) uniform coherent uimage2DArray workCounters;
void countWork(ivec2 pixel, int counter, uint n) { imageAtomicAdd(workCounters, ivec3(pixel, counter), n); }
#else
void countWork(ivec2 pixel, int counter, uint n) {}
#endif
