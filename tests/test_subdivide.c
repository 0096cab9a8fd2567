/* test_subdivide.c — q2n_mesh_subdivide: counts, ordering, topology and closed-form positions.
 * References: V' = V + F + E, F' = sum of face sizes, Euler characteristic and boundary loops
 * preserved; closed forms of one Catmull–Clark step on the cube [-1,1]^3 (worked by hand below);
 * a planar uniform grid is reproduced exactly at half spacing (the rules reproduce linear
 * functions, and the boundary rule (a + 6v + b)/8 fixes equally spaced collinear points);
 * single n-gons (corners fixed, edge midpoints, centroid).  Limit points (q2n_mesh_limit_points):
 * on a uniform grid carrying z = x² + y² the bicubic B-spline limit of a vertex is its z plus
 * (h²/6) Δz = z + 2/3 inside, z + 1/3 on a side (the boundary curve's (a + 4v + b)/6 along x), z at a
 * corner; the cube's corner after one step, by hand; a face that is not a quad is refused.
 * OpenSubdiv positions and limits are compared in tests/ref_subdivide.cpp. */
#include "check.h"
#include "mesh/mesh.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static q2n_mesh *from(int nv, const double *pos, int nf, const int *fs, const int *fv)
{
    q2n_mesh *m = NULL;
    q2n_error err = {0};
    q2n_status st = q2n_mesh_from_arrays(nv, pos, nf, fs, fv, "proc", &m, &err);
    CHECK(st == Q2N_OK, "from_arrays: %s", err.message);
    return m;
}

static void check_pos(const q2n_mesh *m, int v, double x, double y, double z, const char *what)
{
    const double *p = q2n_mesh_vpos(m, v);
    CHECK(fabs(p[0] - x) <= 1e-15 && fabs(p[1] - y) <= 1e-15 && fabs(p[2] - z) <= 1e-15,
          "%s (vertex %d): (%.17g %.17g %.17g), expected (%.17g %.17g %.17g)", what, v, p[0], p[1],
          p[2], x, y, z);
}

/* Cube [-1,1]^3, outward faces.  One step, by hand:
 *   face point of x = +1 face: (1,0,0)
 *   edge point of edge (1,1,1)-(1,1,-1): ((1,1,1)+(1,1,-1)+(1,0,0)+(0,1,0))/4 = (3/4, 3/4, 0)
 *   vertex (1,1,1), n = 3: F = (1/3,1/3,1/3), R = mean of (1,1,0),(1,0,1),(0,1,1) = (2/3,2/3,2/3),
 *   (F + 2R + 0 P)/3 = (5/9, 5/9, 5/9). */
