#include "pipeline/train/trainer.h"

#include "nets/functional/elementwise.h"

namespace smokesvd::train {

Var sumOf(Tape& tape, const std::vector<Var>& values) {
  Var sum;
  for (const Var& v : values) sum = sum ? fn::add(tape, sum, v) : v;
  return sum;
}

void addUpTotal(Tape& tape, LossTerms& terms) {
  std::vector<Var> values;
  for (const auto& [name, term] : terms.terms) values.push_back(term);
  terms.total = sumOf(tape, values);
}

}  // namespace smokesvd::train
