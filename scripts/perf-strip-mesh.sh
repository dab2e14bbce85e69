#!/usr/bin/env bash
# The strip mesh step of the default scene, cold and cached, one command:
#
#   scripts/perf-strip-mesh.sh
#
# Runs the static stage of the default scene twice into an empty mesh cache
# (static-contact's `static_breakdown` example, release): the first run meshes the strip with gmsh
# (Tet4) and raises it to Tet10 in Rust (gmsh_mesh::elevate), the second reads the cached Tet4
# file and raises it. Prints the load average, each run's `mesh_s` (mesh choice + gmsh + reading
# + elevation, s), node count and η, the whole process's wall/user/sys, and gmsh's own stage
# lines (CPU per stage) and its process CPU. gmsh runs through a wrapper named by $GMSH that logs
# its output; the real gmsh is $GMSH, else `gmsh`.
set -euo pipefail
cd "$(dirname "$0")/.."

cargo build --release -q -p static-contact --example static_breakdown
bin="$PWD/target/release/examples/static_breakdown"
scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
real_gmsh="$(command -v "${GMSH:-gmsh}")"
cat > "$scratch/gmsh" <<EOF
#!/usr/bin/env bash
set -o pipefail
/usr/bin/time -f "gmsh process: %e s wall %U user %S sys" "$real_gmsh" "\$@" 2>&1 | tee -a "$scratch/gmsh.log"
EOF
chmod +x "$scratch/gmsh"

echo "load average: $(cut -d' ' -f1-3 /proc/loadavg)"
for run in cold cached; do
  GMSH="$scratch/gmsh" SAWDRIVE_MESH_CACHE="$scratch/cache" \
    /usr/bin/time -o "$scratch/time" -f "%e s wall %U user %S sys" "$bin" > "$scratch/out.json"
  python3 - "$run" "$scratch/out.json" "$(cat "$scratch/time")" <<'EOF'
import json, sys
d = json.load(open(sys.argv[2]))
print(f"{sys.argv[1]}: mesh_s {d['mesh_s']:.3f} s, {d['nodes']} nodes, "
      f"eta {d['effective_contact_ratio']!r}; process {sys.argv[3]}")
EOF
done
grep -E "Done meshing|Done optimizing|gmsh process" "$scratch/gmsh.log" || true
ls -l "$scratch/cache"