static void test_cube_closed_form(void)
{
    static const double pos[] = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1,
                                 -1, -1, 1,  1, -1, 1,  1, 1, 1,  -1, 1, 1};
    static const int fs[] = {0, 4, 8, 12, 16, 20, 24};
    static const int fv[] = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4,
                             2, 3, 7, 6, 1, 2, 6, 5, 3, 0, 4, 7};
    q2n_mesh *m = from(8, pos, 6, fs, fv), *s = NULL;
    q2n_error err = {0};
    if (!m) return;
    CHECK(q2n_mesh_subdivide(m, 1, &s, &err) == Q2N_OK, "cube: %s", err.message);
    if (!s) { q2n_mesh_free(m); return; }
    CHECK(s->nv == 8 + 6 + 12 && s->nf == 24 && s->all_quads && s->n_boundary_loops == 0,
          "cube counts V %d F %d", s->nv, s->nf);
    for (int v = 0; v < 8; v++)
        check_pos(s, v, 5.0 / 9 * pos[3 * v], 5.0 / 9 * pos[3 * v + 1], 5.0 / 9 * pos[3 * v + 2],
                  "cube vertex point");
    check_pos(s, 8 + 4, 1, 0, 0, "face point of face 4 (x = +1)");
    /* edge 2-6 = (1,1,-1)-(1,1,1): find its number through the half-edges of the input */
    int e26 = -1;
    for (int h = 0; h < m->nh; h++)
        if (q2n_he_origin(m, h) == 2 && q2n_he_dest(m, h) == 6) e26 = m->he_edge[h];
    CHECK(e26 >= 0, "edge 2-6 exists");
    if (e26 >= 0) check_pos(s, 8 + 6 + e26, 0.75, 0.75, 0, "edge point of edge 2-6");
    /* all 26 vertices by symmetry: |coordinates| sorted are (5/9,5/9,5/9), (0,0,1), (0,3/4,3/4) */
    int bad = 0;
    for (int v = 0; v < s->nv; v++) {
        const double *p = q2n_mesh_vpos(s, v);
        double a[3] = {fabs(p[0]), fabs(p[1]), fabs(p[2])}, t;
        for (int i = 0; i < 2; i++)
            for (int j = 0; j < 2 - i; j++)
                if (a[j] > a[j + 1]) t = a[j], a[j] = a[j + 1], a[j + 1] = t;
        int ok = (v < 8 && fabs(a[0] - 5.0 / 9) < 1e-15 && fabs(a[2] - 5.0 / 9) < 1e-15) ||
                 (v >= 8 && v < 14 && a[1] == 0 && a[2] == 1) ||
                 (v >= 14 && a[0] == 0 && a[1] == 0.75 && a[2] == 0.75);
        bad += !ok;
    }
    CHECK(bad == 0, "cube: %d vertices off the closed form", bad);
    /* sub-quad at corner i of face f is (v_i, e_i, f, e_{i-1}) */
    int badq = 0;
    for (int f = 0; f < 6; f++)
        for (int i = 0; i < 4; i++) {
            int h = 4 * f + i, hp = 4 * f + (i + 3) % 4;
            const int *q = s->face_vert + 4 * h;
            badq += q[0] != fv[h] || q[1] != 14 + m->he_edge[h] || q[2] != 8 + f ||
                    q[3] != 14 + m->he_edge[hp];
        }
    CHECK(badq == 0, "cube: %d sub-quads not (v_i, e_i, f, e_{i-1})", badq);
    q2n_mesh_free(s);
    q2n_mesh_free(m);
}

/* Planar (n x n) grid with spacing 1: one step gives the grid with spacing 1/2 exactly. */
/* The N x N grid of unit quads on [0, N]^2 (vertex j (N + 1) + i at x = i, y = j), z = 0.5 x + 0.25 y
 * (a plane, not z = 0) or, with quadratic set, x² + y²; pos receives the positions. */
enum { N = 4 };
static q2n_mesh *grid(double pos[3 * (N + 1) * (N + 1)], int quadratic)
{
    int fs[N * N + 1], fv[4 * N * N];
    for (int j = 0; j <= N; j++)
        for (int i = 0; i <= N; i++) {
            double *p = pos + 3 * (j * (N + 1) + i);
            p[0] = i; p[1] = j; p[2] = quadratic ? (double)(i * i + j * j) : 0.5 * i + 0.25 * j;
        }
    for (int j = 0, f = 0; j < N; j++)
        for (int i = 0; i < N; i++, f++) {
            int v = j * (N + 1) + i;
            fs[f] = 4 * f;
            fv[4 * f] = v; fv[4 * f + 1] = v + 1; fv[4 * f + 2] = v + N + 2; fv[4 * f + 3] = v + N + 1;
        }
    fs[N * N] = 4 * N * N;
    return from((N + 1) * (N + 1), pos, N * N, fs, fv);
}

static void test_grid_reproduction(void)
{
    double pos[3 * (N + 1) * (N + 1)];
    q2n_mesh *m = grid(pos, 0), *s = NULL;
    q2n_error err = {0};
    if (!m) return;
    CHECK(q2n_mesh_subdivide(m, 2, &s, &err) == Q2N_OK, "grid: %s", err.message);
    if (s) {
        int M = 4 * N; /* two steps: spacing 1/4 */
        CHECK(s->nv == (M + 1) * (M + 1) && s->nf == M * M && s->n_boundary_loops == 1,
              "grid 2 steps: V %d F %d", s->nv, s->nf);
        int bad = 0, seen[(4 * N + 1) * (4 * N + 1)] = {0};
        for (int v = 0; v < s->nv; v++) {
            const double *p = q2n_mesh_vpos(s, v);
            double x = p[0] * M / N, y = p[1] * M / N;
            int i = (int)lround(x), j = (int)lround(y);
            if (fabs(x - i) > 1e-13 || fabs(y - j) > 1e-13 || i < 0 || j < 0 || i > M || j > M ||
                fabs(p[2] - (0.5 * p[0] + 0.25 * p[1])) > 1e-14 || seen[j * (M + 1) + i]++)
                bad++;
        }
        CHECK(bad == 0, "grid: %d vertices off the half-spacing lattice", bad);
        /* the old vertices keep their indices and (here) their positions */
        for (int v = 0; v < m->nv; v++)
            check_pos(s, v, pos[3 * v], pos[3 * v + 1], pos[3 * v + 2], "grid old vertex");
    }
    q2n_mesh_free(s);
    q2n_mesh_free(m);
}

