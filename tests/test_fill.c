/* test_fill.c — q2n_mesh_fill_ngons (--fill-ngons) and what it does for a run.
 * References, independent of fill.c's construction: counts from the ring-and-grid rule (n + a b
 * quads and (a + 1)(b + 1) new vertices for a = floor(n/4), b = n/2 - a); the valences it promises
 * (the polygon's vertices gain one face, four new vertices of valence 3, the rest 4), read from the
 * built half-edge mesh; the harmonic property (every new vertex the mean of its neighbours, found
 * by walking its fan) and the plane of a planar polygon; the face order and OBJ lines; a warped
 * polygon filled, odd ones left, a star-shaped one refused, an elongated slot given a long thin grid.
 * End to end (public API): a 40-sided cylinder with flat caps fits to its targets through every
 * vertex of the input, and the report counts the fill; a UV sphere with 24-gon poles meets its
 * targets filled, and subdivided too (which needs more than 12 refinement rounds). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "mesh/mesh.h"
#include "mesh/mesh_policy.h"
#include "meshgen.h"
#include "quad2nurbs.h"

static q2n_mesh *fill(const q2n_mesh *m, int *nfill, int *nquads, q2n_error *err)
{
    q2n_mesh *out = NULL;
    if (q2n_mesh_fill_ngons(m, &out, nfill, nquads, err)) return NULL;
    q2n_error e2;
    CHECK(q2n_mesh_check(out, &e2) == Q2N_OK, "filled mesh's half-edges: %s", e2.message);
    return out;
}

/* Largest distance of a new vertex (index >= first) from the mean of its neighbours, and how many
 * new vertices have valence 3, 4 or other. */
static double harmonic_defect(const q2n_mesh *m, int first, int val[3])
{
    double worst = 0;
    val[0] = val[1] = val[2] = 0;
    for (int v = first; v < m->nv; v++) {
        double mean[3] = {0, 0, 0};
        int n = 0;
        for (int h = 0; h < m->nh; h++) /* half-edges leaving v: their destinations are its neighbours */
            if (q2n_he_origin(m, h) == v) {
                const double *p = q2n_mesh_vpos(m, q2n_he_dest(m, h));
                for (int c = 0; c < 3; c++) mean[c] += p[c];
                n++;
            }
        val[m->valence[v] == 3 ? 0 : m->valence[v] == 4 ? 1 : 2]++;
        const double *p = q2n_mesh_vpos(m, v);
        for (int c = 0; c < 3; c++) worst = fmax(worst, fabs(mean[c] / n - p[c]));
    }
    return worst;
}

static void cylinder(int n)
{
    int rows = 2, side = n * rows;
    q2n_mesh *m = mg_ngon_cylinder(n, rows, 1.0);
    CHECK(m != NULL, "cylinder %d: generator", n);
    if (!m) return;
    int nf = -1, nq = -1, a = n / 4, b = n / 2 - a;
    q2n_error err = {0, ""};
    CHECK(q2n_mesh_fill_count(m, 0) == 2, "cylinder %d: %d faces to fill, expected 2", n, q2n_mesh_fill_count(m, 0));
    q2n_mesh *f = fill(m, &nf, &nq, &err);
    CHECK(f != NULL, "cylinder %d: %s", n, err.message);
    if (f) {
        int quads = n + a * b;
        CHECK(nf == 2 && nq == 2 * quads && f->nf == side + 2 * quads && f->nv == m->nv + 2 * (a + 1) * (b + 1) &&
                  f->all_quads,
              "cylinder %d: %d filled, %d quads, %d faces, %d vertices", n, nf, nq, f->nf, f->nv);
        /* the side is untouched: same faces, same order */
        int same = 1;
        for (int k = 0; k < side; k++)
            for (int c = 0; c < 4; c++) same &= f->face_vert[f->face_start[k] + c] == m->face_vert[m->face_start[k] + c];
        CHECK(same, "cylinder %d: the side's faces changed", n);
        /* ring quad k of the bottom cap starts at the polygon's vertex k and runs along its edge k */
        const int *o = m->face_vert + m->face_start[side];
        int ring = 1;
        for (int k = 0; k < n; k++) {
            const int *q = f->face_vert + f->face_start[side + k];
            ring &= q[0] == o[k] && q[1] == o[(k + 1) % n] && q[2] >= m->nv && q[3] >= m->nv;
        }
        CHECK(ring, "cylinder %d: the bottom cap's ring does not follow its polygon", n);
        /* the rim is regular now (two side faces and two ring quads) */
        int rim_ok = 1;
        for (int v = 0; v < m->nv; v++) rim_ok &= f->valence[v] == 4;
        int val[3];
        double d = harmonic_defect(f, m->nv, val);
        CHECK(rim_ok && val[0] == 8 && val[2] == 0, "cylinder %d: rim regular %d, new vertices of valence 3 / 4 / other: "
              "%d / %d / %d (expected 8 / rest / 0)", n, rim_ok, val[0], val[1], val[2]);
        CHECK(d <= 1e-13, "cylinder %d: a new vertex is %.3g from its neighbours' mean", n, d);
        /* each cap's fill lies in its plane: the first new vertices are the bottom cap's */
        double z = 0;
        int per = (a + 1) * (b + 1);
        for (int v = m->nv; v < f->nv; v++) z = fmax(z, fabs(q2n_mesh_vpos(f, v)[2] - (v < m->nv + per ? 0.0 : 1.0)));
        CHECK(z <= 1e-14, "cylinder %d: the fill leaves its cap's plane by %.3g", n, z);
    }
    q2n_mesh_free(f);
    q2n_mesh_free(m);
}

