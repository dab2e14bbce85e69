#!/usr/bin/env bash
# Scaling of elastic-fem's iterative path (p-multigrid PCG, SA-AMG coarse solve) on the generated
# Tet10 unit cube (clamped at z = 0, gravity), release build, one thread by default:
#
#   scripts/compare-box-scale.sh [--threads N] [UNKNOWNS ...]     (default 350000 1000000 2000000)
#
# Per size: the example's stage times and PCG iterations, then whole-process wall time, CPU time
# (user + sys), peak resident memory (/usr/bin/time) and the load average before the run; last,
# the fitted cost exponents d ln(cost) / d ln(N) between consecutive sizes and first → last, for
# wall and CPU time. On a shared machine compare CPU times; wall times only on an idle one.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
target="${CARGO_TARGET_DIR:-$root/target}"
threads=1
sizes=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --threads) threads="$2"; shift 2 ;;
    *) sizes+=("$1"); shift ;;
  esac
done
[[ ${#sizes[@]} -gt 0 ]] || sizes=(350000 1000000 2000000)
(cd "$root" && cargo build -q --release -p elastic-fem --example box_solve)
bin="$target/release/examples/box_solve"
out="$(mktemp)"
trap 'rm -f "$out"' EXIT
for n in "${sizes[@]}"; do
  load="$(cut -d' ' -f1-3 /proc/loadavg)"
  log="$(RAYON_NUM_THREADS="$threads" /usr/bin/time -f "TIME %e %U %S %M" "$bin" "$n" iterative 2>&1)"
  echo "$log" | grep -v '^TIME'
  read -r wall user sys rss <<<"$(echo "$log" | grep '^TIME' | cut -d' ' -f2-)"
  reduced="$(echo "$log" | sed -n 's/.*(reduced \([0-9]*\)).*/\1/p')"
  echo "$reduced $wall $user $sys $rss" >>"$out"
  echo "SIZE reduced $reduced, $threads thread(s): wall $wall s, CPU $(awk "BEGIN{print $user + $sys}") s, peak $((rss / 1024)) MB, load before ($load)"
done
python3 - "$out" <<'PY'
import math, sys
rows = [list(map(float, l.split())) for l in open(sys.argv[1])]
def exponent(a, b, k):
    return math.log(b[k] / a[k]) / math.log(b[0] / a[0])
cpu = lambda r: [r[0], r[1], r[2] + r[3]]
for a, b in zip(rows, rows[1:]):
    print(f"EXPONENT {a[0]:.0f} -> {b[0]:.0f}: wall N^{exponent(a, b, 1):.2f}, CPU N^{exponent(cpu(a), cpu(b), 2):.2f}")
if len(rows) > 2:
    a, b = rows[0], rows[-1]
    print(f"EXPONENT {a[0]:.0f} -> {b[0]:.0f}: wall N^{exponent(a, b, 1):.2f}, CPU N^{exponent(cpu(a), cpu(b), 2):.2f}")
PY
