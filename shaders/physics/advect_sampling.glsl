// Shared by the advection kernels: the push block, cell indexing, trace velocities and the
// trilinear stencil with mantaflow's clamping.
//
// Index names: n = grid size (x, y, z) in cells; c = integer cell (i, j, k), centred at c + ½;
// cells = n.x·n.y·n.z; a plane is one scalar grid of `cells` floats inside a tensor, at offset
// plane·cells. The plane's MODE (constant_id 3) says where its values live and which velocity
// traces them:
//   MODE 0: at cell centres, traced by the centred velocity (½(u(c) + u(c + e_d)) per axis d),
//   MODE 1 + m: MAC component m at the lower m-face, traced by the face velocity: component m is
//     u_m(c) itself, a component d ≠ m the average of the four d-faces around the m-face,
//     ¼(u_d(c) + u_d(c − e_m) + u_d(c + e_d) + u_d(c + e_d − e_m)).
// A MAC plane is interpolated exactly like a centred one: shifting the face by −½ e_m moves the
// face to a cell centre and the traced point with it (mantaflow's getInterpolatedComponent).
#ifndef SMOKESVD_ADVECT_SAMPLING_GLSL
#define SMOKESVD_ADVECT_SAMPLING_GLSL

layout(constant_id = 3) const int MODE = 0;

// dt is signed (a backward trace passes −dt); strength is MacCormack's correction factor;
// directScale and hasPrior belong to the adjoint kernels.
layout(push_constant) uniform AdvectPush {
  ivec3 n;
  int plane;
  float dt;
  float strength;
  float directScale;
  int hasPrior;
};

int cellCount() { return n.x * n.y * n.z; }
int cellIndex(ivec3 c) { return (c.z * n.y + c.y) * n.x + c.x; }
// Kernels run on a 3D grid of invocations, one per cell (x fastest along the SIMD lanes).
ivec3 invocationCell() { return ivec3(gl_GlobalInvocationID); }
bool inGrid(ivec3 c) { return all(greaterThanEqual(c, ivec3(0))) && all(lessThan(c, n)); }
bool isInterior(ivec3 c) { return all(greaterThan(c, ivec3(0))) && all(lessThan(c, n - 1)); }
ivec3 axisStride() { return ivec3(1, n.x, n.x * n.y); }

float fetchVelocity(samplerBuffer velocity, int component, int index) {
  return texelFetch(velocity, component * cellCount() + index).x;
}

vec3 traceVelocity(samplerBuffer velocity, ivec3 c) {
  const int at = cellIndex(c);
  const ivec3 stride = axisStride();
  vec3 v;
  if (MODE == 0) {
    for (int d = 0; d < 3; ++d)
      v[d] = 0.5 * (fetchVelocity(velocity, d, at) + fetchVelocity(velocity, d, at + stride[d]));
    return v;
  }
  const int m = MODE - 1;
  for (int d = 0; d < 3; ++d) {
    if (d == m) {
      v[d] = fetchVelocity(velocity, d, at);
    } else {
      const int up = at + stride[d];
      v[d] = 0.25 * (fetchVelocity(velocity, d, at) + fetchVelocity(velocity, d, at - stride[m]) +
                     fetchVelocity(velocity, d, up) + fetchVelocity(velocity, d, up - stride[m]));
    }
  }
  return v;
}

// The traced point of cell c: c + ½ − v·dt.
vec3 departurePoint(ivec3 c, vec3 v, float signedDt) { return vec3(c) + 0.5 - v * signedDt; }

// Trilinear stencil of point p: base cell b and upper weights w1 per axis (lower weights 1 − w1),
// q = p − ½, b = trunc(q); where q < 0 the lookup sits on cell 0 (w1 = 0), where b ≥ n − 1 on cell
// n − 1 (b = n − 2, w1 = 1). slope = ∂w1/∂p: 1 inside, 0 on a clamped axis.
struct Stencil {
  ivec3 base;
  vec3 w1;
  vec3 slope;
};

Stencil stencilAt(vec3 p) {
  Stencil s;
  const vec3 q = p - 0.5;
  s.base = ivec3(q);
  s.w1 = q - vec3(s.base);
  s.slope = vec3(1.0);
  for (int d = 0; d < 3; ++d) {
    if (q[d] < 0.0) {
      s.base[d] = 0;
      s.w1[d] = 0.0;
      s.slope[d] = 0.0;
    }
    if (s.base[d] >= n[d] - 1) {
      s.base[d] = n[d] - 2;
      s.w1[d] = 1.0;
      s.slope[d] = 0.0;
    }
  }
  return s;
}

// The eight stencil values, corner (a, b, e) ∈ {0,1}³ at index a + 2b + 4e.
void fetchCorners(samplerBuffer field, int planeOffset, Stencil s, out float corner[8]) {
  const ivec3 stride = axisStride();
  const int at = planeOffset + cellIndex(s.base);
  for (int k = 0; k < 8; ++k)
    corner[k] = texelFetch(field, at + (k & 1) * stride.x + ((k >> 1) & 1) * stride.y + (k >> 2) * stride.z).x;
}

// Trilinear value, summed in mantaflow's order (y, then x, then z).
float trilinear(float corner[8], Stencil s) {
  const vec3 w1 = s.w1;
  const vec3 w0 = 1.0 - w1;
  return ((corner[0] * w0.y + corner[2] * w1.y) * w0.x + (corner[1] * w0.y + corner[3] * w1.y) * w1.x) * w0.z +
         ((corner[4] * w0.y + corner[6] * w1.y) * w0.x + (corner[5] * w0.y + corner[7] * w1.y) * w1.x) * w1.z;
}

// ∂ trilinear / ∂p (zero along clamped axes).
vec3 trilinearGradient(float corner[8], Stencil s) {
  const vec3 w1 = s.w1;
  const vec3 w0 = 1.0 - w1;
  const float dx = ((corner[1] - corner[0]) * w0.y + (corner[3] - corner[2]) * w1.y) * w0.z +
                   ((corner[5] - corner[4]) * w0.y + (corner[7] - corner[6]) * w1.y) * w1.z;
  const float dy = ((corner[2] - corner[0]) * w0.x + (corner[3] - corner[1]) * w1.x) * w0.z +
                   ((corner[6] - corner[4]) * w0.x + (corner[7] - corner[5]) * w1.x) * w1.z;
  const float dz = ((corner[4] - corner[0]) * w0.x + (corner[5] - corner[1]) * w1.x) * w0.y +
                   ((corner[6] - corner[2]) * w0.x + (corner[7] - corner[3]) * w1.x) * w1.y;
  return vec3(dx, dy, dz) * s.slope;
}

#endif