/* polygons on their own: a warped octagon is filled (harmonic), a heptagon and a pentagon are left
 * as they are, a twelve-pointed star is refused, naming its line */
static void single_faces(void)
{
    enum { N = 8 };
    double pos[3 * N];
    for (int k = 0; k < N; k++) {
        double t = 2 * M_PI * k / N;
        pos[3 * k] = cos(t), pos[3 * k + 1] = 0.6 * sin(t), pos[3 * k + 2] = 0.3 * cos(2 * t); /* a saddle */
    }
    int fs[2] = {0, N}, fv[N], line = 7;
    for (int k = 0; k < N; k++) fv[k] = k;
    q2n_mesh *m = NULL, *f = NULL;
    q2n_error err = {0, ""};
    CHECK(q2n_mesh_from_arrays_lines(N, pos, 1, fs, fv, &line, "oct", &m, &err) == Q2N_OK, "octagon: %s", err.message);
    int nf = 0, nq = 0, val[3];
    if (m && (f = fill(m, &nf, &nq, &err))) {
        double d = harmonic_defect(f, N, val);
        CHECK(nf == 1 && nq == 12 && f->nf == 12 && f->nv == N + 9 && d <= 1e-13 && val[0] == 4 && val[1] == 5,
              "warped octagon: %d filled, %d quads, %d faces, %d vertices, defect %.3g, valences %d / %d", nf, nq, f->nf,
              f->nv, d, val[0], val[1]);
        int lines = 1;
        for (int k = 0; k < f->nf; k++) lines &= f->face_line[k] == 7;
        CHECK(lines, "warped octagon: its quads do not keep its line");
        /* the polygon's boundary stays the mesh's boundary */
        int bnd = 0;
        for (int v = 0; v < f->nv; v++) bnd += f->vert_boundary[v];
        CHECK(bnd == N, "warped octagon: %d boundary vertices, expected %d", bnd, N);
    } else
        CHECK(0, "warped octagon: %s", err.message);
    q2n_mesh_free(f);
    q2n_mesh_free(m);

    /* a heptagon and a pentagon: odd, so left as they are */
    double pp[3 * 12];
    int fs2[3] = {0, 7, 12}, fv2[12];
    for (int k = 0; k < 12; k++) {
        int hep = k < 7, j = hep ? k : k - 7, n = hep ? 7 : 5;
        double t = 2 * M_PI * j / n;
        pp[3 * k] = cos(t) + (hep ? 0 : 3), pp[3 * k + 1] = sin(t), pp[3 * k + 2] = 0;
        fv2[k] = k;
    }
    m = f = NULL;
    CHECK(q2n_mesh_from_arrays(12, pp, 2, fs2, fv2, "odd", &m, &err) == Q2N_OK, "odd polygons: %s", err.message);
    if (m) {
        CHECK(q2n_mesh_fill_count(m, 0) == 0, "odd polygons: %d to fill", q2n_mesh_fill_count(m, 0));
        f = fill(m, &nf, &nq, &err);
        CHECK(f && nf == 0 && nq == 0 && f->nf == 2 && f->nv == 12, "odd polygons: changed (%d, %d)", nf, nq);
    }
    q2n_mesh_free(f);
    q2n_mesh_free(m);

    /* a twelve-pointed star (radii 1 and 0.3): its fill would turn against it */
    enum { S = 12 };
    double ps[3 * S];
    for (int k = 0; k < S; k++) {
        double t = 2 * M_PI * k / S, r = k % 2 ? 0.3 : 1;
        ps[3 * k] = r * cos(t), ps[3 * k + 1] = r * sin(t), ps[3 * k + 2] = 0;
    }
    int fs3[2] = {0, S}, fv3[S], line3 = 42;
    for (int k = 0; k < S; k++) fv3[k] = k;
    m = f = NULL;
    CHECK(q2n_mesh_from_arrays_lines(S, ps, 1, fs3, fv3, &line3, "star.obj", &m, &err) == Q2N_OK, "star: %s", err.message);
    if (m) {
        q2n_status st = q2n_mesh_fill_ngons(m, &f, &nf, &nq, &err);
        CHECK(st == Q2N_ERR_GEOMETRY && !f && strstr(err.message, "star.obj:42: face 0 (12 vertices)") &&
                  strstr(err.message, "--subdivide 1"),
              "star: status %d, '%s'", st, err.message);
    }
    q2n_mesh_free(f);
    q2n_mesh_free(m);
}

