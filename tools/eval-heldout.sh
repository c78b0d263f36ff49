#!/usr/bin/env bash
# The table of docs/evaluation.md on the project's own held-out scenes: for each scene, its front view
# rendered in the networks' look (the scene's absorption, ambient 1, no light: the truth in the networks'
# units seen through the reconstruction's renderer), reconstructed by every method variant with
# --framing box --intensity none, and measured by `smokesvd eval --truth`. Resumable: a finished
# reconstruction or evaluation is kept. Prints one markdown row per variant (the mean over the scenes).
#
#   tools/eval-heldout.sh OUT_DIR [SCENE_DIR...]
#       defaults: scenes 0009, 0019, 0029 of data/small (held out: every 10th scene), frames 0:FRAMES
#   environment: SMOKESVD (default build/smokesvd), MODELS (default: the shipped models/small),
#                FRAMES (default 24), VARIANTS (default: all below)
set -euo pipefail
cd "$(dirname "$0")/.."
SMOKESVD=${SMOKESVD:-build/smokesvd}
FRAMES=${FRAMES:-24}
OUT=${1:?usage: tools/eval-heldout.sh OUT_DIR [SCENE_DIR...]}
shift
SCENES=("$@")
[ ${#SCENES[@]} -gt 0 ] || SCENES=(data/small/scene_0009 data/small/scene_0019 data/small/scene_0029)
MODELS_FLAG=()
[ -z "${MODELS:-}" ] || MODELS_FLAG=(--models "$MODELS")

declare -A FLAGS=(
  [full]=""
  [no-refinement]="--no-refine"
  [no-progressive]="--no-progressive"
  [mirror-side]="--side-view mirror"
  [polish-20]="--polish 20"
)
VARIANTS=(${VARIANTS:-full no-refinement no-progressive mirror-side polish-20})

for scene in "${SCENES[@]}"; do
  name=$(basename "$scene")
  front="$OUT/$name/front"
  if [ ! -f "$front.done" ]; then
    absorption=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['render']['absorption'])" "$scene/scene.json")
    volumes=()
    for ((t = 0; t < FRAMES; t++)); do volumes+=("$scene/fields/density_$(printf %04d $t).npz"); done
    "$SMOKESVD" render "${volumes[@]}" --preset small --angles 0 --absorption "$absorption" --ambient 1 \
      --bits 16 --out "$front" > /dev/null
    touch "$front.done"
  fi
  for variant in "${VARIANTS[@]}"; do
    recon="$OUT/$name/$variant"
    # shellcheck disable=SC2086
    [ -f "$recon/run.json" ] && grep -q '"complete": true' "$recon/run.json" ||
      "$SMOKESVD" reconstruct "$front" --out "$recon" --framing box --intensity none --resume \
        "${MODELS_FLAG[@]}" ${FLAGS[$variant]} --no-videos
    [ -f "$OUT/$name/eval-$variant/metrics.json" ] ||
      "$SMOKESVD" eval "$recon" --truth "$scene" --out "$OUT/$name/eval-$variant" --quiet
  done
done

python3 - "$OUT" "${VARIANTS[@]}" <<'EOF'
import json, sys, glob, os
out, variants = sys.argv[1], sys.argv[2:]
def group(m, name):
    return m["image"][name]
print("| variant | input PSNR / SSIM | side PSNR / SSIM | novel PSNR / SSIM | density RMSE | scenes |")
print("|---|---|---|---|---|---|")
for v in variants:
    files = sorted(glob.glob(os.path.join(out, "*", "eval-" + v, "metrics.json")))
    if not files: continue
    ms = [json.load(open(f)) for f in files]
    def mean(f): return sum(f(m) for m in ms) / len(ms)
    cells = []
    for g in ("input", "side", "novel"):
        cells.append("%.2f / %.3f" % (mean(lambda m: group(m, g)["psnr"]["ours"]), mean(lambda m: group(m, g)["ssim"]["ours"])))
    rmse = mean(lambda m: m["volume"]["density_rmse"]["ours"])
    print("| %s | %s | %.4f | %d |" % (v, " | ".join(cells), rmse, len(ms)))
m = [json.load(open(f)) for f in sorted(glob.glob(os.path.join(out, "*", "eval-" + variants[0], "metrics.json")))]
if m:
    for floor in ("floor_black", "floor_input"):
        cells = []
        for g in ("input", "side", "novel"):
            vals = [group(x, g)["psnr"].get(floor) for x in m]
            ss = [group(x, g)["ssim"].get(floor) for x in m]
            cells.append("-" if None in vals else "%.2f / %.3f" % (sum(vals) / len(vals), sum(ss) / len(ss)))
        print("| %s | %s | | %d |" % (floor, " | ".join(cells), len(m)))
EOF
