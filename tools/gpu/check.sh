#!/usr/bin/env bash
# The checks to run on a GPU machine in one go, from the repository root (docs/benchmarks.md, "Checking
# on a GPU"), with build-gpu/bundle.tar.xz made by tools/gpu/make-bundle.sh copied beside it. In order of
# what is missing most, each step under its own time limit so that a slow one cannot take the rest:
#   1. the device (smokesvd info);
#   2. every network's training step and inference pass at the small and paper presets (smokesvd bench
#      /small, /paper: time, GFLOP/s, the recording's memory), with the GPU's own memory in use sampled by nvidia-smi
#      meanwhile (the paper preset must fit a 24 GB GPU at batch 1);
#   3. a short paper-preset training run of the coarse G_rho on freshly simulated paper-preset scenes;
#   4. the test programs, with the Khronos validation layer on as in ctest;
#   5. every kernel benchmark (smokesvd bench).
# Writes at most eight files under $OUT (default /tmp/gpu-check), summary.txt among them. Without an
# NVIDIA driver it runs on whatever Vulkan device the loader finds (lavapipe on a CPU machine), which is
# how the script itself is checked; GPU_CHECK_QUICK=1 then shrinks the steps to the tiny preset.
set -uo pipefail
cd "$(dirname "$0")/../.."
out=${OUT:-/tmp/gpu-check}
mkdir -p "$out"
bundle=$PWD/build-gpu/bundle
if [[ ! -f build-gpu/bundle.tar.xz ]]; then
  echo "check.sh: build-gpu/bundle.tar.xz is missing: make it with tools/gpu/make-bundle.sh and copy it here" >&2
  exit 2
fi
if [[ build-gpu/bundle.tar.xz -nt "$bundle/smokesvd" ]]; then  # unpack with tar and xz, or Python's tarfile
  rm -rf "$bundle"
  tar -xJf build-gpu/bundle.tar.xz -C build-gpu 2>/dev/null ||
    python3 -c 'import tarfile, sys; tarfile.open(sys.argv[1]).extractall(sys.argv[2])' build-gpu/bundle.tar.xz build-gpu
  touch "$bundle/smokesvd"
fi
quick=${GPU_CHECK_QUICK:-0}
summary=$out/summary.txt
: >"$summary"
note() { echo "$*" | tee -a "$summary"; }

# The tests' programs name the source folder and the smokesvd binary by the absolute paths of the build
# machine (SMOKESVD_SOURCE_DIR, SMOKESVD_SMOKESVD_BINARY): give this checkout that path if it has another.
source_dir=$(grep -a -o -m1 -E '/[^[:space:][:cntrl:]]*/build-gpu/smokesvd' "$bundle/test_runtime" | head -1 | sed 's|/build-gpu/smokesvd$||')
if [[ -n "$source_dir" && "$source_dir" != "$PWD" && ! -e "$source_dir" ]]; then
  mkdir -p "$(dirname "$source_dir")" && ln -s "$PWD" "$source_dir"
fi
[[ -e build-gpu/smokesvd ]] || ln -s bundle/smokesvd build-gpu/smokesvd

