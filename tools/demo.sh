#!/bin/sh
# demo.sh — the main job on the bundled mesh: build the augmented surface of data/demo_torus.obj,
# write its tessellation and a sample listing into demo_out/.
set -e
exe=${1:-build/quad2nurbs}
mkdir -p demo_out
"$exe" data/demo_torus.obj -o demo_out/demo_torus_tess.obj --tess 17
"$exe" sample data/demo_torus.obj --grid 5 > demo_out/demo_torus_samples.txt
echo "demo: wrote demo_out/demo_torus_tess.obj and demo_out/demo_torus_samples.txt ($(wc -l < demo_out/demo_torus_samples.txt) sample lines)"