/* Odd polygons, paired by strips: a 21-sided cylinder of two rows has one strip of two wall quads
 * between its caps (each cap 22-sided after it, filled; the wall 44 quads; 148 faces in all); the
 * three new vertices on the crossed edges are regular and lie where the four-point rule puts them,
 * 1.9e-4 inside the unit circle (the chord's midpoint would be 1.1e-2 inside).  A pentagon beside a
 * heptagon (sharing an edge: a strip of no quads) becomes a hexagon and an octagon, both filled. */
static void odd_polygons(void)
{
    enum { N = 21, R = 2 };
    q2n_mesh *m = mg_ngon_cylinder(N, R, 1.0), *f = NULL;
    q2n_error err = {0, ""};
    int nf = 0, nq = 0;
    CHECK(m && q2n_mesh_fill_count(m, 0) == 2, "21-sided cylinder: %d to fill, expected 2", m ? q2n_mesh_fill_count(m, 0) : -1);
    if (m && (f = fill(m, &nf, &nq, &err))) {
        CHECK(f->all_quads && nf == 2 && nq == 104 && f->nf == N * R + R + 104, "21-sided cylinder: %d filled, %d quads, %d faces",
              nf, nq, f->nf);
        double worst = 0;
        int regular = 1;
        for (int v = m->nv; v < m->nv + R + 1 && v < f->nv; v++) {
            const double *p = q2n_mesh_vpos(f, v);
            worst = fmax(worst, fabs(hypot(p[0], p[1]) - 1));
            regular &= f->valence[v] == 4;
        }
        CHECK(worst < 5e-4 && regular, "21-sided cylinder: strip vertices %.3g off the circle (four-point: 1.9e-4), regular %d",
              worst, regular);
    } else
        CHECK(0, "21-sided cylinder: %s", err.message);
    q2n_mesh_free(f);
    q2n_mesh_free(m);

    /* pentagon 0 1 2 3 4 and heptagon 1 0 5 6 7 8 9 sharing the edge 0-1 */
    double pos[3 * 10] = {0, 0, 0, 1, 0, 0, 1.3, 0.9, 0, 0.5, 1.5, 0, -0.3, 0.9, 0,
                          -0.2, -0.8, 0, 0.2, -1.5, 0, 0.8, -1.6, 0, 1.2, -1.4, 0, 1.3, -0.7, 0};
    int fs[3] = {0, 5, 12}, fv[12] = {0, 1, 2, 3, 4, 1, 0, 5, 6, 7, 8, 9};
    m = f = NULL;
    CHECK(q2n_mesh_from_arrays(10, pos, 2, fs, fv, "pent-hept", &m, &err) == Q2N_OK, "pentagon and heptagon: %s", err.message);
    if (m) {
        CHECK(q2n_mesh_fill_count(m, 0) == 2, "pentagon and heptagon: %d to fill", q2n_mesh_fill_count(m, 0));
        f = fill(m, &nf, &nq, &err);
        CHECK(f && f->all_quads && nf == 2 && nq == (6 + 2) + (8 + 4), "pentagon and heptagon: %s, %d filled, %d quads",
              f ? "filled" : err.message, nf, nq);
    }
    q2n_mesh_free(f);
    q2n_mesh_free(m);
}

