/* test_pair.c — q2n_mesh_pair_triangles (--pair-triangles) and what it does for a run.
 * References: a quad grid (jittered, wavy) cut along one diagonal per quad, the diagonals' directions
 * random, must come back quad for quad (the same vertices in the same cyclic order, each in the
 * place of its first triangle, with that triangle's OBJ line); shapes that must not pair (a flat
 * fan of 24 thin triangles: its pairs would be near-triangles; an octahedron: its faces 71 degrees
 * apart) and one that pairs (an icosahedron, 42 degrees) with counts that add up; a mesh of quads and
 * triangles keeps its quads; a strip whose best quad the greedy pass takes is re-paired by an augmenting
 * path.  End to end (public API): a thin lip of revolution whose quads were cut
 * into sliver triangles (aspect ~50) — through --subdivide 1 its surface folds over; paired, it is
 * the quad grid's own surface (the same patches, to rounding) and fits to its targets. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "mesh/mesh.h"
#include "quad2nurbs.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static unsigned rnd_state = 12345u;
static double rnd(void)
{
    rnd_state = rnd_state * 1103515245u + 12345u;
    return ((rnd_state >> 8) & 0xffff) / 65536.0;
}

/* an (n x m)-quad grid of a height field with jitter; quads in rows, counter-clockwise from above */
static void grid(int n, int m, double jit, double *pos, int *quads)
{
    for (int i = 0; i <= n; i++)
        for (int j = 0; j <= m; j++) {
            double *p = pos + 3 * (i * (m + 1) + j);
            p[0] = i + jit * (rnd() - 0.5);
            p[1] = 0.7 * j + jit * (rnd() - 0.5);
            p[2] = 0.3 * sin(0.9 * p[0]) * cos(1.3 * p[1]);
        }
    for (int i = 0, k = 0; i < n; i++)
        for (int j = 0; j < m; j++, k++) {
            int *q = quads + 4 * k;
            q[0] = i * (m + 1) + j, q[1] = (i + 1) * (m + 1) + j, q[2] = (i + 1) * (m + 1) + j + 1, q[3] = i * (m + 1) + j + 1;
        }
}

/* quad k cut along the diagonal from corner s (0 or 1): triangles (q_s, q_s+1, q_s+2), (q_s+2, q_s+3, q_s) */
static void cut(const int *q, int s, int *t)
{
    int a = q[s], b = q[s + 1], c = q[(s + 2) & 3], d = q[(s + 3) & 3];
    t[0] = a, t[1] = b, t[2] = c, t[3] = c, t[4] = d, t[5] = a;
}

/* the same cycle of four vertices, from any start */
static int same_cycle(const int *a, const int *b)
{
    for (int r = 0; r < 4; r++) {
        int ok = 1;
        for (int i = 0; i < 4; i++) ok &= a[i] == b[(i + r) & 3];
        if (ok) return 1;
    }
    return 0;
}

static q2n_mesh *mesh_of(int nv, const double *pos, int nf, const int *fs, const int *fv, const int *lines)
{
    q2n_mesh *m = NULL;
    q2n_error err = {0};
    q2n_status st = q2n_mesh_from_arrays_lines(nv, pos, nf, fs, fv, lines, "proc", &m, &err);
    CHECK(st == Q2N_OK, "from_arrays: %s", err.message);
    return m;
}

static q2n_mesh *paired(const q2n_mesh *m, int *np, int *left)
{
    q2n_mesh *out = NULL;
    q2n_error err = {0};
    q2n_status st = q2n_mesh_pair_triangles(m, &out, np, left, &err);
    CHECK(st == Q2N_OK, "pair: %s", err.message);
    if (out) {
        q2n_status c = q2n_mesh_check(out, &err);
        CHECK(c == Q2N_OK, "paired mesh's half-edges: %s", err.message);
    }
    return out;
}