/* A single n-gon: corners (valence 2) stay, edge points are midpoints, face point the centroid. */
static void test_single_ngon(void)
{
    for (int n = 3; n <= 7; n++) {
        double pos[3 * 7];
        int fs[2] = {0, n}, fv[7];
        for (int i = 0; i < n; i++) {
            pos[3 * i] = cos(2 * M_PI * i / n) + 0.1 * i;
            pos[3 * i + 1] = sin(2 * M_PI * i / n);
            pos[3 * i + 2] = 0.01 * i * i;
            fv[i] = i;
        }
        q2n_mesh *m = from(n, pos, 1, fs, fv), *s = NULL;
        q2n_error err = {0};
        if (!m) continue;
        CHECK(q2n_mesh_subdivide(m, 1, &s, &err) == Q2N_OK, "%d-gon: %s", n, err.message);
        if (s) {
            CHECK(s->nv == 2 * n + 1 && s->nf == n && s->all_quads && s->n_boundary_loops == 1,
                  "%d-gon counts V %d F %d", n, s->nv, s->nf);
            double c[3] = {0, 0, 0};
            for (int i = 0; i < n; i++) {
                check_pos(s, i, pos[3 * i], pos[3 * i + 1], pos[3 * i + 2], "n-gon corner");
                int j = (i + 1) % n;
                check_pos(s, n + 1 + i, 0.5 * (pos[3 * i] + pos[3 * j]),
                          0.5 * (pos[3 * i + 1] + pos[3 * j + 1]),
                          0.5 * (pos[3 * i + 2] + pos[3 * j + 2]), "n-gon edge midpoint");
                for (int k = 0; k < 3; k++) c[k] += pos[3 * i + k] / n;
            }
            check_pos(s, n, c[0], c[1], c[2], "n-gon centroid");
            CHECK(q2n_mesh_check(s, &err) == Q2N_OK, "%d-gon check: %s", n, err.message);
        }
        q2n_mesh_free(s);
        q2n_mesh_free(m);
    }
}

/* Boundary vertex rule on two quads side by side: the middle bottom vertex (valence 3) moves to
 * (a + 6v + b)/8 with its two boundary neighbours; the corners (valence 2) stay. */
static void test_boundary_rule(void)
{
    static const double pos[] = {0, 0, 0, 1, 0, 0.3, 2.5, 0, 0, 0, 1, 0, 1, 1, 0, 2.5, 1, 0};
    static const int fs[] = {0, 4, 8}, fv[] = {0, 1, 4, 3, 1, 2, 5, 4};
    q2n_mesh *m = from(6, pos, 2, fs, fv), *s = NULL;
    q2n_error err = {0};
    if (!m) return;
    CHECK(q2n_mesh_subdivide(m, 1, &s, &err) == Q2N_OK, "two quads: %s", err.message);
    if (s) {
        check_pos(s, 1, (0 + 6 * 1 + 2.5) / 8, 0, (6 * 0.3) / 8, "boundary vertex (a+6v+b)/8");
        check_pos(s, 0, 0, 0, 0, "corner fixed");
        check_pos(s, 5, 2.5, 1, 0, "corner fixed");
        /* interior edge 1-4: (v1 + v4 + f0 + f1)/4 */
        int e14 = -1;
        for (int h = 0; h < m->nh; h++)
            if (q2n_he_origin(m, h) == 1 && q2n_he_dest(m, h) == 4) e14 = m->he_edge[h];
        double f0[3] = {0.5, 0.5, 0.075}, f1[3] = {1.75, 0.5, 0.075};
        if (e14 >= 0)
            check_pos(s, 6 + 2 + e14, (1 + 1 + f0[0] + f1[0]) / 4, (0 + 1 + f0[1] + f1[1]) / 4,
                      (0.3 + 0 + f0[2] + f1[2]) / 4, "interior edge point");
        CHECK(e14 >= 0, "edge 1-4 exists");
    }
    q2n_mesh_free(s);
    q2n_mesh_free(m);
}

