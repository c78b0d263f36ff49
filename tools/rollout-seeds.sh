#!/usr/bin/env bash
# SvDiff's 40-frame side-view rollout (`smokesvd rollout`) repeated with several sampler seeds, and the
# spread of its figures across them. Every scene's frame t is sampled with seed + t, so one rollout is
# close to one draw of the sampler's noise (docs/models.md, "SvDiff-init's history-free estimate blended
# in"); comparing samplers or weights wants several. Resumable: a seed whose JSON exists is not rerun.
# Prints one markdown row per seed (rollout PSNR, the four decades of frames, the margin over the
# all-black side view per decade, last 10 - first 10), then the mean and the sample standard deviation.
#
#   tools/rollout-seeds.sh OUT_DIR [SEED...]            (default seeds: 0 1000 2000 3000)
#   environment: SMOKESVD (default build/smokesvd), DATA (default data/small), FRAMES (default 40),
#                SCENES (default 6), ROLLOUT_FLAGS (more `smokesvd rollout` flags, e.g. "--init-share 0.5")
set -euo pipefail
cd "$(dirname "$0")/.."
SMOKESVD=${SMOKESVD:-build/smokesvd}
DATA=${DATA:-data/small}
FRAMES=${FRAMES:-40}
SCENES=${SCENES:-6}
OUT=${1:?usage: tools/rollout-seeds.sh OUT_DIR [SEED...]}
shift
SEEDS=("$@")
[ ${#SEEDS[@]} -gt 0 ] || SEEDS=(0 1000 2000 3000)
command -v python3 > /dev/null || { echo "rollout-seeds.sh: needs python3 for the summary" >&2; exit 1; }
mkdir -p "$OUT"

FILES=()
for seed in "${SEEDS[@]}"; do
  json="$OUT/rollout_seed_$seed.json"
  if [ ! -f "$json" ]; then
    echo "seed $seed: rolling out" >&2
    # shellcheck disable=SC2086  # ROLLOUT_FLAGS is a list of flags
    "$SMOKESVD" rollout --data "$DATA" --frames "$FRAMES" --scenes "$SCENES" --seed "$seed" ${ROLLOUT_FLAGS:-} \
      --quiet --out "$json.tmp"
    mv "$json.tmp" "$json"
  fi
  FILES+=("$json")
done

python3 - "${FILES[@]}" <<'EOF'
import json, statistics, sys

def decades(values):
    n = len(values) // 4
    return [sum(values[i * n:(i + 1) * n]) / n for i in range(4)] if n else []

rows = []
print("| seed | rollout (dB) | frames by quarter | over all-black | over mirrored front | last 10 - first 10 |")
print("|---|---|---|---|---|---|")
for path in sys.argv[1:]:
    r = json.load(open(path))
    side, black = r["psnr_per_frame"], r["psnr_black_per_frame"]
    q, qb = decades(side), decades(black)
    row = {"mean": r["psnr_mean"], "over_mirrored": r["psnr_mean"] - r["psnr_mirrored_front_mean"],
           "fall": r["psnr_last_10"] - r["psnr_first_10"]}
    rows.append(row)
    seed = path.rsplit("_", 1)[-1].removesuffix(".json")
    print(f"| {seed} | {row['mean']:.2f} | {' / '.join(f'{v:.2f}' for v in q)} | "
          f"{' / '.join(f'{a - b:+.2f}' for a, b in zip(q, qb))} | {row['over_mirrored']:+.2f} | {row['fall']:+.2f} |")
if len(rows) > 1:
    def spread(key):
        values = [row[key] for row in rows]
        sign = "+" if key != "mean" else ""
        return f"{statistics.mean(values):{sign}.2f} ± {statistics.stdev(values):.2f}"
    print(f"| mean ± sd of {len(rows)} | {spread('mean')} | | | {spread('over_mirrored')} | {spread('fall')} |")
EOF