static void test_grid_back(void)
{
    enum { N = 9, M = 7, NQ = N * M };
    double pos[3 * (N + 1) * (M + 1)];
    int quads[4 * NQ], fv[6 * NQ], fs[2 * NQ + 1], lines[2 * NQ];
    grid(N, M, 0.3, pos, quads);
    for (int k = 0; k < NQ; k++) cut(quads + 4 * k, rnd() < 0.5, fv + 6 * k);
    for (int f = 0; f <= 2 * NQ; f++) fs[f] = 3 * f;
    for (int f = 0; f < 2 * NQ; f++) lines[f] = 100 + f;
    q2n_mesh *m = mesh_of((N + 1) * (M + 1), pos, 2 * NQ, fs, fv, lines);
    int np = -1, left = -1;
    q2n_mesh *p = m ? paired(m, &np, &left) : NULL;
    CHECK(p && np == NQ && left == 0 && p->nf == NQ && p->all_quads, "grid: %d pairs, %d left (expected %d, 0)", np,
          left, NQ);
    for (int k = 0; p && k < NQ && k < p->nf; k++) {
        CHECK(same_cycle(p->face_vert + p->face_start[k], quads + 4 * k), "grid: face %d is not quad %d", k, k);
        CHECK(p->face_line[k] == 100 + 2 * k, "grid: face %d line %d (its first triangle's: %d)", k, p->face_line[k],
              100 + 2 * k);
        CHECK(p->face_vert[p->face_start[k]] == fv[6 * k], "grid: face %d starts at vertex %d, not at its first "
              "triangle's first vertex %d", k, p->face_vert[p->face_start[k]], fv[6 * k]);
    }
    q2n_mesh_free(p);
    q2n_mesh_free(m);
}

static void test_no_pairs(void)
{
    /* a flat fan of 24 triangles around a centre: two neighbours make a quad with a 165-degree corner */
    enum { F = 24 };
    double pos[3 * (F + 1)] = {0, 0, 0};
    int fv[3 * F], fs[F + 1];
    for (int k = 0; k < F; k++) {
        pos[3 * (k + 1)] = cos(2 * M_PI * k / F), pos[3 * (k + 1) + 1] = sin(2 * M_PI * k / F), pos[3 * (k + 1) + 2] = 0;
        fv[3 * k] = 0, fv[3 * k + 1] = 1 + k, fv[3 * k + 2] = 1 + (k + 1) % F;
    }
    for (int f = 0; f <= F; f++) fs[f] = 3 * f;
    q2n_mesh *m = mesh_of(F + 1, pos, F, fs, fv, NULL);
    int np = -1, left = -1;
    q2n_mesh *p = m ? paired(m, &np, &left) : NULL;
    CHECK(p && np == 0 && left == F && p->nf == F, "fan: %d pairs, %d left (expected 0, %d)", np, left, F);
    q2n_mesh_free(p);
    q2n_mesh_free(m);
    /* an octahedron: neighbouring faces 70.5 degrees apart, beyond Q2N_PAIR_MAX_BEND */
    static const double op[18] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
    static const int of[24] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
    int ofs[9];
    for (int f = 0; f <= 8; f++) ofs[f] = 3 * f;
    m = mesh_of(6, op, 8, ofs, of, NULL);
    p = m ? paired(m, &np, &left) : NULL;
    CHECK(p && np == 0 && left == 8, "octahedron: %d pairs, %d left (expected 0, 8)", np, left);
    q2n_mesh_free(p);
    q2n_mesh_free(m);
    /* an open square pyramid 0.8 high over a 2 x 2 base: both pairs of opposite triangles make convex
     * quads (121 degrees at the apex, the triangles 52 degrees apart), but taking both would leave
     * the apex two faces */
    static const double sp[15] = {0, 0, 0.8, 1, -1, 0, 1, 1, 0, -1, 1, 0, -1, -1, 0};
    static const int sf[12] = {0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1};
    int sfs[5] = {0, 3, 6, 9, 12};
    m = mesh_of(5, sp, 4, sfs, sf, NULL);
    p = m ? paired(m, &np, &left) : NULL;
    CHECK(p && np == 1 && left == 2 && p->nf == 3, "pyramid: %d pairs, %d left (expected 1, 2)", np, left);
    q2n_mesh_free(p);
    q2n_mesh_free(m);
}

/* A strip of four triangles whose middle two make the best quad (a unit square), the outer pairs
 * parallelograms (smallest sine 0.64): the greedy pass takes the square and leaves both ends alone; the
 * augmenting path end - square - end trades it for the two parallelograms. */
