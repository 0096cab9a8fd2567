#!/bin/sh
# demo.sh — the main job on the bundled mesh data/demo_torus.obj (an unevenly spaced torus):
# build the augmented interpolatory surface (C2, centripetal), fit it into bi-quintic B-splines,
# write STEP, IGES, the fit report and a tessellation into demo_out/, then import the STEP with
# FreeCAD, audit its continuity and write the HTML continuity report (when FreeCAD and matplotlib
# are installed).
set -e
exe=${1:-build/quad2nurbs}
mesh=data/demo_torus.obj
mkdir -p demo_out
"$exe" "$mesh" -o demo_out/demo_torus.step -o demo_out/demo_torus.igs \
    -o demo_out/demo_torus_report.json -o demo_out/demo_torus_tess.obj --tess 17
"$exe" sample "$mesh" --grid 5 > demo_out/demo_torus_samples.txt
echo "demo: wrote demo_out/demo_torus.step, .igs, _report.json, _tess.obj, _samples.txt"
if [ -x /usr/bin/python3 ] && [ -d /usr/lib/freecad-python3/lib ]; then
    /usr/bin/python3 tools/q2n_audit.py demo_out/demo_torus.step --mesh "$mesh" --report demo_out/demo_torus_report.json --json demo_out/demo_torus_audit.json >/dev/null
    /usr/bin/python3 tools/q2n_compare.py demo_out/demo_torus_audit.json demo_out/demo_torus_report.json
    if /usr/bin/python3 -c "import matplotlib" 2>/dev/null; then
        /usr/bin/python3 tools/q2n_report.py demo_out/demo_torus.step --mesh "$mesh" \
            --json demo_out/demo_torus_report.json --samples demo_out/demo_torus_samples.txt \
            -o demo_out/demo_torus_report.html
    else
        echo "demo: matplotlib not installed (apt-get install python3-matplotlib), HTML report skipped"
    fi
else
    echo "demo: FreeCAD not installed, import audit skipped"
fi
