// Parameter-free layers for Sequential: activations (torch.nn.ReLU, LeakyReLU, SiLU, Sigmoid, Tanh) and
// Dropout. They hold no parameters but take their index in a Sequential, as in PyTorch, so the names of
// the layers after them agree ("0.weight", "2.weight" around an activation at 1).
#pragma once

#include <cstdint>

#include "nets/modules/module.h"

namespace smokesvd::modules {

enum class ActivationKind { ReLU, LeakyReLU, SiLU, Sigmoid, Tanh };

Var activate(Tape& tape, ActivationKind kind, const Var& x, float negativeSlope = 0.01f);

class Activation : public UnaryModule {
 public:
  explicit Activation(ActivationKind kind, float negativeSlope = 0.01f) : kind_(kind), negativeSlope_(negativeSlope) {}
  Var forward(Tape& tape, const Var& x) override { return activate(tape, kind_, x, negativeSlope_); }

 private:
  ActivationKind kind_;
  float negativeSlope_;
};

// Active in training mode only. Each forward call draws a new mask (mask seed = (seed << 32) + call); a
// recording that is submitted many times repeats the mask of the call that recorded it.
class Dropout : public UnaryModule {
 public:
  explicit Dropout(float p, uint64_t seed = 0) : p_(p), seed_(seed) {}
  Var forward(Tape& tape, const Var& x) override;
  // forward returns its input itself (evaluation mode, or p = 0)
  bool passesThrough() const { return !training() || p_ == 0.0f; }

 private:
  float p_;
  uint64_t seed_;
  uint64_t calls_ = 0;
};

}  // namespace smokesvd::modules
