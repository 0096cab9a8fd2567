#!/bin/sh
# install-deps.sh — install the Debian 12 packages quad2nurbs needs, only those missing.
#   gcc, g++, make             build (C11 library and CLI; C++ only for the Ceres shim and test references)
#   libceres-dev               Ceres Solver: the least-squares fit of patches into B-splines (src/fit)
#   liblapack-dev, libblas-dev LAPACK: the fit's null-space form of exact gluing constraints and its
#                              direct reference solver (src/core/dense.c); BLAS: the fair construction's
#                              energy blocks (src/patch/ev_fair.c)
#   libsuitesparse-dev         CHOLMOD: the fair construction's sparse energy solve (src/core/sparse.c)
#   libosd-dev                 OpenSubdiv: Catmull-Clark limit reference in tests and the evaluation benchmark
#   libocct-*-dev              OpenCASCADE: STEP/IGES import and fitting reference in tests/benchmarks
#   freecad-python3            FreeCAD (headless): import audit of the exported STEP/IGES files (tools/)
#   python3-numpy              vectorised evaluation of the imported B-spline faces (tools/q2n_nurbs.py)
#   python3-matplotlib         the pictures of the HTML continuity report (tools/q2n_report.py)
#   python3-pil                PNG decoding in the report's test (matplotlib depends on it anyway)
#   chromium                   headless browser: the report's test renders the page and screenshots it
#   strace                     a test checks that outputs are fsync'ed before the rename (skipped without it)
#   clang, libclang-rt-14-dev  libFuzzer with ASan/UBSan: make fuzz / fuzz-check (run by make check-full)
#   pkgconf                    pkg-config: tests/test_install.c builds the example against `make install`
set -e
PKGS="gcc g++ make libceres-dev liblapack-dev libblas-dev libsuitesparse-dev libosd-dev libocct-foundation-dev \
libocct-modeling-data-dev libocct-modeling-algorithms-dev libocct-data-exchange-dev freecad-python3 \
python3-numpy python3-matplotlib python3-pil chromium strace clang libclang-rt-14-dev pkgconf"
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
