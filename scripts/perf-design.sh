#!/usr/bin/env bash
# Wall and CPU time of UQ and design (target: 200 UQ samples in ≤ 60 s), whole process, this machine:
#
#   uq-N      `sawdrive uq validation/design/scatter.toml --samples N --seed 1` (the default scene,
#             the paper's motor, under the case study's scatter), fresh output folder (no resumed
#             samples); N = 200 unless --samples;
#   design-X  `sawdrive design validation/design/X.toml` (X = ideal, robust), fresh output folder;
#
# then the per-sample cost split (operator once, static and dynamic parts of a sample) from the
# UQ's summary.json, and the per-evaluation cost by fidelity from each design's summary.json.
# Numbers go to stdout as `name wall_s user_s sys_s max_rss_kb` lines, the UQ's samples/s and CPU
# per sample, the load average before and after, then `cost …` lines.
#
#   scripts/perf-design.sh [--samples N] [--no-design]
#
# Builds the release binary first (cargo build --release -p sawdrive-cli). No FEM runs here: the
# whole-slider lattice model needs none. On a machine shared with other jobs, user+sys (CPU time)
# is the steadier number; the wall time is what a user waits.
set -euo pipefail
cd "$(dirname "$0")/.."

samples=200
design=1
while [[ $# -gt 0 ]]; do
  case "$1" in
    --samples) samples="$2"; shift 2 ;;
    --no-design) design=0; shift ;;
    *) echo "usage: $0 [--samples N] [--no-design]" >&2; exit 2 ;;
  esac
done
[[ "$samples" =~ ^[1-9][0-9]*$ ]] || { echo "error: --samples must be a positive integer" >&2; exit 2; }

cargo build --release -q -p sawdrive-cli
bin="$PWD/target/release/sawdrive"
scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT

# timed NAME CMD...: one line "NAME wall user sys maxrss".
timed() {
  local name="$1"; shift
  /usr/bin/time -f "$name %e %U %S %M" -o "$scratch/time" "$@" >"$scratch/stdout" 2>"$scratch/stderr" || {
    echo "error: $name failed:" >&2; cat "$scratch/stderr" >&2; exit 1; }
  cat "$scratch/time"
}

echo "# name wall_s user_s sys_s max_rss_kb   ($(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg))"
timed "uq-$samples" "$bin" uq validation/design/scatter.toml --samples "$samples" --seed 1 \
  --out "$scratch/uq" --json | tee "$scratch/uq.time"
cp "$scratch/stdout" "$scratch/uq.json"
read -r _ wall user sys _ <"$scratch/uq.time"
python3 -c "import sys; n, w, u, s = int(sys.argv[1]), *map(float, sys.argv[2:5]); \
print(f'uq-{n} samples_per_s={n / w:.2f} cpu_per_sample_s={(u + s) / n:.3f} (wall {w:.1f} s, cpu {u + s:.1f} s)')" \
  "$samples" "$wall" "$user" "$sys"
echo "# load after uq-$samples: $(cut -d' ' -f1-3 /proc/loadavg)"
if [[ $design == 1 ]]; then
  for x in ideal robust; do
    timed "design-$x" "$bin" design "validation/design/$x.toml" --out "$scratch/design" --json
    cp "$scratch/stdout" "$scratch/design-$x.json"
  done
fi
python3 - "$scratch" <<'PY'
import json, pathlib, sys
d = pathlib.Path(sys.argv[1])
u = json.loads((d / "uq.json").read_text())
c = u["cost"]
print(f"cost uq fidelity={u['fidelity']} samples={u['samples']} failed={len(u['failed_samples'])} "
      f"operator_s={c['operator_s']:.3f} static_s={c['static_s']:.3f} "
      f"(own_operator_s={c['sample_operator_s']:.3f}) dynamic_s={c['dynamic_s']:.4f} "
      f"sample_s={u['sample_cost_s']:.3f} operators_built={c['operators_built']} wall_s={u['wall_time_s']:.1f}")
for p in sorted(d.glob("design-*.json")):
    r = json.loads(p.read_text())
    for fid, n, s in r["cost"]:
        print(f"cost {p.stem} fidelity={fid} evaluations={n} per_evaluation_s={s:.3f}")
    print(f"cost {p.stem} wall_s={r['wall_time_s']:.1f} optimum_stage={r['optimum']['stage']}")
PY