static void test_augmenting_path(void)
{
    static const double sp[18] = {-1.2, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 2.2, 1, 0};
    static const int sf[12] = {0, 1, 3, 1, 4, 3, 1, 2, 4, 2, 5, 4};
    int sfs[5] = {0, 3, 6, 9, 12}, np = -1, left = -1;
    q2n_mesh *m = mesh_of(6, sp, 4, sfs, sf, NULL), *p = m ? paired(m, &np, &left) : NULL;
    CHECK(p && np == 2 && left == 0 && p->all_quads, "strip: %d pairs, %d left (expected 2, 0)", np, left);
    static const int want[2][4] = {{0, 1, 4, 3}, {1, 2, 5, 4}};
    for (int k = 0; p && p->nf == 2 && k < 2; k++)
        CHECK(same_cycle(p->face_vert + p->face_start[k], want[k]), "strip: face %d is not the parallelogram", k);
    q2n_mesh_free(p);
    q2n_mesh_free(m);
}

static void test_icosahedron_and_mixed(void)
{
    /* icosahedron: faces 41.8 degrees apart, rhombi of 60/120 degrees: pairs, each triangle once */
    double t = (1 + sqrt(5)) / 2, ip[36] = {-1, t, 0, 1, t, 0, -1, -t, 0, 1, -t, 0, 0, -1, t, 0, 1, t,
                                             0, -1, -t, 0, 1, -t, t, 0, -1, t, 0, 1, -t, 0, -1, -t, 0, 1};
    static const int itri[60] = {0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2,
                                 10, 7, 6, 7, 1, 8, 3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5,
                                 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1};
    int ifs[21];
    for (int f = 0; f <= 20; f++) ifs[f] = 3 * f;
    q2n_mesh *m = mesh_of(12, ip, 20, ifs, itri, NULL);
    int np = -1, left = -1;
    q2n_mesh *p = m ? paired(m, &np, &left) : NULL;
    CHECK(p && np >= 5 && np <= 10 && left == 20 - 2 * np && p->nf == 20 - np,
          "icosahedron: %d pairs, %d left, %d faces", np, left, p ? p->nf : -1);
    q2n_mesh_free(p);
    q2n_mesh_free(m);
    /* two quads, then a quad cut in two, then one more quad: the quads stay as they were, in place */
    double pos[3 * 10];
    for (int i = 0; i < 5; i++)
        for (int j = 0; j < 2; j++) pos[3 * (2 * i + j)] = i, pos[3 * (2 * i + j) + 1] = j, pos[3 * (2 * i + j) + 2] = 0.1 * i * j;
    int fv[] = {0, 2, 3, 1, 2, 4, 5, 3, 4, 6, 7, 7, 5, 4, 6, 8, 9, 7}, fs[] = {0, 4, 8, 11, 14, 18};
    m = mesh_of(10, pos, 5, fs, fv, NULL);
    p = m ? paired(m, &np, &left) : NULL;
    CHECK(p && np == 1 && left == 0 && p->nf == 4 && p->all_quads, "mixed: %d pairs, %d left", np, left);
    static const int want[4][4] = {{0, 2, 3, 1}, {2, 4, 5, 3}, {4, 6, 7, 5}, {6, 8, 9, 7}};
    for (int k = 0; p && k < 4; k++)
        CHECK(memcmp(p->face_vert + p->face_start[k], want[k], sizeof want[k]) == 0, "mixed: face %d not in place", k);
    q2n_mesh_free(p);
    q2n_mesh_free(m);
}

/* A lip of revolution (a U-shaped profile of 5 points 0.25 wide, a quarter turn of radius 8 in 4
 * steps, ~3.1 long): quads of aspect ~25, cut along a diagonal into slivers of aspect ~50. */
enum { LA = 4, LP = 5, LNV = (LA + 1) * LP, LNQ = LA * (LP - 1) };
static void lip(double *pos, int *quads)
{
    static const double prof[LP][2] = {{0, 0}, {0.1, 0.37}, {0, 0.49}, {-0.23, 0.37}, {-0.5, 0}};
    for (int i = 0; i <= LA; i++)
        for (int j = 0; j < LP; j++) {
            double th = 0.5 * M_PI * i / LA, r = 8 + 0.5 * prof[j][0], *p = pos + 3 * (LP * i + j);
            p[0] = r * cos(th), p[1] = 0.5 * prof[j][1], p[2] = r * sin(th);
        }
    for (int i = 0, k = 0; i < LA; i++)
        for (int j = 0; j < LP - 1; j++, k++) {
            int *q = quads + 4 * k;
            q[0] = LP * i + j, q[1] = LP * (i + 1) + j, q[2] = LP * (i + 1) + j + 1, q[3] = LP * i + j + 1;
        }
}

