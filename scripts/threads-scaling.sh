#!/usr/bin/env bash
# 1 vs 2 (or more) threads of the FEM, per phase (target: 2 threads ≥ 1.7× one on assembly and solve at 350k), this machine:
#
#   punch   `punch_scaling --level L --method iterative` (validation example; default level 3 =
#           349 558 unknowns): pattern, assembly, reduction, multigrid set-up, PCG solve;
#   strip   `static_breakdown` (static-contact example; the default scene's slider strip, direct
#           path): assembly (pattern + element matrices + reduction), METIS ordering + symbolic
#           analysis, numeric Cholesky, condensation onto the posts.
#
# Each repeat runs RAYON_NUM_THREADS=1 then =T back to back (T = --threads, default 2), so both
# see the same load; the summary keeps the minimum over the repeats of every phase, prints the
# speed-up per phase and the load average before every run.
#
# The machine's own limit: with --threads 2 each repeat also runs two one-thread processes side
# by side (skip with --no-side-by-side). Two independent copies share nothing but the hardware
# (memory bandwidth, caches, the host), so 2 × t(alone) / t(side by side) is the most any
# two-thread version of a phase can gain on this machine; the summary prints it per phase as
# `ceiling`, and the speed-up as a share of it. Bitwise check: the printed result
# (k_sn clamped for the punch, η for the strip, 17 digits) must be identical across repeats with
# the same thread count (the script fails otherwise); whether 1 and T threads agree is printed.
#
#   scripts/threads-scaling.sh [--repeats N] [--threads T] [--level L] [--no-punch] [--no-strip]
#                              [--no-side-by-side]
#
# A 2-thread speed-up is only measurable on an otherwise idle machine (load average < 1 on 2
# cores); the load is printed so that the numbers can be judged. Builds the two release examples
# first. Output: one line per run (`case threads wall_s user_s sys_s load1 phases...`), then the
# summary.
set -euo pipefail
cd "$(dirname "$0")/.."

repeats=3
threads=2
level=3
punch=1
strip=1
side=1
while [[ $# -gt 0 ]]; do
  case "$1" in
    --repeats) repeats="$2"; shift 2 ;;
    --threads) threads="$2"; shift 2 ;;
    --level) level="$2"; shift 2 ;;
    --no-punch) punch=0; shift ;;
    --no-strip) strip=0; shift ;;
    --no-side-by-side) side=0; shift ;;
    *) echo "usage: $0 [--repeats N] [--threads T] [--level L] [--no-punch] [--no-strip] [--no-side-by-side]" >&2; exit 2 ;;
  esac
done
[[ "$repeats" =~ ^[1-9][0-9]*$ ]] || { echo "error: --repeats must be a positive integer" >&2; exit 2; }
[[ "$threads" =~ ^[2-9][0-9]*$|^[1-9][0-9]+$ ]] || { echo "error: --threads must be an integer ≥ 2" >&2; exit 2; }
[[ "$level" =~ ^[0-9]+$ ]] || { echo "error: --level must be a non-negative integer" >&2; exit 2; }

cargo build --release -q -p validation --example punch_scaling
cargo build --release -q -p static-contact --example static_breakdown
bin="${CARGO_TARGET_DIR:-$PWD/target}/release/examples"
scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
log="$scratch/runs.jsonl"

if [[ $punch == 1 ]]; then
  # Mesh generated (gmsh) once, outside the timed runs.
  mesh="$("$bin/punch_scaling" --mesh-only --level "$level" | tail -1)"
fi

# record CASE THREADS LOAD SUFFIX: appends the JSON line {case, threads, load1, wall_s, user_s,
# sys_s, result} of the run whose time and output are $scratch/time$SUFFIX, $scratch/out$SUFFIX
# (THREADS a count, or "pair" for a copy run side by side).
record() {
  python3 - "$1" "$2" "$3" "$scratch/time$4" "$scratch/out$4" >>"$log" <<'EOF'
import json, sys
case, t, load, time_path, out_path = sys.argv[1:]
wall, user, sys_ = (float(x) for x in open(time_path).read().split()[-3:])
r = json.loads(open(out_path).read().strip().splitlines()[-1])
print(json.dumps({"case": case, "threads": int(t) if t.isdigit() else t, "load1": float(load),
                  "wall_s": wall, "user_s": user, "sys_s": sys_, "result": r}))
EOF
}

# one CASE THREADS CMD...: runs CMD with RAYON_NUM_THREADS=THREADS and records it.
one() {
  local case="$1" t="$2"; shift 2
  local load; load="$(cut -d' ' -f1 /proc/loadavg)"
  RAYON_NUM_THREADS="$t" /usr/bin/time -f "%e %U %S" -o "$scratch/time" "$@" >"$scratch/out" 2>"$scratch/err" || {
    echo "error: $case with $t threads failed:" >&2; tail -5 "$scratch/err" >&2; exit 1; }
  record "$case" "$t" "$load" ""
  tail -1 "$log"
}

