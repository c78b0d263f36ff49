#version 450
// Per-cell flag masks for the MacCormack kernels, derived once from mantaflow's flags (1 fluid,
// 2 obstacle, 4 empty) so that a kernel reads one texel instead of up to nine flags. For cell c,
// with FE(x) = x is fluid or empty (false outside the grid) and e_m the unit step along axis m:
//   bit 0       fluid(c)
//   bit 1       FE(c)
//   bit 2 + m   fluid(c) and (c_m = 0 or fluid(c − e_m))   (MAC component m may be corrected)
//   bit 5 + m   FE(c) and c_m > 0 and FE(c − e_m)           (MAC component m may keep a correction)
//   bit 8 + k   FE(c + (k & 1, (k >> 1) & 1, k >> 2))       (the 2x2x2 block based at c)
// stored as an exact float. n = grid size (x, y, z), one invocation per cell.
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer flags;
layout(std430, binding = 1) writeonly buffer Masks { float masks[]; };
layout(push_constant) uniform Push { ivec3 n; };

int cellIndex(ivec3 c) { return (c.z * n.y + c.y) * n.x + c.x; }
bool inGrid(ivec3 c) { return all(greaterThanEqual(c, ivec3(0))) && all(lessThan(c, n)); }

uint flagsAt(ivec3 c) { return inGrid(c) ? uint(texelFetch(flags, cellIndex(c)).x) : 0u; }
bool fluid(uint bits) { return (bits & 1u) != 0u; }
bool fluidOrEmpty(uint bits) { return (bits & 5u) != 0u; }

void main() {
  const ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  const uint own = flagsAt(c);
  uint mask = (fluid(own) ? 1u : 0u) | (fluidOrEmpty(own) ? 2u : 0u);
  for (int m = 0; m < 3; ++m) {
    ivec3 below = c;
    below[m] -= 1;
    const uint neighbour = flagsAt(below);
    if (fluid(own) && (c[m] == 0 || fluid(neighbour))) mask |= 1u << (2 + m);
    if (fluidOrEmpty(own) && c[m] > 0 && fluidOrEmpty(neighbour)) mask |= 1u << (5 + m);
  }
  for (int k = 0; k < 8; ++k)
    if (fluidOrEmpty(flagsAt(c + ivec3(k & 1, (k >> 1) & 1, k >> 2)))) mask |= 1u << (8 + k);
  masks[cellIndex(c)] = float(mask);
}