static q2n_model *open_lip(const double *pos, const int *fv, int nf, int tri, int pair, int subdivide, char *eb)
{
    int sizes[2 * LNQ];
    for (int f = 0; f < nf; f++) sizes[f] = tri ? 3 : 4;
    q2n_options o;
    memset(&o, 0, sizeof o);
    o.pair_triangles = pair;
    o.subdivide = subdivide;
    o.threads = 1;
    o.frame = -1; /* the mesh's own frame: the fold the pairing is for (in its isotropic frame the
                     subdivided lip does not fold) */
    q2n_model *m = NULL;
    q2n_status st = q2n_open_mesh(LNV, pos, (size_t)nf, sizes, fv, &o, &m, eb, 256);
    CHECK(st == Q2N_OK, "lip (pair %d, subdivide %d): %s", pair, subdivide, eb);
    return m;
}

static void test_lip(void)
{
    double pos[3 * LNV];
    int quads[4 * LNQ], tris[6 * LNQ];
    char eb[256] = "";
    lip(pos, quads);
    for (int k = 0; k < LNQ; k++) cut(quads + 4 * k, 0, tris + 6 * k);
    q2n_model *q = open_lip(pos, quads, LNQ, 0, 0, 0, eb), *p = open_lip(pos, tris, 2 * LNQ, 1, 1, 0, eb);
    q2n_model *s = open_lip(pos, tris, 2 * LNQ, 1, 0, 1, eb);
    if (!q || !p || !s) goto done;
    /* through --subdivide 1 the needle quads fold (the warnings say so); the paired lip does not */
    int sw = 0, pw = 0;
    for (int i = 0; q2n_warning(s, i); i++) sw += strstr(q2n_warning(s, i), "folds over") != NULL;
    for (int i = 0; q2n_warning(p, i); i++) pw++;
    CHECK(sw > 0, "lip through --subdivide 1: expected its fold warning (the case pairing is for)");
    CHECK(pw == 0, "paired lip: %d warnings, the first: %s", pw, pw ? q2n_warning(p, 0) : "");
    /* the paired lip is the quad lip: the same patches, to rounding (each face may start at another
     * corner: compare the patch of face k at the corner its first triangle starts at) */
    CHECK(q2n_patch_count(p) == LNQ, "paired lip: %d patches, expected %d", q2n_patch_count(p), LNQ);
    double dmax = 0;
    for (int k = 0; k < LNQ && q2n_patch_count(p) == LNQ; k++)
        for (int a = 0; a <= 4; a++)
            for (int b = 0; b <= 4; b++) {
                double e1[9], e2[9], u = a / 4.0, v = b / 4.0;
                q2n_patch_eval(q, k, u, v, e1);
                q2n_patch_eval(p, k, u, v, e2); /* cut from corner 0: the quad starts where the grid's does */
                for (int c = 0; c < 3; c++) dmax = fmax(dmax, fabs(e1[c] - e2[c]));
            }
    CHECK(dmax <= 1e-12, "paired lip vs quad lip: patches differ by %.3g", dmax);
    if (q2n_fit(p, eb, sizeof eb) == Q2N_OK) {
        q2n_report r;
        q2n_get_report(p, &r);
        CHECK(r.tol_met && r.paired_quads == LNQ && r.triangles_left == 0 && r.spans_max <= 4,
              "paired lip fit: tol_met %d, %d pairs, %d left, %d spans", r.tol_met, r.paired_quads, r.triangles_left,
              r.spans_max);
    } else {
        CHECK(0, "paired lip fit: %s", eb);
    }
done:
    q2n_close(q);
    q2n_close(p);
    q2n_close(s);
}

int main(void)
{
    test_grid_back();
    test_no_pairs();
    test_augmenting_path();
    test_icosahedron_and_mixed();
    test_lip();
    CHECK_DONE("test_pair");
}