/* Smallest corner sine of faces first.. of f, signed by +z (the polygons here are in z = 0). */
static double min_sine_z(const q2n_mesh *f, int first)
{
    double worst = 1;
    for (int k = first; k < f->nf; k++)
        for (int c = 0; c < 4; c++) {
            const int *q = f->face_vert + f->face_start[k];
            const double *p = q2n_mesh_vpos(f, q[c]), *pn = q2n_mesh_vpos(f, q[(c + 1) % 4]),
                         *pp = q2n_mesh_vpos(f, q[(c + 3) % 4]);
            double e1[2] = {pn[0] - p[0], pn[1] - p[1]}, e2[2] = {pp[0] - p[0], pp[1] - p[1]};
            worst = fmin(worst, (e1[0] * e2[1] - e1[1] * e2[0]) / (hypot(e1[0], e1[1]) * hypot(e2[0], e2[1])));
        }
    return worst;
}

/* An elongated slot (a stadium 5 x 1, 34 vertices: 9 on each straight side, 8 on each arc): the
 * balanced 8 x 9 grid would squeeze its cells to a smallest corner sine of 0.18 (a Python prototype
 * of the same fill); the shape search takes a 3 x 14 grid (34 + 42 quads), whose corners are all
 * above a sine of 0.6.  A circle of the same count keeps the balanced grid (34 + 8 x 9 quads). */
static void slot(void)
{
    enum { N = 34 };
    for (int round = 0; round < 2; round++) {
        double pos[3 * N];
        int k = 0;
        for (int i = 0; i < 9; i++, k++) pos[3 * k] = -2 + 0.5 * i, pos[3 * k + 1] = -0.5;
        for (int i = 1; i < 9; i++, k++) pos[3 * k] = 2 + 0.5 * sin(M_PI * i / 9), pos[3 * k + 1] = -0.5 * cos(M_PI * i / 9);
        for (int i = 0; i < 9; i++, k++) pos[3 * k] = 2 - 0.5 * i, pos[3 * k + 1] = 0.5;
        for (int i = 1; i < 9; i++, k++) pos[3 * k] = -2 - 0.5 * sin(M_PI * i / 9), pos[3 * k + 1] = 0.5 * cos(M_PI * i / 9);
        for (k = 0; k < N; k++) {
            if (round) pos[3 * k] = cos(2 * M_PI * k / N), pos[3 * k + 1] = sin(2 * M_PI * k / N);
            pos[3 * k + 2] = 0;
        }
        int fs[2] = {0, N}, fv[N];
        for (k = 0; k < N; k++) fv[k] = k;
        q2n_mesh *m = NULL, *f = NULL;
        q2n_error err = {0, ""};
        int nf = 0, nq = 0;
        CHECK(q2n_mesh_from_arrays(N, pos, 1, fs, fv, "slot", &m, &err) == Q2N_OK, "slot: %s", err.message);
        if (m && (f = fill(m, &nf, &nq, &err))) {
            double sn = min_sine_z(f, 0);
            if (round)
                CHECK(nq == N + 8 * 9 && sn > 0.6, "34-gon circle: %d quads (expected %d), smallest corner sine %.3f", nq,
                      N + 72, sn);
            else
                CHECK(nq == N + 3 * 14 && sn > 0.6, "slot: %d quads (expected %d: a 3 x 14 grid), smallest corner sine %.3f",
                      nq, N + 42, sn);
        } else
            CHECK(0, "slot: %s", err.message);
        q2n_mesh_free(f);
        q2n_mesh_free(m);
    }
}

