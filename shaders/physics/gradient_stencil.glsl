// Finite differences of the differential operators on cell-centred fields (index names: n grid size
// (x, y, z), c cell, e_d unit step along axis d; planes of cells = n.x·n.y·n.z floats).
// Along one axis of m cells the difference operator is
//   ∂f(i) = f(1) − f(0)              at i = 0,
//           (f(i+1) − f(i−1)) / 2    inside,
//           f(m−1) − f(m−2)          at i = m − 1,
// (central inside, one-sided at the faces, like numpy.gradient), and its transpose is
//   (∂ᵀg)(j) = Σ_{i ∈ {j−1, j, j+1}} weight(i, j)·g(i).
#ifndef SMOKESVD_GRADIENT_STENCIL_GLSL
#define SMOKESVD_GRADIENT_STENCIL_GLSL

layout(push_constant) uniform GridPush { ivec3 n; };

int cellCount() { return n.x * n.y * n.z; }
int cellIndex(ivec3 c) { return (c.z * n.y + c.y) * n.x + c.x; }
bool inGrid(ivec3 c) { return all(greaterThanEqual(c, ivec3(0))) && all(lessThan(c, n)); }
ivec3 unitStep(int d) { return ivec3(d == 0 ? 1 : 0, d == 1 ? 1 : 0, d == 2 ? 1 : 0); }

float valueAt(samplerBuffer field, int plane, ivec3 c) {
  return texelFetch(field, plane * cellCount() + cellIndex(c)).x;
}

// The coefficient of f(j) in ∂f(i) along an axis of m cells.
float differenceWeight(int i, int j, int m) {
  if (i == 0) return j == 0 ? -1.0 : (j == 1 ? 1.0 : 0.0);
  if (i == m - 1) return j == m - 2 ? -1.0 : (j == m - 1 ? 1.0 : 0.0);
  return j == i - 1 ? -0.5 : (j == i + 1 ? 0.5 : 0.0);
}

// ∂_d of plane `plane` of `field` at cell c.
float difference(samplerBuffer field, int plane, ivec3 c, int d) {
  const ivec3 e = unitStep(d);
  if (c[d] == 0) return valueAt(field, plane, c + e) - valueAt(field, plane, c);
  if (c[d] == n[d] - 1) return valueAt(field, plane, c) - valueAt(field, plane, c - e);
  return 0.5 * (valueAt(field, plane, c + e) - valueAt(field, plane, c - e));
}

// (∂_dᵀ g)(c) for plane `plane` of g.
float differenceTransposed(samplerBuffer g, int plane, ivec3 c, int d) {
  float sum = 0.0;
  for (int s = -1; s <= 1; ++s) {
    const int i = c[d] + s;
    if (i < 0 || i >= n[d]) continue;
    const float weight = differenceWeight(i, c[d], n[d]);
    if (weight != 0.0) sum += weight * valueAt(g, plane, c + s * unitStep(d));
  }
  return sum;
}

#endif
