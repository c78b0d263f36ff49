#include "nets/functional/timestep_embedding.h"

#include "nets/op_registry.h"
#include "runtime/error.h"

namespace smokesvd::fn {

Var timestepEmbedding(Tape& tape, const Var& t, int64_t dim, ops::TimestepEmbeddingParams params) {
  if (dim < 1) throw Error("timestep embedding: dim " + std::to_string(dim) + " must be positive");
  Tensor y(tape.context(), {t->value.numel(), dim});
  ops::timestepEmbedding(tape.stream(), t->value, params, y);
  return tape.output(y, {});
}

namespace {

const bool registered = registerOp(
    {"timestep_embedding", "y [N, dim] = sinusoidal embedding of timesteps t [N] (no gradient)", {"t"}, {},
     {{"dim", "", "embedding width"},
      {"max_period", "10000", "longest period"},
      {"shift", "1", "frequency shift: f_j = max_period^(-j / (dim/2 - shift))"},
      {"cos_first", "0", "1 puts the cosines first"}},
     {"y"},
     [](Tape& tape, const std::vector<Var>& in, const OpAttrs& attrs) {
       const ops::TimestepEmbeddingParams params{static_cast<float>(attrs.number("max_period")),
                                                 static_cast<float>(attrs.number("shift")),
                                                 attrs.integer("cos_first") != 0};
       return std::vector<Var>{timestepEmbedding(tape, in[0], attrs.integer("dim"), params)};
     },
     {{.name = "DDPM, odd width", .inputs = {{"t", draw::integers({5}, 0, 999)}}, .attrs = {{"dim", "7"}}},
      {.name = "guided diffusion, cosines first",
       .inputs = {{"t", draw::integers({2, 3}, 0, 999)}},
       .attrs = {{"dim", "8"}, {"shift", "0"}, {"cos_first", "1"}}}},
     Differentiable::No});

}  // namespace
}  // namespace smokesvd::fn
