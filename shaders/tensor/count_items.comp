#version 450
// Index check (tests/runtime/flat_index_test.cpp): every invocation counts the items it strides over,
//   for item = flat_index(); item < n; item += flat_invocations():  counts[item] += 1
// and invocation 0 stores flat_invocations() in counts[n]; a correct flat dispatch leaves every count at 1.
#extension GL_GOOGLE_include_directive : require
#include "index.glsl"

layout(std430, binding = 0) buffer Counts { uint counts[]; };
layout(push_constant) uniform Push { uint n; };

void main() {
  for (uint item = flat_index(); item < n; item += flat_invocations()) atomicAdd(counts[item], 1u);
  if (flat_index() == 0u) counts[n] = flat_invocations();
}
