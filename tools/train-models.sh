#!/usr/bin/env bash
# Reproduces the shipped weights of a preset from nothing: simulates the training scenes, then trains the
# six networks in the order their dependencies need (docs/models.md, "Training"). Every step resumes
# where it stopped, so the script can be run again after an interruption.
#
#   tools/train-models.sh [PRESET] [DATA_DIR] [MODELS_DIR]      defaults: small, data/PRESET, models/PRESET
set -euo pipefail
cd "$(dirname "$0")/.."
PRESET=${1:-small}
DATA=${2:-data/$PRESET}
MODELS=${3:-models/$PRESET}
SMOKESVD=${SMOKESVD:-build/smokesvd}
SCENES=${SCENES:-120}
SEED=${SEED:-1000}

"$SMOKESVD" simulate --scenes "$SCENES" --seed "$SEED" --preset "$PRESET" --out "$DATA"
STAGES=${STAGES:-train/$PRESET}  # runs that a shipped network starts from; not shipped
# run NETWORK OUT [FLAGS]: trains NETWORK into OUT unless it is there
run() {
  local network=$1 out=$2
  shift 2
  if [ -f "$out/model.safetensors" ]; then
    echo "$out: trained"
  else
    "$SMOKESVD" train "$network" --data "$DATA" --models "$MODELS" --out "$out" --resume "$@"
  fi
}
train() {
  local network=$1
  shift
  run "$network" "$MODELS/$network" --preset "$PRESET" "$@"
}
# The shipped small svdiff's epsilon stage, and the first G_u that its guidance ran, were trained for fewer steps
# than their configs say (docs/models.md, "Training"); SHIPPED_STEPS=0 trains every network for its config's steps.
shortened() {
  if [ "$PRESET" = small ] && [ "${SHIPPED_STEPS:-1}" = 1 ]; then echo --steps "$1"; fi
}
# ship FOLDER NETWORK [FILE...]: a run's weights, config and logs (and FILEs) replace MODELS/NETWORK's
ship() {
  local from=$1 network=$2
  shift 2
  for file in model.safetensors config.json loss.csv loss.png validation.csv run.json "$@"; do
    cp "$from/$file" "$MODELS/$network/$file"
  done
}
train grho-coarse
train grho-fine --init "$MODELS/grho-coarse/model.safetensors"
# The small preset's first G_u is the narrow one (models/configs/small/gu-narrow.json): svdiff's epsilon stage's
# guidance was trained through it, and the shipped G_u (twice as wide) replaces it below.
if [ "$PRESET" = small ]; then
  run gu "$MODELS/gu" --config models/configs/small/gu-narrow.json $(shortened 2500)
else
  train gu
fi
# The shipped small NvRef: trained with the true history, then twice on its own (docs/models.md, "NvRef and
# its history").
if [ "$PRESET" = small ]; then
  run nvref "$STAGES/nvref-true-history" --preset small
  run nvref "$STAGES/nvref-own-history-1" --config models/configs/small/nvref-own-history-1.json --seed 16 \
    --init "$STAGES/nvref-true-history/model.safetensors"
  run nvref "$MODELS/nvref" --config models/configs/small/nvref-own-history-2.json --seed 7 \
    --init "$STAGES/nvref-own-history-1/model.safetensors"
else
  train nvref
fi
# The small SvDiff-init and SvDiff are first trained to predict the noise (the paper's epsilon), then continued
# below to predict v, as the shipped weights do (docs/models.md, "SvDiff predicts v").
if [ "$PRESET" = small ]; then
  run svdiff-init "$STAGES/svdiff-init-epsilon" --config models/configs/small/svdiff-init-epsilon.json
  run svdiff "$STAGES/svdiff-epsilon" --config models/configs/small/svdiff-epsilon.json $(shortened 1200)
else
  train svdiff-init
  train svdiff
fi
# Two continuations of grho-fine's first run (above; all 16 true views, which gu fine-tuned on), both small only:
# - grho-fine-true-views, on 16 true views with the renders weighted 4 (docs/models.md, "The fine G_ρ on true
#   views"); the reconstruction does not use it;
# - the shipped fine G_rho, on the views the reconstruction gives it (docs/models.md, "The fine G_rho and the
#   views it is given"); its model card describes both of its runs.
if [ "$PRESET" = small ]; then
  run grho-fine "$MODELS/grho-fine-true-views" --config models/configs/small/grho-fine-true-views.json --seed 61 \
    --init "$MODELS/grho-fine/model.safetensors"
  run grho-fine "$STAGES/grho-fine-inference-views" --config models/configs/small/grho-fine-inference-views.json \
    --init "$MODELS/grho-fine/model.safetensors"
  ship "$STAGES/grho-fine-inference-views" grho-fine  # its shipped model card describes both runs
  # The shipped G_u: the preset's config (filters 16-128, the advected density weighted 100), from scratch on
  # true densities (docs/models.md, "The shipped G_u").
  run gu "$STAGES/gu" --preset small --seed 91
  ship "$STAGES/gu" gu model_card.md  # the narrow G_u's card does not describe these weights
  # The shipped SvDiff-init and SvDiff: the preset's configs (v prediction), from the epsilon runs above; SvDiff's
  # guidance runs through the shipped G_u.
  train svdiff-init --seed 5 --init "$STAGES/svdiff-init-epsilon/model.safetensors"
  train svdiff --seed 5 --init "$STAGES/svdiff-epsilon/model.safetensors"
fi
# The shipped folder keeps what a user needs: each network's weights, config and model card, and the
# loss curve; the logs stay beside them.
for network in grho-coarse grho-fine grho-fine-true-views gu nvref svdiff-init svdiff; do
  rm -f "$MODELS/$network/checkpoint.safetensors"
done
