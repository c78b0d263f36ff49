#version 450
// First pass of the global gradient norm: partial[offset + g] = sum of grad[i]^2 over the items
// workgroup g visits (grid-stride over vec4 texels of one large gradient, or of the small ones gathered end
// to end, nets/optim/flat_layout.h; four texels per iteration into a vec4 accumulator while whole texels
// remain, about 1.5x faster on lavapipe than one; then a tree in shared memory).
// Each pass gets its own range of partials; nn/clip_factor adds them all.
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer grad4;
layout(std430, binding = 1) writeonly buffer Partials { float partial[]; };
layout(push_constant) uniform Push { uint n; uint offset; };

shared float tree[gl_WorkGroupSize.x];

void main() {
  const uint local = gl_LocalInvocationID.x;
  const uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  const uint texels = (n + 3u) / 4u;
  vec4 acc = vec4(0.0);
  const uint full = n / 4u;
  uint t = gl_GlobalInvocationID.x;
  for (; t + 3u * stride < full; t += 4u * stride) {
    const vec4 a = texelFetch(grad4, int(t));
    const vec4 b = texelFetch(grad4, int(t + stride));
    const vec4 c = texelFetch(grad4, int(t + 2u * stride));
    const vec4 d = texelFetch(grad4, int(t + 3u * stride));
    acc += a * a + b * b + c * c + d * d;
  }
  for (; t < texels; t += stride) {
    vec4 g = texelFetch(grad4, int(t));
    const uint base = 4u * t;
    if (base + 3u >= n) g = mix(vec4(0.0), g, lessThan(uvec4(base) + uvec4(0u, 1u, 2u, 3u), uvec4(n)));
    acc += g * g;
  }
  const float sum = acc.x + acc.y + acc.z + acc.w;
  tree[local] = sum;
  barrier();
  for (uint half_ = gl_WorkGroupSize.x / 2u; half_ > 0u; half_ /= 2u) {
    if (local < half_) tree[local] += tree[local + half_];
    barrier();
  }
  if (local == 0u) partial[offset + gl_WorkGroupID.x] = tree[0];
}
