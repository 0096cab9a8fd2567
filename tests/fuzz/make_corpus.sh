#!/bin/sh
# make_corpus.sh OBJ_DIR MODEL_DIR — writes the seed corpus of the fuzz harnesses (generated here,
# so nothing binary is committed): small OBJ meshes covering the reader's syntax, the topology
# cases, the surface constructions (regular, extraordinary interior and boundary vertices, open
# and closed, non-quads for --subdivide) and the degenerate shapes of issue 16.  OBJ_DIR gets the
# texts (fuzz_obj); MODEL_DIR gets each text behind option bytes (fuzz_model reads the first byte:
# bits 0-1 method mod 3, bit 2 one Catmull-Clark step, bits 3-4 parametrization, 5-6 class,
# 7 G1 patches at extraordinary vertices).
set -eu
obj=${1:?usage: make_corpus.sh OBJ_DIR MODEL_DIR}
model=${2:?usage: make_corpus.sh OBJ_DIR MODEL_DIR}
mkdir -p "$obj" "$model"

seed() { # name text
    printf '%b' "$2" > "$obj/$1.obj"
}

grid() { # nx ny zexpr(awk, of i j) -> OBJ text of an (nx x ny)-quad grid
    awk -v nx="$1" -v ny="$2" "BEGIN {
        for (j = 0; j <= ny; j++) for (i = 0; i <= nx; i++) printf \"v %d %d %s\\n\", i, j, $3;
        for (j = 0; j < ny; j++) for (i = 0; i < nx; i++) {
            a = j * (nx + 1) + i + 1; printf \"f %d %d %d %d\\n\", a, a + 1, a + nx + 2, a + nx + 1 } }"
}

seed quad 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n'
grid 3 3 '0' > "$obj/grid_flat.obj"
grid 4 3 'sin(0.7 * i) * cos(0.5 * j) * 0.6' > "$obj/grid_curved.obj"
grid 2 2 '(i == 1 && j == 1) ? 0.8 : 0' > "$obj/grid_bump.obj"
cube='v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n'
cubef='f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n'
seed cube "$cube$cubef"
seed cube_jitter "v -1.1 -0.93 -1.02\nv 0.97 -1.04 -0.91\nv 1.06 0.95 -1.08\nv -0.92 1.03 -0.97\nv -1.05 -0.98 1.09\nv 1.02 -1.07 0.94\nv 0.93 1.01 1.03\nv -0.99 0.96 1.05\n$cubef"
seed cube_open "$cube"'f 1 4 3 2\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n'
awk 'BEGIN { n = 4; m = 3; for (i = 0; i < n; i++) for (j = 0; j < m; j++) {
        a = 6.2831853 * i / n; b = 6.2831853 * j / m;
        printf "v %.6f %.6f %.6f\n", (3 + cos(b)) * cos(a), (3 + cos(b)) * sin(a), sin(b) }
    for (i = 0; i < n; i++) for (j = 0; j < m; j++) {
        i1 = (i + 1) % n; j1 = (j + 1) % m;
        printf "f %d %d %d %d\n", i * m + j + 1, i1 * m + j + 1, i1 * m + j1 + 1, i * m + j1 + 1 } }' > "$obj/torus.obj"
# one interior vertex of valence 5 (a fan of quads) and a boundary vertex of valence 4 (L shape)
awk 'BEGIN { n = 5; print "v 0 0 0.3"; for (i = 0; i < 2 * n; i++) { r = (i % 2) ? 1.6 : 1;
        a = 3.14159265 * i / n; printf "v %.6f %.6f %.6f\n", r * cos(a), r * sin(a), 0.1 * (i % 3) }
    for (i = 0; i < n; i++) printf "f 1 %d %d %d\n", 2 + 2 * i, 3 + 2 * i, 2 + (2 * i + 2) % (2 * n) }' > "$obj/fan5.obj"
seed lshape 'v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\nv 0 2 0\nv 1 2 0\nf 1 2 5 4\nf 2 3 6 5\nf 4 5 8 7\n'
seed mixed 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0.5 0.2\nf 1 2 3 4\nf 2 5 3\n'
# a wavy grid cut along alternating diagonals (--pair-triangles gives its quads back) and a triangle fan
awk 'BEGIN { n = 3; for (j = 0; j <= n; j++) for (i = 0; i <= n; i++) printf "v %d %d %.4f\n", i, j, 0.3 * sin(i + 2 * j);
    for (j = 0; j < n; j++) for (i = 0; i < n; i++) { a = j * (n + 1) + i + 1; b = a + 1; c = a + n + 2; d = a + n + 1;
        if ((i + j) % 2) printf "f %d %d %d\nf %d %d %d\n", a, b, c, c, d, a;
        else printf "f %d %d %d\nf %d %d %d\n", b, c, d, d, a, b } }' > "$obj/grid_triangulated.obj"
