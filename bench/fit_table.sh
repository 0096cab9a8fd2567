#!/bin/sh
# Prints docs/fit.md's "Measured" table: every shared mesh (non-quad ones --subdivide 1) fitted in
# G2 mode (the CLI defaults), in G1 mode (--ev-patch g1 --continuity g1) and at --tol 1e-4, one
# Markdown row per mesh; a row that misses a target ends in MISSED.  Not a test: it prints figures.
# usage: sh bench/fit_table.sh [QUAD2NURBS [OUTDIR]]   (meshes: $Q2N_SHARED_MESHES or ../shared/meshes)
bin=${1:-build/quad2nurbs}
out=${2:-build/scratch/fit_table}
meshes=${Q2N_SHARED_MESHES:-../shared/meshes}
[ -d "$meshes" ] || { echo "fit_table: $meshes: no such folder (set Q2N_SHARED_MESHES)" >&2; exit 2; }
mkdir -p "$out" || exit 1
echo "| mesh | faces | G2 mode: KB/face | cp/face median/max | max_dev | G1 (deg) | G2 | exact edges | fit s | G1 mode: KB/face | G1 (deg) | tol 1e-4: KB/face (1e-5 ÷ 1e-4) |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
for f in "$meshes"/*.obj; do
    m=$(basename "$f" .obj)
    if grep -Eq '^f( +[^ ]+){5,}|^f( +[^ ]+){3} *$' "$f"; then sub="--subdivide 1"; else sub=""; fi
    ok=1
    # shellcheck disable=SC2086
    "$bin" "$f" $sub --threads 2 -q -o "$out/$m.g2.step" -o "$out/$m.g2.json" || ok=0
    # shellcheck disable=SC2086
    "$bin" "$f" $sub --threads 2 -q --ev-patch g1 --continuity g1 -o "$out/$m.g1.step" -o "$out/$m.g1.json" || ok=0
    # shellcheck disable=SC2086
    "$bin" "$f" $sub --threads 2 -q --tol 1e-4 -o "$out/$m.t4.step" -o "$out/$m.t4.json" || ok=0
    if [ $ok = 0 ]; then echo "| $m $sub | run failed |"; continue; fi
    /usr/bin/python3 - "$out" "$m" "$m${sub:+ $sub}" <<'PY'
import json, os, sys
out, m, label = sys.argv[1:]
def rep(t): return json.load(open(f"{out}/{m}.{t}.json"))
g2, g1, t4 = rep("g2"), rep("g1"), rep("t4")
nf = g2["faces"]
def kb(t): return os.path.getsize(f"{out}/{m}.{t}.step") / 1024 / nf
met = all(d["tol_met"] and d["g1_met"] and d["g2_met"] for d in (g2, g1, t4))
cp, ge = g2["control_points_per_patch"], g2["g1_edges"]
print(f"| {label} | {nf} | {kb('g2'):.1f} | {cp['median']}/{cp['max']} | {g2['max_dev_rel']:.1e} | "
      f"{g2['g1_max_deg']:.1e} | {g2['g2_max_rel']:.1e} | {ge['exact']}/{ge['exact'] + ge['least_squares']} | "
      f"{g2['timings_s']['total']:.2f} | {kb('g1'):.1f} | {g1['g1_max_deg']:.1e} | "
      f"{kb('t4'):.1f} ({kb('g2') / kb('t4'):.2f}) |" + ("" if met else " MISSED"))
PY
done