/* Larger slots (a stadium 5 x 1 sampled evenly along its perimeter): 80 sides, where every shape
 * and start is tried, and 200, where a lattice of them is tried and then its best's neighbours
 * (mesh_policy.h Q2N_FILL_SEARCH_MAX).  Until stop 38 polygons of more than 64 sides took the
 * balanced grid, which squeezes a slot's cells until they turn over (an 80-sided slot's fitted
 * surface folded on 8 faces).  Both get a thin grid whose corners all turn their way with a margin;
 * the 80-gon's fill does not depend on which vertex the polygon starts at. */
static void stadium(int N, int rot, double *pos)
{
    double per = 2 * 4 + M_PI; /* straight sides 4, half circles of radius 0.5 */
    for (int k = 0; k < N; k++) {
        double t = per * ((k + rot) % N) / N, x, y;
        if (t < 4) x = -2 + t, y = -0.5;
        else if ((t -= 4) < M_PI / 2) x = 2 + 0.5 * sin(t / 0.5), y = -0.5 * cos(t / 0.5);
        else if ((t -= M_PI / 2) < 4) x = 2 - t, y = 0.5;
        else t -= 4, x = -2 - 0.5 * sin(t / 0.5), y = 0.5 * cos(t / 0.5);
        pos[3 * k] = x, pos[3 * k + 1] = y, pos[3 * k + 2] = 0;
    }
}

static void large_slots(void)
{
    static const int sizes[] = {80, 200};
    for (int c = 0; c < 2; c++) {
        int N = sizes[c], nq0 = -1;
        double sn0 = 0;
        for (int rot = 0; rot < (N <= Q2N_FILL_SEARCH_MAX ? 2 : 1); rot++) {
            double *pos = malloc(sizeof(double) * 3 * N);
            int *fv = malloc(sizeof(int) * N), fs[2] = {0, N};
            stadium(N, rot ? 7 : 0, pos);
            for (int k = 0; k < N; k++) fv[k] = k;
            q2n_mesh *m = NULL, *f = NULL;
            q2n_error err = {0, ""};
            int nf = 0, nq = 0, balanced = N + (N / 4) * (N / 2 - N / 4), thin = N + (N / 8) * (N / 2 - N / 8);
            CHECK(q2n_mesh_from_arrays(N, pos, 1, fs, fv, "slot", &m, &err) == Q2N_OK, "slot %d: %s", N, err.message);
            if (m && (f = fill(m, &nf, &nq, &err))) {
                double sn = min_sine_z(f, 0);
                CHECK(nq < thin && sn > 0.3, "%d-gon slot: %d quads (a grid of N/8 rows: %d; balanced: %d), smallest corner "
                      "sine %.3f", N, nq, thin, balanced, sn);
                if (rot) CHECK(nq == nq0 && fabs(sn - sn0) < 1e-12, "%d-gon slot turned by 7 vertices: %d quads, sine %.15g (from "
                               "vertex 0: %d, %.15g)", N, nq, sn, nq0, sn0);
                nq0 = nq, sn0 = sn;
            } else
                CHECK(0, "slot %d: %s", N, err.message);
            q2n_mesh_free(f);
            q2n_mesh_free(m);
            free(pos), free(fv);
        }
    }
}

/* A chain of four pentagons A-B-C-D in a row (unit squares side by side, each with one more vertex
 * above its top edge), listed B, C, A, D: each pairs with a neighbour across their shared edge.
 * Paired in face order, B took C and left A and D with no partner (exit 2 through the CLI); with
 * the polygons of fewest partners first (A and D: one each) all four are filled. */
static void pentagon_chain(void)
{
    double pos[3 * 14];
    for (int i = 0; i <= 4; i++) {
        pos[3 * i] = i, pos[3 * i + 1] = 0, pos[3 * i + 2] = 0;             /* bottom: 0..4 */
        pos[3 * (5 + i)] = i, pos[3 * (5 + i) + 1] = 1, pos[3 * (5 + i) + 2] = 0; /* top: 5..9 */
    }
    for (int i = 0; i < 4; i++) pos[3 * (10 + i)] = i + 0.5, pos[3 * (10 + i) + 1] = 1.2, pos[3 * (10 + i) + 2] = 0;
    static const int col[4] = {1, 2, 0, 3}; /* B, C, A, D */
    int fv[20], fs[5] = {0, 5, 10, 15, 20};
    for (int k = 0; k < 4; k++) {
        int i = col[k], *q = fv + 5 * k;
        q[0] = i, q[1] = i + 1, q[2] = 5 + i + 1, q[3] = 10 + i, q[4] = 5 + i;
    }
    q2n_mesh *m = NULL, *f = NULL;
    q2n_error err = {0, ""};
    int nf = 0, nq = 0;
    CHECK(q2n_mesh_from_arrays(14, pos, 4, fs, fv, "chain", &m, &err) == Q2N_OK, "pentagon chain: %s", err.message);
    if (m && (f = fill(m, &nf, &nq, &err)))
        CHECK(nf == 4 && f->all_quads, "pentagon chain listed B, C, A, D: %d of 4 filled", nf);
    else
        CHECK(0, "pentagon chain: %s", err.message);
    q2n_mesh_free(f);
    q2n_mesh_free(m);
}