# Vulkan's loader and validation layer from the bundle's packages, unpacked outside /.
vk=/tmp/gpu-check-vulkan
for deb in "$bundle"/debs/*.deb; do dpkg -x "$deb" "$vk"; done
export LD_LIBRARY_PATH="$vk/usr/lib/x86_64-linux-gnu:$bundle/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export VK_LAYER_PATH="$vk/usr/share/vulkan/explicit_layer.d"
nvidia_icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
if [[ -f "$nvidia_icd" ]]; then
  export VK_DRIVER_FILES="$nvidia_icd" VK_ICD_FILENAMES="$nvidia_icd"
  export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
fi
smokesvd=$bundle/smokesvd

# Every step ends by the deadline, GPU_CHECK_SECONDS (default 540) after the start, so that the whole
# script fits a 10-minute slot.
deadline=$((SECONDS + ${GPU_CHECK_SECONDS:-540}))
step() {  # step NAME SECONDS COMMAND...: runs COMMAND under a time limit into $out/NAME.log
  local name=$1 seconds=$2
  shift 2
  local start=$SECONDS left=$((deadline - SECONDS))
  if ((left < 5)); then
    note "$name: not run, the deadline has passed"
    return 0
  fi
  ((seconds > left)) && seconds=$left
  timeout "$seconds" "$@" >"$out/$name.log" 2>&1
  local rc=$?
  note "$name: exit $rc after $((SECONDS - start)) s (limit $seconds s)"
  return 0
}

step info 30 "$smokesvd" info
head -3 "$out/info.log" | tee -a "$summary"

# 2. Training steps, with the GPU's memory sampled every 100 ms.
sampler=
if command -v nvidia-smi >/dev/null; then
  nvidia-smi --query-gpu=timestamp,memory.used,memory.total --format=csv,noheader -lms 100 >"$out/gpu-memory.csv" &
  sampler=$!
fi
# (smokesvd bench prints its table at the end: one step per preset keeps the small rows if the paper
# ones run out of time.)
if [[ "$quick" == 1 ]]; then
  step bench-train-small 600 "$smokesvd" bench train/grho-coarse/tiny --runs 1 --warmup 0
else
  step bench-train-small 60 "$smokesvd" bench /small --runs 3 --warmup 1
  step bench-train-paper 120 "$smokesvd" bench /paper --runs 3 --warmup 1
fi
cat "$out"/bench-train-*.log >"$out/bench-train.log" 2>/dev/null; rm -f "$out"/bench-train-*.log
if [[ -n "$sampler" ]]; then
  kill "$sampler"
  awk -F', ' '{gsub(/ MiB/, "", $2); if ($2 + 0 > peak) peak = $2 + 0} END {print "GPU memory in use, peak over the training benchmarks: " peak " MiB"}' \
    "$out/gpu-memory.csv" | tee -a "$summary"
fi
grep -E '^(train|infer)/' "$out/bench-train.log" >>"$summary" 2>/dev/null

# 3. A short paper-preset training run (11 scenes: every 10th is held out for validation).
preset=paper
[[ "$quick" == 1 ]] && preset=tiny
data=/tmp/gpu-check-scenes
rm -rf "$data" /tmp/gpu-check-run
step simulate 60 "$smokesvd" simulate --preset "$preset" --scenes 11 --frames 4 --seed 1 --out "$data"
step train 90 "$smokesvd" train grho-coarse --preset "$preset" --data "$data" --steps 40 --out /tmp/gpu-check-run
tail -2 "$out/train.log" >>"$summary" 2>/dev/null
cat "$out/simulate.log" "$out/train.log" >"$out/training.log" 2>/dev/null; rm -f "$out/simulate.log" "$out/train.log"
[[ -f /tmp/gpu-check-run/model_card.md ]] && cp /tmp/gpu-check-run/model_card.md "$out/training-model-card.md"

# 4. The test programs, as ctest runs them (validation on; a validation message fails the test).
for program in "$bundle"/test_*; do
  name=$(basename "$program")
  filter='*'
  [[ "$quick" == 1 ]] && filter='*Shape*'
  SMOKESVD_VALIDATION=1 SMOKESVD_SYNC_VALIDATION=1 step "$name" 120 "$program" --gtest_brief=1 --gtest_filter="$filter"
  grep -E '^\[  (PASSED|FAILED|SKIPPED) ' "$out/$name.log" 2>/dev/null | sed "s/^/$name /" >>"$summary"
done
cat "$out"/test_*.log >"$out/tests.log" 2>/dev/null; rm -f "$out"/test_*.log

# 5. Every kernel benchmark.
if [[ "$quick" != 1 ]]; then
  step bench-kernels 90 "$smokesvd" bench --passes 2
fi
cat "$summary"
