#version 450
// C[m, n] = sum_k A(m, k) * B(k, n) + bias[n] for m < M, n < N, k < K, where
//   A(m, k) = A[m*K + k] (A_KM = 0: A is [M, K]) or A[k*M + m] (A_KM = 1: A is [K, M]),
//   B(k, n) = B[k*N + n] (B_NK = 0: B is [K, N]) or B[n*K + k] (B_NK = 1: B is [N, K], like a PyTorch
//   linear weight [out, in]). bias only with HAS_BIAS.
// Register blocking: invocation (x, y) computes the 4 x 8 tile of C at rows m0 = 4y.., columns n0 = 8x..;
// lanes along x share rows (every lane fetches the same A texels). K runs in chunks of 4: a 4 x 4 block
// of A and a 4 x 8 block of B per chunk, then a tail of K % 4 single steps.
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

float elementA(uint index) { return A_VEC4 ? texelFetch(A, int(index / 4u))[index % 4u] : texelFetch(A, int(index)).x; }
float elementB(uint index) { return B_VEC4 ? texelFetch(B, int(index / 4u))[index % 4u] : texelFetch(B, int(index)).x; }
uint row(uint i) { return min(m0 + i, M - 1u); }
uint column(uint j) { return min(n0 + j, N - 1u); }

// A(m0..m0+3, k)
vec4 columnOfA(uint k) {
  if (A_KM == 1 && A_VEC4) return texelFetch(A, int((k * M + m0) / 4u));
  if (A_KM == 1) return vec4(elementA(k * M + row(0u)), elementA(k * M + row(1u)), elementA(k * M + row(2u)), elementA(k * M + row(3u)));
  return vec4(elementA(row(0u) * K + k), elementA(row(1u) * K + k), elementA(row(2u) * K + k), elementA(row(3u) * K + k));
}

// B(k, n0..n0+3) and B(k, n0+4..n0+7)
void rowOfB(uint k, out vec4 low, out vec4 high) {
  if (B_NK == 0 && B_VEC4) {
    low = texelFetch(B, int((k * N + n0) / 4u));
    high = texelFetch(B, int((k * N + min(n0 + 4u, N - 4u)) / 4u));
  } else if (B_NK == 0) {
    low = vec4(elementB(k * N + column(0u)), elementB(k * N + column(1u)), elementB(k * N + column(2u)), elementB(k * N + column(3u)));
    high = vec4(elementB(k * N + column(4u)), elementB(k * N + column(5u)), elementB(k * N + column(6u)), elementB(k * N + column(7u)));
  } else {
    low = vec4(elementB(column(0u) * K + k), elementB(column(1u) * K + k), elementB(column(2u) * K + k), elementB(column(3u) * K + k));
    high = vec4(elementB(column(4u) * K + k), elementB(column(5u) * K + k), elementB(column(6u) * K + k), elementB(column(7u) * K + k));
  }
}

// a[kk] = A(m0..m0+3, k0+kk)
void blockOfA(uint k0, out mat4 a) {
  if (A_KM == 0 && A_VEC4) {
    a = transpose(mat4(texelFetch(A, int((row(0u) * K + k0) / 4u)), texelFetch(A, int((row(1u) * K + k0) / 4u)),
                       texelFetch(A, int((row(2u) * K + k0) / 4u)), texelFetch(A, int((row(3u) * K + k0) / 4u))));
  } else {
    a = mat4(columnOfA(k0), columnOfA(k0 + 1u), columnOfA(k0 + 2u), columnOfA(k0 + 3u));
  }
}

// low[kk] = B(k0+kk, n0..n0+3), high[kk] = B(k0+kk, n0+4..n0+7)
void blockOfB(uint k0, out mat4 low, out mat4 high) {
  if (B_NK == 1 && B_VEC4) {
    low = transpose(mat4(texelFetch(B, int((column(0u) * K + k0) / 4u)), texelFetch(B, int((column(1u) * K + k0) / 4u)),
                         texelFetch(B, int((column(2u) * K + k0) / 4u)), texelFetch(B, int((column(3u) * K + k0) / 4u))));
    high = transpose(mat4(texelFetch(B, int((column(4u) * K + k0) / 4u)), texelFetch(B, int((column(5u) * K + k0) / 4u)),
                          texelFetch(B, int((column(6u) * K + k0) / 4u)), texelFetch(B, int((column(7u) * K + k0) / 4u))));
  } else {
    for (uint kk = 0u; kk < 4u; ++kk) rowOfB(k0 + kk, low[kk], high[kk]);
  }
}

void main() {
  n0 = 8u * gl_GlobalInvocationID.x;
  m0 = 4u * gl_GlobalInvocationID.y;
  if (n0 >= N || m0 >= M) return;

  vec4 low[4] = vec4[4](vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0));   // C(m0+i, n0..n0+3)
  vec4 high[4] = vec4[4](vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0));  // C(m0+i, n0+4..n0+7)
  const uint chunked = K & ~3u;
  for (uint k0 = 0u; k0 < chunked; k0 += 4u) {
    mat4 a, bLow, bHigh;
    blockOfA(k0, a);
    blockOfB(k0, bLow, bHigh);
    for (uint kk = 0u; kk < 4u; ++kk) {
      for (uint i = 0u; i < 4u; ++i) {
        low[i] += a[kk][i] * bLow[kk];
        high[i] += a[kk][i] * bHigh[kk];
      }
    }
  }
  for (uint k = chunked; k < K; ++k) {
    const vec4 a = columnOfA(k);
    vec4 bLow, bHigh;
    rowOfB(k, bLow, bHigh);
    for (uint i = 0u; i < 4u; ++i) {
      low[i] += a[i] * bLow;
      high[i] += a[i] * bHigh;
    }
  }

  vec4 biasLow = vec4(0.0), biasHigh = vec4(0.0);
  if (HAS_BIAS) {
    biasLow = vec4(texelFetch(bias, int(column(0u))).x, texelFetch(bias, int(column(1u))).x,
                   texelFetch(bias, int(column(2u))).x, texelFetch(bias, int(column(3u))).x);
    biasHigh = vec4(texelFetch(bias, int(column(4u))).x, texelFetch(bias, int(column(5u))).x,
                    texelFetch(bias, int(column(6u))).x, texelFetch(bias, int(column(7u))).x);
  }
  for (uint i = 0u; i < 4u && m0 + i < M; ++i) {
    const vec4 valuesLow = low[i] + biasLow;
    const vec4 valuesHigh = high[i] + biasHigh;
    const uint base = (m0 + i) * N + n0;
    for (uint j = 0u; j < 4u && n0 + j < N; ++j) C[base + j] = valuesLow[j];
    for (uint j = 0u; j < 4u && n0 + 4u + j < N; ++j) C[base + 4u + j] = valuesHigh[j];
  }
}
