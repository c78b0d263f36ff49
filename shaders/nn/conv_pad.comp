#version 450
// Zero padding for the direct convolution, optionally through leaky ReLU (ACTIVATE; f(0) = 0, so the
// padding stays zero):
//   xp[q, z, y, x] = f(src[q, z - lowZ, y - lowY, x - lowX]) where that lies inside src, else 0,
//   f(v) = v > 0 ? v : slope v when ACTIVATE, else v,
// q = n*C + c over [Q, D, H, W] -> [Q, Dp, Hp, Wp]. One invocation writes one row y as vec4s (Wp is a
// multiple of 4); lanes run along y, workgroup y is the plane q*Dp + z, so the only division is
// shared by the workgroup.
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const bool ACTIVATE = false;

layout(binding = 0) uniform samplerBuffer src;
layout(std430, binding = 1) writeonly buffer Padded { vec4 xp[]; };
layout(push_constant) uniform Push {
  int depth, height, width;  // D, H, W
  int paddedDepth;           // Dp
  int paddedHeight;          // Hp
  int paddedRowVec4s;        // Wp / 4
  int lowZ, lowY, lowX;      // padding before the first element
  float slope;               // negative slope of f (ACTIVATE)
};

void main() {
  const int y = int(gl_GlobalInvocationID.x);
  if (y >= paddedHeight) return;
  const int plane = int(gl_WorkGroupID.y);
  const int q = plane / paddedDepth;
  const int sz = plane - q * paddedDepth - lowZ;
  const int sy = y - lowY;
  const bool inside = sz >= 0 && sz < depth && sy >= 0 && sy < height;
  const int source = ((q * depth + sz) * height + sy) * width;
  const int row = (plane * paddedHeight + y) * paddedRowVec4s;
  for (int column = 0; column < paddedRowVec4s; ++column) {
    vec4 v = vec4(0.0);
    for (int i = 0; i < 4; ++i) {
      const int sx = column * 4 + i - lowX;
      if (inside && sx >= 0 && sx < width) v[i] = texelFetch(src, source + sx).x;
    }
    xp[row + column] = ACTIVATE ? mix(slope * v, v, greaterThan(v, vec4(0.0))) : v;
  }
}
