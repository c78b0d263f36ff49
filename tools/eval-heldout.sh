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
#                FRAMES (default 24), VARIANTS (default: all below but the polish-20-* ones, init-share-*, no-multi-frame and the true-side
#                ones, which bound what a better side view would buy: the scene's true 90-degree view,
#                rendered like the front, given with --side-views),
#                NO_MULTI_FRAME_MODELS: for the no-multi-frame variant, a models folder whose svdiff was
#                trained with options.multi_frame = false (docs/evaluation.md says how)
#                SEED: the side-view sampler's seed (default: reconstruct's, 0), to repeat a comparison with
#                another draw of its noise
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
  [polish-20-prior-0.1]="--polish 20 --polish-prior-weight 0.1"
  [polish-20-prior-0.1-lr-0.05]="--polish 20 --polish-prior-weight 0.1 --polish-lr 0.05"
  [polish-20-prior-0.1-input-4]="--polish 20 --polish-prior-weight 0.1 --polish-input-weight 4"
  [init-share-0.25]="--init-share 0.25"
  [init-share-0.5]="--init-share 0.5"
  [no-multi-frame]="--models ${NO_MULTI_FRAME_MODELS:-}"
  [true-side]=""
  [true-side-no-refinement]="--no-refine"
)
read -ra VARIANTS <<< "${VARIANTS:-full no-refinement no-progressive mirror-side polish-20}"

for scene in "${SCENES[@]}"; do
  name=$(basename "$scene")
  front="$OUT/$name/front"
  absorption=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['render']['absorption'])" "$scene/scene.json")
  volumes=()
  for ((t = 0; t < FRAMES; t++)); do volumes+=("$scene/fields/density_$(printf %04d $t).npz"); done
  for view in front:0 side:90; do
    folder="$OUT/$name/${view%:*}"
    [ -f "$folder.done" ] && continue
    "$SMOKESVD" render "${volumes[@]}" --preset small --angles "${view#*:}" --absorption "$absorption" --ambient 1 \
      --bits 16 --out "$folder" > /dev/null
    touch "$folder.done"
  done
  for variant in "${VARIANTS[@]}"; do
    recon="$OUT/$name/$variant"
    models=("${MODELS_FLAG[@]}")
    if [ "$variant" = no-multi-frame ]; then
      [ -n "${NO_MULTI_FRAME_MODELS:-}" ] || { echo "no-multi-frame: set NO_MULTI_FRAME_MODELS" >&2; exit 2; }
      models=()
    fi
    [[ "$variant" != true-side* ]] || models+=(--side-views "$OUT/$name/side")
    [ -z "${SEED:-}" ] || models+=(--seed "$SEED")
    # shellcheck disable=SC2086
    [ -f "$recon/run.json" ] && grep -q '"complete": true' "$recon/run.json" ||
      "$SMOKESVD" reconstruct "$front" --out "$recon" --framing box --intensity none --resume \
        "${models[@]}" ${FLAGS[$variant]} --no-videos
    [ -f "$OUT/$name/eval-$variant/metrics.json" ] ||
      "$SMOKESVD" eval "$recon" --truth "$scene" --out "$OUT/$name/eval-$variant" --quiet
  done
done

python3 - "$OUT" "${VARIANTS[@]}" <<'EOF'
import json,glob,sys,os
out=sys.argv[1]; variants=sys.argv[2:]
print("| variant | input PSNR / SSIM | side PSNR / SSIM | novel PSNR / SSIM | density RMSE | velocity RMSE | side warp error ×10⁴ | side flow mean / std |")
print("|---|---|---|---|---|---|---|---|")
def mean(ms,f): return sum(f(m) for m in ms)/len(ms)
for v in variants:
    files=sorted(glob.glob(os.path.join(out,'*','eval-'+v,'metrics.json')))
    if not files: continue
    ms=[json.load(open(f)) for f in files]
    cells=["%.2f / %.3f"%(mean(ms,lambda m:m['image'][g]['psnr']['ours']),mean(ms,lambda m:m['image'][g]['ssim']['ours'])) for g in ('input','side','novel')]
    cells.append("%.4f"%mean(ms,lambda m:m['volume']['density_rmse']['ours']))
    cells.append("%.4f"%mean(ms,lambda m:m['volume']['velocity_rmse']['ours']))
    cells.append("%.2f"%(1e4*mean(ms,lambda m:m['temporal']['side']['warp_error']['ours'])))
    cells.append("%.3f / %.3f"%(mean(ms,lambda m:m['temporal']['side']['flow_mean']['ours']),mean(ms,lambda m:m['temporal']['side']['flow_std']['ours'])))
    print("| %s (%d scenes) | %s |"%(v,len(ms)," | ".join(cells)))
ms=[json.load(open(f)) for f in sorted(glob.glob(os.path.join(out,'*','eval-'+variants[0],'metrics.json')))]
for floor,label,vol in (('floor_black','all-black image; all-zero volume','floor_zero'),('floor_input','input view as the view (mirrored from 90°)',None)):
    cells=[]
    for g in ('input','side','novel'):
        if ms[0]['image'][g]['psnr'].get(floor) is None: cells.append('–'); continue
        cells.append("%.2f / %.3f"%(mean(ms,lambda m:m['image'][g]['psnr'][floor]),mean(ms,lambda m:m['image'][g]['ssim'][floor])))
    cells.append("%.4f"%mean(ms,lambda m:m['volume']['density_rmse'][vol]) if vol else '')
    cells.append("%.4f"%mean(ms,lambda m:m['volume']['velocity_rmse'][vol]) if vol else '')
    cells.append("%.2f"%(1e4*mean(ms,lambda m:m['temporal']['side']['warp_error'][floor])))
    cells.append("%.3f / %.3f"%(mean(ms,lambda m:m['temporal']['side']['flow_mean'][floor]),mean(ms,lambda m:m['temporal']['side']['flow_std'][floor])))
    print("| floor: %s | %s |"%(label," | ".join(cells)))
cells=['–','–','–','','', "%.2f"%(1e4*mean(ms,lambda m:m['temporal']['side']['warp_error']['reference'])), "%.3f / %.3f"%(mean(ms,lambda m:m['temporal']['side']['flow_mean']['reference']),mean(ms,lambda m:m['temporal']['side']['flow_std']['reference']))]
print("| the truth itself (its own temporal figures) | %s |"%" | ".join(cells))
EOF
