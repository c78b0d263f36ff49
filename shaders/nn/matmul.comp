#version 450
// C[m, n] = sum_k A(m, k) * B(k, n) + bias[n] for m < M, n < N, k < K, where
//   A(m, k) = A[m*K + k] (A_KM = 0: A is [M, K]) or A[k*M + m] (A_KM = 1: A is [K, M]),
//   B(k, n) = B[k*N + n] (B_NK = 0: B is [K, N]) or B[n*K + k] (B_NK = 1: B is [N, K], like a PyTorch
//   linear weight [out, in]). bias only with HAS_BIAS.
// Register blocking: invocation (x, y) computes the 8 x 4 tile of C at rows m0 = 8y.., columns n0 = 4x..;
// the SIMD lanes run along x, so they share rows and every lane fetches the same A texels (cache hits),
// which is why the tile is tall. K runs in chunks of 4 (an 8 x 4 block of A and a 4 x 4 block of B),
// then a tail of K % 4 single steps.
// A_VEC4 / B_VEC4: the operand's fastest extent (K or M for A, N or K for B) is a multiple of 4, so it is
// bound as vec4 texels; otherwise as one float per texel. Reads past M or N are clamped to the last
// row or column and their results discarded.
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int A_KM = 0;
layout(constant_id = 4) const int B_NK = 0;
layout(constant_id = 5) const bool A_VEC4 = false;
layout(constant_id = 6) const bool B_VEC4 = false;
layout(constant_id = 7) const bool HAS_BIAS = false;

layout(binding = 0) uniform samplerBuffer A;
layout(binding = 1) uniform samplerBuffer B;
layout(binding = 2) uniform samplerBuffer bias;
layout(std430, binding = 3) writeonly buffer Output { float C[]; };
layout(push_constant) uniform Push { uint M, N, K; };

uint m0, n0;

// Single elements, for operands bound one float per texel. (The K tail also reaches them for a vec4
// operand that is contiguous along k, but then K % 4 == 0 and the tail is empty.)
float elementA(uint index) { return texelFetch(A, int(index)).x; }
float elementB(uint index) { return texelFetch(B, int(index)).x; }
uint row(uint i) { return min(m0 + i, M - 1u); }
uint column(uint j) { return min(n0 + j, N - 1u); }

// A(m0+4h .. m0+4h+3, k) for half h
vec4 columnOfA(uint k, uint h) {
  if (A_KM == 1 && A_VEC4) return texelFetch(A, int((k * M + min(m0 + 4u * h, M - 4u)) / 4u));
  if (A_KM == 1)
    return vec4(elementA(k * M + row(4u * h)), elementA(k * M + row(4u * h + 1u)), elementA(k * M + row(4u * h + 2u)),
                elementA(k * M + row(4u * h + 3u)));
  return vec4(elementA(row(4u * h) * K + k), elementA(row(4u * h + 1u) * K + k), elementA(row(4u * h + 2u) * K + k),
              elementA(row(4u * h + 3u) * K + k));
}

// B(k, n0..n0+3)
vec4 rowOfB(uint k) {
  if (B_NK == 0 && B_VEC4) return texelFetch(B, int((k * N + n0) / 4u));
  if (B_NK == 0)
    return vec4(elementB(k * N + column(0u)), elementB(k * N + column(1u)), elementB(k * N + column(2u)),
                elementB(k * N + column(3u)));
  return vec4(elementB(column(0u) * K + k), elementB(column(1u) * K + k), elementB(column(2u) * K + k),
              elementB(column(3u) * K + k));
}

// a[kk] = A(m0+4h .. m0+4h+3, k0+kk)
mat4 blockOfA(uint k0, uint h) {
  if (A_KM == 0 && A_VEC4) {
    return transpose(mat4(texelFetch(A, int((row(4u * h) * K + k0) / 4u)), texelFetch(A, int((row(4u * h + 1u) * K + k0) / 4u)),
                          texelFetch(A, int((row(4u * h + 2u) * K + k0) / 4u)), texelFetch(A, int((row(4u * h + 3u) * K + k0) / 4u))));
  }
  return mat4(columnOfA(k0, h), columnOfA(k0 + 1u, h), columnOfA(k0 + 2u, h), columnOfA(k0 + 3u, h));
}

// b[kk] = B(k0+kk, n0..n0+3)
mat4 blockOfB(uint k0) {
  if (B_NK == 1 && B_VEC4) {
    return transpose(mat4(texelFetch(B, int((column(0u) * K + k0) / 4u)), texelFetch(B, int((column(1u) * K + k0) / 4u)),
                          texelFetch(B, int((column(2u) * K + k0) / 4u)), texelFetch(B, int((column(3u) * K + k0) / 4u))));
  }
  return mat4(rowOfB(k0), rowOfB(k0 + 1u), rowOfB(k0 + 2u), rowOfB(k0 + 3u));
}

void main() {
  n0 = 4u * gl_GlobalInvocationID.x;
  m0 = 8u * gl_GlobalInvocationID.y;
  if (n0 >= N || m0 >= M) return;

  vec4 sums[8] = vec4[8](vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0));
  const uint chunked = K & ~3u;
  for (uint k0 = 0u; k0 < chunked; k0 += 4u) {
    const mat4 low = blockOfA(k0, 0u);
    const mat4 high = blockOfA(k0, 1u);
    const mat4 b = blockOfB(k0);
    for (uint kk = 0u; kk < 4u; ++kk) {
      for (uint i = 0u; i < 4u; ++i) {
        sums[i] += low[kk][i] * b[kk];
        sums[4u + i] += high[kk][i] * b[kk];
      }
    }
  }
  for (uint k = chunked; k < K; ++k) {
    const vec4 low = columnOfA(k, 0u);
    const vec4 high = columnOfA(k, 1u);
    const vec4 b = rowOfB(k);
    for (uint i = 0u; i < 4u; ++i) {
      sums[i] += low[i] * b;
      sums[4u + i] += high[i] * b;
    }
  }

  vec4 biasRow = vec4(0.0);
  if (HAS_BIAS) {
    biasRow = vec4(texelFetch(bias, int(column(0u))).x, texelFetch(bias, int(column(1u))).x,
                   texelFetch(bias, int(column(2u))).x, texelFetch(bias, int(column(3u))).x);
  }
  for (uint i = 0u; i < 8u; ++i) {
    if (m0 + i >= M) break;
    const vec4 values = sums[i] + biasRow;
    const uint base = (m0 + i) * N + n0;
    for (uint j = 0u; j < 4u; ++j)
      if (n0 + j < N) C[base + j] = values[j];
  }
}