/* An L-shaped hexagon (a 2 x 2 square less one quadrant): no ring and grid fills a reflex corner,
 * and until stop 38 it was refused; now it is split into two quads at the reflex corner, both
 * turning its way. */
static void l_hexagon(void)
{
    static const double pos[] = {0, 0, 0, 2, 0, 0, 2, 1, 0, 1, 1, 0, 1, 2, 0, 0, 2, 0};
    static const int fv[] = {0, 1, 2, 3, 4, 5}, fs[] = {0, 6};
    q2n_mesh *m = NULL, *f = NULL;
    q2n_error err = {0, ""};
    int nf = 0, nq = 0;
    CHECK(q2n_mesh_from_arrays(6, pos, 1, fs, fv, "L", &m, &err) == Q2N_OK, "L hexagon: %s", err.message);
    if (m && (f = fill(m, &nf, &nq, &err))) {
        double sn = min_sine_z(f, 0);
        CHECK(nf == 1 && nq == 2 && f->nv == 6 && sn > 0.7, "L hexagon: %d filled with %d quads, %d vertices, smallest corner "
              "sine %.3f", nf, nq, f->nv, sn);
    } else
        CHECK(0, "L hexagon: %s", err.message);
    q2n_mesh_free(f);
    q2n_mesh_free(m);
}

/* Strongly non-convex polygons beyond the hexagon (stop 39; refused before: no ring and grid turns
 * their way): a U (8 vertices, two reflex corners), a T (8, two), an L with every side halved (12,
 * one) and a U with every side halved (16, two) are split along chords from their reflex corners
 * into even polygons (fill.c fill_poly).  Every quad turns the polygon's way (smallest corner sine
 * in the plane above 0.2), and the polygon's own vertices are kept. */
static void nonconvex(void)
{
    static const double U[] = {0, 0, 3, 0, 3, 3, 2, 3, 2, 1, 1, 1, 1, 3, 0, 3};
    static const double T[] = {0, 2, 1, 2, 1, 0, 2, 0, 2, 2, 3, 2, 3, 3, 0, 3};
    static const double L[] = {0, 0, 2, 0, 2, 1, 1, 1, 1, 2, 0, 2};
    struct { const char *name; const double *xy; int n, halve; } cases[] = {
        {"U", U, 8, 0}, {"T", T, 8, 0}, {"L, sides halved", L, 6, 1}, {"U, sides halved", U, 8, 1}};
    for (int c = 0; c < 4; c++) {
        int n = cases[c].n * (1 + cases[c].halve), fv[16], fs[2] = {0, n};
        double pos[48];
        for (int k = 0; k < cases[c].n; k++) {
            const double *a = cases[c].xy + 2 * k, *b = cases[c].xy + 2 * ((k + 1) % cases[c].n);
            for (int t = 0; t <= cases[c].halve; t++) {
                double *p = pos + 3 * (k * (1 + cases[c].halve) + t), s = t / 2.0;
                p[0] = a[0] + s * (b[0] - a[0]), p[1] = a[1] + s * (b[1] - a[1]), p[2] = 0;
            }
        }
        for (int k = 0; k < n; k++) fv[k] = k;
        q2n_mesh *m = NULL, *f = NULL;
        q2n_error err = {0, ""};
        int nf = 0, nq = 0;
        CHECK(q2n_mesh_from_arrays(n, pos, 1, fs, fv, cases[c].name, &m, &err) == Q2N_OK, "%s: %s", cases[c].name, err.message);
        if (m && (f = fill(m, &nf, &nq, &err))) {
            double sn = min_sine_z(f, 0);
            int kept = 1;
            for (int v = 0; v < n; v++) kept &= q2n_mesh_vpos(f, v)[0] == pos[3 * v] && q2n_mesh_vpos(f, v)[1] == pos[3 * v + 1];
            printf("%s: %d quads, %d vertices, smallest corner sine %.3f\n", cases[c].name, nq, f->nv, sn);
            CHECK(nf == 1 && nq == f->nf && sn > 0.2 && kept, "%s: %d filled with %d quads, smallest corner sine %.3f, vertices kept %d",
                  cases[c].name, nf, nq, sn, kept);
        } else
            CHECK(0, "%s: %s", cases[c].name, err.message);
        q2n_mesh_free(f);
        q2n_mesh_free(m);
    }
}