seed fan 'v 0 0 0\nv 1 0 0\nv 0.5 0.87 0.1\nv -0.5 0.87 0\nv -1 0 0.1\nv -0.5 -0.87 0\nv 0.5 -0.87 0.1\nf 1 2 3\nf 1 3 4\nf 1 4 5\nf 1 5 6\nf 1 6 7\nf 1 7 2\n'
seed stl_ascii 'solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\nendloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex 1 1 0\nvertex 0 1 0\nvertex 0 0 0\nendloop\nendfacet\nendsolid t\n'
# a hexagonal prism with hexagon caps and a warped octagon (--fill-ngons fills them)
seed hexprism 'v 1 0 0\nv 0.5 0.87 0\nv -0.5 0.87 0\nv -1 0 0\nv -0.5 -0.87 0\nv 0.5 -0.87 0\nv 1 0 1\nv 0.5 0.87 1\nv -0.5 0.87 1\nv -1 0 1\nv -0.5 -0.87 1\nv 0.5 -0.87 1\nf 1 2 8 7\nf 2 3 9 8\nf 3 4 10 9\nf 4 5 11 10\nf 5 6 12 11\nf 6 1 7 12\nf 6 5 4 3 2 1\nf 7 8 9 10 11 12\n'
seed octagon_warped 'v 1 0 0.3\nv 0.71 0.42 0\nv 0 0.6 -0.3\nv -0.71 0.42 0\nv -1 0 0.3\nv -0.71 -0.42 0\nv 0 -0.6 -0.3\nv 0.71 -0.42 0\nf 1 2 3 4 5 6 7 8\n'
seed pentagon 'v 0 0 0\nv 2 0 0\nv 2.6 1.5 0.3\nv 1 2.5 0\nv -0.6 1.5 0.3\nf 1 2 3 4 5\n'
seed tetra 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n'
# degenerate and folded shapes (issue 16)
seed dart 'v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\nv 3 1 0\nv 0 2 0\nv 1 2 0\nv 1.3 1.3 0\nv 3 2 0\nv 0 3 0\nv 1 3 0\nv 2 3 0\nv 3 3 0\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 5 6 10 9\nf 6 7 11 10\nf 7 8 12 11\nf 9 10 14 13\nf 10 11 15 14\nf 11 12 16 15\n'
seed bowtie 'v 0 0 0\nv 2 2 0\nv 2 0 0\nv 0 1 0\nf 1 2 3 4\n'
seed tiny_edge 'v 0 0 0\nv 1 0 0\nv 1 1e-50 0\nv 0 1 0\nf 1 2 3 4\n'
seed collinear 'v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nf 1 2 3 4\n'
seed v0v2 'v 0 0 0\nv 1 0 0\nv 0 0 0\nv 0 1 0\nf 1 2 3 4\n'
seed straight 'v 0 0 0\nv 2 0 0\nv 2 2 0\nv 1 1 0\nf 1 2 3 4\n'
seed small_scale 'v 0 0 0\nv 1e-200 0 0\nv 1e-200 1e-200 3e-201\nv 0 1e-200 0\nv 2e-200 0 1e-201\nv 2e-200 1e-200 0\nf 1 2 3 4\nf 2 5 6 3\n'
seed large_scale 'v 0 0 0\nv 5e300 0 0\nv 5e300 5e300 1.5e300\nv 0 5e300 0\nv 1e301 0 5e299\nv 1e301 5e300 0\nf 1 2 3 4\nf 2 5 6 3\n'
seed far 'v 1e9 1e9 0\nv 1000000001 1e9 0\nv 1000000001 1000000001 0.5\nv 1e9 1000000001 0\nf 1 2 3 4\n'
seed huge 'v 0 0 0\nv 1e308 0 0\nv 1e308 1e308 0\nv 0 1e308 0\nf 1 2 3 4\n'
# found by fuzz_model (option byte 204): a sliver whose subdivided patches have singular points;
# the fit report's curvature jump there was NaN (and the JSON invalid)
seed sliver 'v 1e9 1e9 0\nv 1000000001 1e9 5\nv 1861769399 1000000001 0.5\nv 1e9 1000000001 0\nf 1 2 3 4\n'
# the reader's syntax and topology errors
seed syntax '# comment\r\nmtllib a.mtl\r\no obj\r\ng grp\r\nv 0 0 0 1\r\nv 0x1p0 0 0\r\nv 1 1 0 0.5 0.5 0.5\r\nv 0 1 \\\r\n 0\r\nvt 0 0\r\nvn 0 0 1\r\ns off\r\nusemtl m\r\nf 1/1/1 2/1/1 -2//1 +4\r\nl 1 2\r\n'
seed nonmanifold 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n'
seed orientation 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\nf 1 2 3 4\nf 2 3 6 5\n'
seed bowtie_vertex 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv -1 0 0\nv 0 -1 0\nf 1 2 3\nf 1 4 5\n'
seed badnum 'v 0 0 0\nv 1 x 0\nv nan 0 0\nf 1 2 0\n'

# model seeds: each text behind a few option bytes
for f in "$obj"/*.obj; do
    b=$(basename "$f" .obj)
    for o in 000 001 002 204; do   # augmented, acc3, acc-g1, augmented + subdivide + G1 EV patches
        { printf "\\$o"; cat "$f"; } > "$model/${b}_$o"
    done
done
