#version 450
// SSIM map of image pairs (Wang, Bovik, Sheikh, Simoncelli 2004), images [N, H, W] with values in [0, 1] (L = 1):
//   mu_a = sum_w a,  s_aa = sum_w a^2 - mu_a^2,  s_ab = sum_w a b - mu_a mu_b   (likewise b)
//   ssim = (2 mu_a mu_b + C1)(2 s_ab + C2) / ((mu_a^2 + mu_b^2 + C1)(s_aa + s_bb + C2)),
//   C1 = (0.01 L)^2, C2 = (0.03 L)^2,
// where sum_w is the 11 x 11 Gaussian window (sigma 1.5, weights normalised to sum 1) at every position where it
// lies wholly inside the image ('valid'): the map is [N, H - 10, W - 10], entry (n, r, c) for the window whose
// top-left pixel is (r, c). One invocation per map entry on a 3D grid (c, r, n).
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer a;
layout(binding = 1) uniform samplerBuffer b;
layout(std430, binding = 2) writeonly buffer Map { float ssim[]; };
layout(push_constant) uniform Push { int width, height, images; };

const int WINDOW = 11;
const float SIGMA = 1.5;
const float C1 = 0.0001;  // (0.01 L)^2
const float C2 = 0.0009;  // (0.03 L)^2

void main() {
  const int mapWidth = width - WINDOW + 1, mapHeight = height - WINDOW + 1;
  const ivec3 id = ivec3(gl_GlobalInvocationID);
  if (id.x >= mapWidth || id.y >= mapHeight || id.z >= images) return;
  float weights[WINDOW];
  float total = 0.0;
  for (int i = 0; i < WINDOW; ++i) {
    const float d = float(i - WINDOW / 2);
    weights[i] = exp(-d * d / (2.0 * SIGMA * SIGMA));
    total += weights[i];
  }
  const float norm = 1.0 / (total * total);
  // Two passes: the means, then the centred moments (equal to sum_w a^2 - mu_a^2 since the weights sum to 1,
  // without its cancellation in float).
  float mu_a = 0.0, mu_b = 0.0;
  const int base = id.z * width * height;
  for (int r = 0; r < WINDOW; ++r) {
    const int row = base + (id.y + r) * width + id.x;
    for (int c = 0; c < WINDOW; ++c) {
      const float w = weights[r] * weights[c] * norm;
      mu_a += w * texelFetch(a, row + c).r;
      mu_b += w * texelFetch(b, row + c).r;
    }
  }
  float s_aa = 0.0, s_bb = 0.0, s_ab = 0.0;
  for (int r = 0; r < WINDOW; ++r) {
    const int row = base + (id.y + r) * width + id.x;
    for (int c = 0; c < WINDOW; ++c) {
      const float w = weights[r] * weights[c] * norm;
      const float x = texelFetch(a, row + c).r - mu_a, y = texelFetch(b, row + c).r - mu_b;
      s_aa += w * x * x;
      s_bb += w * y * y;
      s_ab += w * x * y;
    }
  }
  ssim[(id.z * mapHeight + id.y) * mapWidth + id.x] =
      (2.0 * mu_a * mu_b + C1) * (2.0 * s_ab + C2) / ((mu_a * mu_a + mu_b * mu_b + C1) * (s_aa + s_bb + C2));
}