/* A unit cube whose faces are a 7-gon, a 5-gon, a 7-gon, a 5-gon, a hexagon and a quad (vertices
 * added at edge midpoints): the odd polygons pair across the cube's edges, and the vertex each pair
 * gets sits on a 90° edge.  The four-point rule along the polygons' boundaries put it 6 % of the
 * edge out of both faces (fill.c edge_point, before stop 38), and the fills of the flat faces
 * warped by 1.6 % of the diagonal; on planar polygons it is now projected into their planes.  Every
 * vertex of the filled mesh lies on the cube's surface (a coordinate 0 or 1) to rounding. */
static void cube_polygons(void)
{
    static const double pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 0, 1, 1, 0, 1, 0, 1, 1,
                                 1, 1, 1, 0.5, 0, 0, 0, 0.5, 0, 0.5, 1, 0, 0.5, 0, 1, 0, 0, 0.5};
    static const int fv[] = {0, 9, 2, 10, 3, 1, 8, /**/ 4, 11, 5, 7, 6, /**/ 0, 8, 1, 5, 11, 4, 12,
                             /**/ 2, 6, 7, 3, 10, /**/ 0, 12, 4, 6, 2, 9, /**/ 1, 3, 7, 5};
    static const int fs[] = {0, 7, 12, 19, 24, 30, 34};
    q2n_mesh *m = NULL, *f = NULL;
    q2n_error err = {0, ""};
    int nf = 0, nq = 0;
    CHECK(q2n_mesh_from_arrays(13, pos, 6, fs, fv, "cube567", &m, &err) == Q2N_OK, "cube567: %s", err.message);
    if (m && (f = fill(m, &nf, &nq, &err))) {
        double worst = 0;
        for (int v = 0; v < f->nv; v++) {
            const double *p = q2n_mesh_vpos(f, v);
            double d = 1;
            for (int c = 0; c < 3; c++) d = fmin(d, fmin(fabs(p[c]), fabs(p[c] - 1)));
            worst = fmax(worst, d);
        }
        CHECK(nf == 5 && worst < 1e-15, "cube567: %d polygons filled; a vertex %.3g off the cube's faces", nf, worst);
    } else
        CHECK(0, "cube567: %s", err.message);
    q2n_mesh_free(f);
    q2n_mesh_free(m);
}

/* A 40-sided cylinder with flat caps through the public API, filled: it fits to its targets, every
 * vertex of the input is interpolated (the patches of the side faces pass through their corners),
 * and the report counts what was filled. */
