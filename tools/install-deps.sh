#!/bin/sh
# install-deps.sh — install the Debian 12 packages quad2nurbs needs, only those missing.
#   gcc, g++, make             build (C11 library and CLI; C++ only for the Ceres shim and test references)
#   libceres-dev               Ceres Solver: the least-squares fit of patches into B-splines (src/fit)
#   libosd-dev                 OpenSubdiv: Catmull-Clark limit reference in tests and the evaluation benchmark
#   libocct-*-dev              OpenCASCADE: STEP/IGES import and fitting reference in tests/benchmarks
#   freecad-python3            FreeCAD (headless): import audit of the exported STEP/IGES files (tools/)
#   strace                     a test checks that outputs are fsync'ed before the rename (skipped without it)
set -e
PKGS="gcc g++ make libceres-dev libosd-dev libocct-foundation-dev \
libocct-modeling-data-dev libocct-modeling-algorithms-dev libocct-data-exchange-dev freecad-python3 strace"
missing=""
for p in $PKGS; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -z "$missing" ]; then
    echo "install-deps: all Debian packages present"
    exit 0
fi
SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO=sudo
echo "install-deps: installing$missing"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq $missing >/dev/null
echo "install-deps: done"