# pair CASE CMD...: two one-thread copies of CMD side by side; records both as threads "pair".
pair() {
  local case="$1"; shift
  local load; load="$(cut -d' ' -f1 /proc/loadavg)"
  local pids=() failed=0
  for k in a b; do
    RAYON_NUM_THREADS=1 /usr/bin/time -f "%e %U %S" -o "$scratch/time.$k" "$@" >"$scratch/out.$k" 2>"$scratch/err.$k" &
    pids+=("$!")
  done
  for p in "${pids[@]}"; do wait "$p" || failed=1; done
  [[ $failed == 0 ]] || { echo "error: $case side by side failed:" >&2; tail -5 "$scratch"/err.* >&2; exit 1; }
  for k in a b; do record "$case" pair "$load" ".$k"; done
}
[[ $threads == 2 ]] || side=0

for r in $(seq 1 "$repeats"); do
  for t in 1 "$threads"; do
    if [[ $punch == 1 ]]; then one punch "$t" "$bin/punch_scaling" --method iterative "$mesh"; fi
    if [[ $strip == 1 ]]; then one strip "$t" "$bin/static_breakdown"; fi
  done
  if [[ $side == 1 ]]; then
    if [[ $punch == 1 ]]; then pair punch "$bin/punch_scaling" --method iterative "$mesh"; fi
    if [[ $strip == 1 ]]; then pair strip "$bin/static_breakdown"; fi
  fi
done >/dev/null

python3 - "$log" <<'EOF'
import json, sys
runs = [json.loads(l) for l in open(sys.argv[1])]
phases = {
    "punch": ["pattern_s", "assembly_s", "reduction_s", "symbolic_s", "numeric_s", "solve_s", "total_s"],
    "strip": ["assembly_s", "ordering_symbolic_s", "numeric_factor_s", "condensation_s", "static_total_s"],
}
value = {"punch": "k_sn_clamped_n_per_m", "strip": "effective_contact_ratio"}
for r in runs:
    print(f"# {r['case']} threads {'1+1 side by side' if r['threads'] == 'pair' else r['threads']} load {r['load1']:.2f}: wall {r['wall_s']:.2f} s, "
          f"CPU {r['user_s'] + r['sys_s']:.2f} s, " + ", ".join(
              f"{p} {r['result'][p]:.3f}" for p in phases[r['case']]) +
          f", {value[r['case']]} {r['result'][value[r['case']]]!r}")
failed = False
for case in ("punch", "strip"):
    pairs = [r for r in runs if r["case"] == case and r["threads"] == "pair"]
    mine = [r for r in runs if r["case"] == case and r["threads"] != "pair"]
    if not mine:
        continue
    counts = sorted({r["threads"] for r in mine})
    print(f"{case}: minimum over {len(mine) // len(counts)} repeats (s); speed-up = 1 thread / {counts[-1]} threads")
    if pairs:
        print("  1+1 side = one-thread copy run beside another (the pair's mean, minimum over the repeats);")
        print("  ceiling = 2 × (1 thr) / (1+1 side): the most two threads can gain on this machine")
    print(f"  {'phase':<22}" + "".join(f"{str(t) + ' thr':>10}" for t in counts) + f"{'speed-up':>10}"
          + (f"{'1+1 side':>10}{'ceiling':>10}{'share':>8}" if pairs else ""))
    def get(r, p):
        return r["user_s"] + r["sys_s"] if p == "cpu_s" else r[p] if p == "wall_s" else r["result"][p]
    for p in phases[case] + ["wall_s", "cpu_s"]:
        row = [min(get(r, p) for r in mine if r["threads"] == t) for t in counts]
        line = f"  {p:<22}" + "".join(f"{v:>10.3f}" for v in row) + f"{row[0] / row[-1]:>10.2f}"
        if pairs and p != "cpu_s":
            side = min((get(a, p) + get(b, p)) / 2 for a, b in zip(pairs[::2], pairs[1::2]))
            ceiling = 2 * row[0] / side if side > 0 else float("nan")
            line += f"{side:>10.3f}{ceiling:>10.2f}{(row[0] / row[-1]) / ceiling:>8.0%}"
        print(line)
    bits = {}
    for t in counts:
        vals = {repr(r["result"][value[case]]) for r in mine + pairs
                if r["threads"] == t or (t == 1 and r["threads"] == "pair")}
        bits[t] = vals
        if len(vals) != 1:
            failed = True
            print(f"  NOT REPRODUCIBLE: {value[case]} differs between runs with {t} threads: {sorted(vals)}")
    same = len(set().union(*bits.values())) == 1
    print(f"  {value[case]}: same bits in every run with the same thread count: "
          f"{'yes' if all(len(v) == 1 for v in bits.values()) else 'NO'}; "
          f"1 and {counts[-1]} threads give the same bits: {'yes' if same else 'no'} "
          f"({', '.join(f'{t}: {sorted(v)[0]}' for t, v in bits.items())})")
    print(f"  load average (1 min) before the runs: "
          f"{min(r['load1'] for r in mine):.2f}–{max(r['load1'] for r in mine):.2f}")
sys.exit(1 if failed else 0)
EOF