static void test_arguments(void)
{
    static const double pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    static const int fs[] = {0, 3}, fv[] = {0, 1, 2};
    q2n_mesh *m = from(3, pos, 1, fs, fv), *s = (q2n_mesh *)1;
    q2n_error err = {0};
    if (!m) return;
    CHECK(q2n_mesh_subdivide(m, -1, &s, &err) == Q2N_ERR_ARG && s == NULL, "steps -1");
    CHECK(q2n_mesh_subdivide(NULL, 1, &s, &err) == Q2N_ERR_ARG, "NULL mesh");
    CHECK(q2n_mesh_subdivide(m, 0, &s, &err) == Q2N_OK && s && s->nv == 3 && s->nf == 1 &&
          s->all_quads == 0, "steps 0 copies the mesh");
    q2n_mesh_free(s);
    q2n_mesh_free(m);
}

/* Shared meshes: counts, check, all quads after one step, Euler characteristic and boundary
 * loops preserved, sub-faces keep their parent's OBJ line. */
static void test_shared_counts(void)
{
    static const char *files[] = {"osd_catmark_cube.obj", "osd_catmark_torus.obj",
                                  "osd_catmark_tent.obj", "osd_catmark_rook.obj",
                                  "osd_catmark_xord_boundary.obj", "crane_spot_control_mesh.obj",
                                  "gismo_octtorus_hole.obj", "osd_catmark_pawn.obj"};
    for (size_t k = 0; k < sizeof files / sizeof files[0]; k++) {
        const char *path = chk_shared_mesh(files[k]);
        if (!path) continue;
        q2n_mesh *m = NULL, *s = NULL, *s2 = NULL;
        q2n_error err = {0};
        if (q2n_mesh_read_obj(path, &m, &err) != Q2N_OK) {
            CHECK(0, "%s: %s", files[k], err.message);
            continue;
        }
        CHECK(q2n_mesh_subdivide(m, 1, &s, &err) == Q2N_OK, "%s: %s", files[k], err.message);
        CHECK(q2n_mesh_subdivide(m, 2, &s2, &err) == Q2N_OK, "%s x2: %s", files[k], err.message);
        if (s && s2) {
            CHECK(s->nv == m->nv + m->nf + m->ne && s->nf == m->nh, "%s: V' %d F' %d", files[k],
                  s->nv, s->nf);
            CHECK(s->ne == 2 * m->ne + m->nh, "%s: E' %d (2E + sum of face sizes = %d)", files[k],
                  s->ne, 2 * m->ne + m->nh);
            CHECK(s->all_quads && s2->all_quads, "%s: not all quads after subdivision", files[k]);
            CHECK(q2n_mesh_check(s, &err) == Q2N_OK && q2n_mesh_check(s2, &err) == Q2N_OK,
                  "%s: check: %s", files[k], err.message);
            int chi = m->nv - m->ne + m->nf;
            CHECK(s->nv - s->ne + s->nf == chi && s2->nv - s2->ne + s2->nf == chi,
                  "%s: Euler characteristic changed", files[k]);
            CHECK(s->n_boundary_loops == m->n_boundary_loops &&
                  s2->n_boundary_loops == m->n_boundary_loops, "%s: boundary loops %d -> %d",
                  files[k], m->n_boundary_loops, s->n_boundary_loops);
            CHECK(s2->nv == s->nv + s->nf + s->ne && s2->nf == 4 * s->nf, "%s: two-step counts",
                  files[k]);
            int badline = 0;
            for (int f = 0; f < m->nf; f++)
                for (int h = m->face_start[f]; h < m->face_start[f + 1]; h++)
                    badline += s->face_line[h] != m->face_line[f] || m->face_line[f] <= 0;
            CHECK(badline == 0, "%s: %d sub-faces lost their OBJ line", files[k], badline);
            /* extraordinary interior vertices keep their valence, new vertices are regular */
            int badval = 0;
            for (int v = 0; v < s->nv; v++) {
                int expect = v < m->nv ? m->valence[v] : v < m->nv + m->nf
                             ? q2n_face_size(m, v - m->nv)
                             : (m->he_twin[m->edge_he[v - m->nv - m->nf]] < 0 ? 3 : 4);
                badval += s->valence[v] != expect;
            }
            CHECK(badval == 0, "%s: %d subdivided vertices with unexpected valence", files[k], badval);
        }
        q2n_mesh_free(s2);
        q2n_mesh_free(s);
        q2n_mesh_free(m);
    }
}

