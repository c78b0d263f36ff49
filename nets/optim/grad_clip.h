// Global-norm gradient clipping on the GPU, torch.nn.utils.clip_grad_norm_ with the 2-norm:
//   norm = sqrt(sum over every gradient of sum g^2),  factor = min(1, maxNorm / (norm + 1e-6)).
// The norm and the factor stay on the GPU in a two-float tensor [norm, factor]: Adam reads the factor
// there (Adam::step), so nothing is read back and no extra pass over the gradients is made. Where the
// gradients themselves must be scaled (torch's in-place behaviour), scaleGradients does it.
#pragma once

#include "nets/optim/parameters.h"
#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::optim {

class GradClip {
 public:
  GradClip(Context& context, double maxNorm);

  // Records the norm of every gradient the parameters have (those without one are skipped) and the factor.
  void record(Stream& stream, const NamedParameters& parameters) const;
  // Records grad *= factor for every gradient (after record); a gradient tensor shared by two parameters
  // is scaled once.
  void scaleGradients(Stream& stream, const NamedParameters& parameters) const;

  const Tensor& result() const { return result_; }  // [norm, factor], written by record
  double maxNorm() const { return maxNorm_; }
  // Read back after the stream ran (for logs; a training loop need not).
  float norm() const;
  float factor() const;

 private:
  double maxNorm_;
  Tensor result_;
};

}  // namespace smokesvd::optim
