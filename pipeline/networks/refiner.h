// NvRef as the pipeline uses it: the blurry render of a view at angle a, the renders at a - beta and
// a + beta of the same density, and the refined images of that view at the two previous frames, blurred
// by halving and doubling their resolution (the paper's down-sampling), through the 2D UNet3+ to a
// residual; the refined image is the render plus the residual:
//   res = UNet3+(cat(w_r(a), w_r(a - b), w_r(a + b), up(down(w_f(t-1, a))), up(down(w_f(t-2, a)))))
//   w_f = w_r(a) + res
// Every image [N, 1, h, w] (N views refined at once); linear resampling by 2 each way.
#pragma once

#include <memory>

#include "nets/models/unet3plus.h"

namespace smokesvd::networks {

struct RefinerOutput {
  Var refined;   // w_f [N, 1, h, w]
  Var residual;  // res [N, 1, h, w]
};

class Refiner {
 public:
  Refiner(Context& context, const models::UNet3PlusConfig& config);
  RefinerOutput forward(Tape& tape, const Var& render, const Var& minus, const Var& plus, const Var& previous,
                        const Var& beforePrevious);
  models::UNet3Plus& net() { return *net_; }

 private:
  std::shared_ptr<models::UNet3Plus> net_;
};

}  // namespace smokesvd::networks