static void test_limit_points(void)
{
    double pos[3 * (N + 1) * (N + 1)];
    q2n_mesh *m = grid(pos, 1), *L = NULL;
    q2n_error err = {0};
    if (!m) return;
    CHECK(q2n_mesh_limit_points(m, &L, &err) == Q2N_OK, "grid limit points: %s", err.message);
    if (L) {
        int bad = 0;
        for (int j = 0; j <= N; j++)
            for (int i = 0; i <= N; i++) {
                int v = j * (N + 1) + i, side = i == 0 || i == N, row = j == 0 || j == N;
                double z = i * i + j * j + (side && row ? 0 : side || row ? 1.0 / 3 : 2.0 / 3);
                const double *p = q2n_mesh_vpos(L, v);
                /* on a side only the curve along it counts: x on the rows j = 0, N, y on the columns */
                if (side != row) z = i * i + j * j + 1.0 / 3;
                if (fabs(p[0] - i) > 1e-13 || fabs(p[1] - j) > 1e-13 || fabs(p[2] - z) > 1e-13) bad++;
            }
        CHECK(bad == 0, "grid limit points: %d off the B-spline limit", bad);
        CHECK(L->nf == m->nf && memcmp(L->face_vert, m->face_vert, sizeof(int) * 4 * N * N) == 0, "grid limit points: faces changed");
    }
    q2n_mesh_free(L);
    q2n_mesh_free(m);
    /* the cube [-1,1]^3 after one step: its corner (5/9, 5/9, 5/9) (valence 3) has edge neighbours
     * (3/4, 3/4, 0) and permutations, opposite vertices the face points (1, 0, 0) ...: limit
     * (9 * 5/9 + 4 * 3 * (1/2) + 1) / 24 per coordinate = (5 + 6 + 1) / 24 = 1/2 */
    static const double cp[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1}, {-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}};
    static const int cf[24] = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 2, 3, 7, 6, 1, 2, 6, 5, 0, 4, 7, 3};
    static const int cs[7] = {0, 4, 8, 12, 16, 20, 24};
    q2n_mesh *c = from(8, &cp[0][0], 6, cs, cf), *s = NULL;
    if (c && q2n_mesh_subdivide(c, 1, &s, &err) == Q2N_OK && q2n_mesh_limit_points(s, &L, &err) == Q2N_OK) {
        check_pos(L, 6, 0.5, 0.5, 0.5, "cube corner's limit point after one step");
        q2n_mesh_free(L);
    } else
        CHECK(0, "cube limit points: %s", err.message);
    /* a pentagon's interior vertex: refused, naming the face */
    static const double pp[6][3] = {{0, 0, 0}, {1, 0, 0}, {1.3, 1, 0}, {0.5, 1.6, 0}, {-0.3, 1, 0}, {0.5, 0.7, 0.1}};
    static const int pf[15] = {0, 1, 5, 1, 2, 5, 2, 3, 5, 3, 4, 5, 4, 0, 5};
    static const int ps[6] = {0, 3, 6, 9, 12, 15};
    q2n_mesh *t = from(6, &pp[0][0], 5, ps, pf);
    L = NULL;
    q2n_status st = t ? q2n_mesh_limit_points(t, &L, &err) : Q2N_OK;
    CHECK(t && st == Q2N_ERR_UNSUPPORTED && strstr(err.message, "face 0 has 3 vertices") && !L,
          "triangles around an interior vertex: %d '%s'", st, err.message);
    q2n_mesh_free(t);
    q2n_mesh_free(s);
    q2n_mesh_free(c);
}

int main(void)
{
    test_cube_closed_form();
    test_grid_reproduction();
    test_single_ngon();
    test_boundary_rule();
    test_arguments();
    test_shared_counts();
    test_limit_points();
    CHECK_DONE("test_subdivide");
}