static void end_to_end(void)
{
    enum { N = 40, R = 2 };
    q2n_mesh *m = mg_ngon_cylinder(N, R, 1.0);
    if (!m) { CHECK(0, "cylinder: generator"); return; }
    size_t nf = (size_t)m->nf;
    int *sizes = malloc(nf * sizeof *sizes);
    for (size_t k = 0; k < nf; k++) sizes[k] = q2n_face_size(m, (int)k);
    q2n_options o;
    memset(&o, 0, sizeof o);
    o.fill_ngons = 1;
    o.threads = 1;
    q2n_model *q = NULL;
    char eb[256] = "";
    q2n_status st = q2n_open_mesh(m->nv, m->pos, nf, sizes, m->face_vert, &o, &q, eb, sizeof eb);
    CHECK(st == Q2N_OK, "cylinder, fill_ngons: %s", eb);
    if (st == Q2N_OK && (st = q2n_fit(q, eb, sizeof eb)) == Q2N_OK) {
        q2n_report r;
        q2n_get_report(q, &r);
        CHECK(r.tol_met && r.g1_met && r.g2_met && r.filled_faces == 2 && r.fill_quads == 2 * (N + 100) &&
                  r.faces == N * R + 2 * (N + 100) && r.input_faces == N * R + 2,
              "cylinder fit: tol %d g1 %d g2 %d, %d filled, %d quads, %d faces of %d", r.tol_met, r.g1_met, r.g2_met,
              r.filled_faces, r.fill_quads, r.faces, r.input_faces);
        double dmax = 0;
        for (int k = 0; k < N * R; k++)
            for (int c = 0; c < 4; c++) {
                double e[9], u = c == 1 || c == 2, v = c >= 2;
                q2n_patch_eval(q, k, u, v, e);
                const double *p = q2n_mesh_vpos(m, m->face_vert[m->face_start[k] + c]);
                for (int d = 0; d < 3; d++) dmax = fmax(dmax, fabs(e[d] - p[d]));
            }
        CHECK(dmax <= 1e-12, "cylinder: the side's corners are %.3g from the input vertices", dmax);
    } else if (st)
        CHECK(0, "cylinder fit: %s", eb);
    /* the option's range */
    o.fill_ngons = 2;
    q2n_model *bad = NULL;
    st = q2n_open_mesh(m->nv, m->pos, nf, sizes, m->face_vert, &o, &bad, eb, sizeof eb);
    CHECK(st == Q2N_ERR_ARG && strstr(eb, "fill_ngons"), "fill_ngons 2: status %d '%s'", st, eb);
    q2n_close(bad);
    q2n_close(q);
    free(sizes);
    q2n_mesh_free(m);
}

/* A UV sphere of 24 sectors and 10 rings whose poles are 24-gons, through the public API with the
 * defaults: subdivided (each pole 24 kites around a vertex of valence 24) its G2 refinement, with the
 * G2 patches glued by smoothsteps, travels around the pole one spoke per round and needs 26 rounds —
 * stopped at 12, as until stop 37, it missed the curvature target (3.0 %); glued by polynomials (the
 * default since stop 54) it meets every target in a few rounds; filled, the poles have no such
 * vertex. */
static void uv_sphere(void)
{
    q2n_mesh *m = mg_uv_ngon_sphere(24, 10);
    if (!m) { CHECK(0, "UV sphere: generator"); return; }
    size_t nf = (size_t)m->nf;
    int *sizes = malloc(nf * sizeof *sizes);
    for (size_t k = 0; k < nf; k++) sizes[k] = q2n_face_size(m, (int)k);
    static const char *const what[3] = {"subdivided", "subdivided, smoothsteps", "filled"};
    for (int c = 0; c < 3; c++) {
        int fill_it = c == 2;
        q2n_options o;
        memset(&o, 0, sizeof o);
        o.fill_ngons = fill_it;
        o.subdivide = !fill_it;
        o.ev_smooth_gluing = c == 1;
        o.threads = 2;
        q2n_model *q = NULL;
        char eb[256] = "";
        q2n_status st = q2n_open_mesh(m->nv, m->pos, nf, sizes, m->face_vert, &o, &q, eb, sizeof eb);
        if (!st) st = q2n_fit(q, eb, sizeof eb);
        CHECK(st == Q2N_OK, "UV sphere (%s): %s", what[c], eb);
        if (!st) {
            q2n_report r;
            q2n_get_report(q, &r);
            CHECK(r.tol_met && r.g1_met && r.g2_met && (c != 1 || r.rounds > 12), "UV sphere (%s): tol %d g1 %d g2 %d (%.3g), %d rounds",
                  what[c], r.dev_met, r.g1_met, r.g2_met, r.g2_max_rel, r.rounds);
            if (fill_it) CHECK(r.faces == 24 * 9 + 2 * (24 + 36), "UV sphere filled: %d faces", r.faces);
        }
        q2n_close(q);
    }
    free(sizes);
    q2n_mesh_free(m);
}

int main(void)
{
    cylinder(40);
    cylinder(12);
    cylinder(6);
    cylinder(10);
    single_faces();
    slot();
    large_slots();
    cube_polygons();
    pentagon_chain();
    l_hexagon();
    nonconvex();
    odd_polygons();
    end_to_end();
    uv_sphere();
    CHECK_DONE("test_fill");
}
