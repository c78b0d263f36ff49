#include "nets/ops/timestep_embedding.h"

#include <cmath>

#include "runtime/error.h"

namespace smokesvd::ops {

void timestepEmbedding(Stream& stream, const Tensor& t, const TimestepEmbeddingParams& params, const Tensor& y) {
  if (y.rank() != 2 || y.size(0) != t.numel())
    throw Error("timestep embedding: the output " + toString(y.shape()) + " must be [" + std::to_string(t.numel()) +
                ", dim] for timesteps " + toString(t.shape()));
  const int64_t dim = y.size(1);
  if (static_cast<float>(dim / 2) - params.frequencyShift <= 0.0f)
    throw Error("timestep embedding: dim " + std::to_string(dim) + " is too small for frequency shift " +
                std::to_string(params.frequencyShift) + " (need dim / 2 > shift)");
  if (!(params.maxPeriod > 0.0f))
    throw Error("timestep embedding: max period " + std::to_string(params.maxPeriod) + " must be positive");
  if (y.numel() == 0) return;
  struct { uint32_t N, dim; float logMaxPeriod, shift; } push{
      static_cast<uint32_t>(t.numel()), static_cast<uint32_t>(dim), std::log(params.maxPeriod), params.frequencyShift};
  const Kernel& kernel = stream.kernel("nn/timestep_embedding", {64, 1, 1}, {params.cosineFirst ? 1 : 0});
  stream.dispatchFlat(kernel, {t, y}, push, static_cast<uint64_t>(y.numel()));
}

}  // namespace smokesvd::ops
