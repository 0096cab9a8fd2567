/* test_acc_masks.c — the Catmull–Clark path against closed forms:
 *  - Examples 1 and 2 of seed 001 (N = 6 masks M_{1,0}, M_{2,0}, M_{1,1} as printed fractions),
 *    computed by running the construction on a procedural valence-6 carpet with the identity
 *    matrix as vertex data (so the output points ARE the masks);
 *  - mask sanity: every mask sums to 1 (affine invariance), no weight outside the stencil;
 *  - a regular closed mesh (perturbed torus): ACC3 and acc-g1 equal the uniform bicubic B-spline
 *    evaluated from its basis functions (to 1e-13 x bbox);
 *  - G1: on procedural carpets (interior EVs N = 3,5,6,7,8,12,16,45; boundary EVs with 3..8 faces)
 *    and on every all-quad mesh of ../shared/meshes the unit-normal jump across every interior
 *    edge is <= 1e-10 rad at 9 Gauss points per edge, for all four strategies; ACC3 shows a
 *    jump there (so the measurement can fail).  Prints [n̂], <c_G>, <c_M> per strategy. */
#include <math.h>
#include <string.h>
#include <time.h>

#include "acc/acc.h"
#include "acc/acc_masks.h"
#include "check.h"
#include "core/vec3.h"
#include "meshgen.h"

/* ---------------------------------------------------------------- procedural carpets */

/* N sectors of 2x2 quads around vertex 0 (interior EV), or, with half != 0, N sectors spanning
 * a half plane (boundary vertex with N faces).  Vertex numbering: 0 centre, 1+k*2+(a-1) the edge
 * points at distance a on ray k, then the sector interiors.  z is perturbed by a smooth bump and
 * noise so that nothing is planar. */
static q2n_mesh *carpet(int N, int half, unsigned seed)
{
    int nrays = half ? N + 1 : N;
    int nv = 1 + 2 * nrays + 4 * N, nf = 4 * N;
    double *pos = calloc(3 * (size_t)nv, sizeof *pos);
    int *fs = malloc(((size_t)nf + 1) * sizeof *fs), *fv = malloc(4 * (size_t)nf * sizeof *fv);
    double span = half ? M_PI : 2 * M_PI;
    for (int k = 0; k < nrays; k++)
        for (int a = 1; a <= 2; a++) {
            double *p = pos + 3 * (1 + 2 * k + a - 1), ang = span * k / N;
            p[0] = a * cos(ang);
            p[1] = a * sin(ang);
        }
    int base = 1 + 2 * nrays;
    for (int k = 0; k < N; k++) {
        double a0 = span * k / N, a1 = span * (k + 1) / N;
        for (int a = 1; a <= 2; a++)
            for (int b = 1; b <= 2; b++) {
                double *p = pos + 3 * (base + 4 * k + (b - 1) * 2 + (a - 1));
                p[0] = a * cos(a0) + b * cos(a1);
                p[1] = a * sin(a0) + b * sin(a1);
            }
    }
    for (int v = 0; v < nv; v++) {
        double *p = pos + 3 * v;
        p[2] = 0.3 * sin(0.9 * p[0] + 0.4) * cos(0.7 * p[1]) + 0.05 * (2 * mg_rnd(&seed) - 1);
        p[0] += 0.03 * (2 * mg_rnd(&seed) - 1);
        p[1] += 0.03 * (2 * mg_rnd(&seed) - 1);
    }
    int f = 0;
    for (int k = 0; k < N; k++) {
        int kn = half ? k + 1 : (k + 1) % N;
#define CV(a, b) ((a) == 0 && (b) == 0 ? 0 : (b) == 0 ? 1 + 2 * k + (a) - 1 \
                  : (a) == 0 ? 1 + 2 * kn + (b) - 1 : base + 4 * k + ((b) - 1) * 2 + (a) - 1)
        for (int b = 0; b < 2; b++)
            for (int a = 0; a < 2; a++) {
                fs[f] = 4 * f;
                fv[4 * f + 0] = CV(a, b);
                fv[4 * f + 1] = CV(a + 1, b);
                fv[4 * f + 2] = CV(a + 1, b + 1);
                fv[4 * f + 3] = CV(a, b + 1);
                f++;
            }
#undef CV
    }
    fs[nf] = 4 * nf;
    q2n_mesh *m = NULL;
    q2n_error err;
    if (q2n_mesh_from_arrays(nv, pos, nf, fs, fv, "carpet", &m, &err))
        fprintf(stderr, "carpet: %s\n", err.message);
    free(pos);
    free(fs);
    free(fv);
    return m;
}

/* Masks of all patches: cp[f*36*nv + p*nv + w] = weight of vertex w in point p of face f. */
static double *masks(const q2n_mesh *m, q2n_acc_method me, q2n_acc_strategy st, int *deg)
{
    int nv = m->nv;
    double *id = calloc((size_t)nv * nv, sizeof *id), *cp = calloc((size_t)m->nf * 36 * nv, sizeof *cp);
    for (int v = 0; v < nv; v++) id[(size_t)v * nv + v] = 1;
    q2n_acc_rings r;
    q2n_error err;
    int ok = q2n_acc_rings_build(m, &r, &err) == Q2N_OK &&
             q2n_acc_control_points(m, &r, me, st, id, nv, deg, cp, &err) == Q2N_OK;
    CHECK(ok, "masks: %s", err.message);
    q2n_acc_rings_free(&r);
    free(id);
    return cp;
}

/* Check a mask (EV-local point (i,j) of sector 0 at vertex 0) against the paper's
 * [v, e_1..e_N, f_1..f_N] / den, e_1 = our e_0. */
static void check_mask(const q2n_mesh *m, const double *cp, int i, int j, const int *num, double den,
                       const char *what)
{
    int N = m->valence[0], nv = m->nv;
    q2n_acc_rings r;
    q2n_acc_rings_build(m, &r, NULL);
    int h = r.he[r.start[0]], f = m->he_face[h], c = h - m->face_start[f];
    const double *w = cp + (size_t)f * 36 * nv + (size_t)q2n_acc_local_index(c, 5, i, j) * nv;
    double expect[256] = { 0 }, sum = 0, maxd = 0;
    expect[0] = num[0] / den;
    for (int k = 0; k < N; k++) {
        int hk = r.he[r.start[0] + k];
        int e = q2n_he_dest(m, hk), fk = q2n_he_dest(m, q2n_he_next(m, hk));
        expect[e] = num[1 + k] / den;
        expect[fk] = num[1 + N + k] / den;
    }
    for (int v = 0; v < nv; v++) {
        sum += w[v];
        if (fabs(w[v] - expect[v]) > maxd) maxd = fabs(w[v] - expect[v]);
    }
    CHECK(maxd < 1e-14, "%s: max weight difference %.3g from the paper's fractions", what, maxd);
    CHECK_NEAR(sum, 1.0, 1e-14, what);
    q2n_acc_rings_free(&r);
}

static void test_examples(void)
{
    q2n_mesh *m = carpet(6, 0, 7);
    CHECK(m && m->valence[0] == 6, "valence-6 carpet");
    if (!m) return;
    int deg[64];
    double *cp = masks(m, Q2N_ACC_G1, Q2N_ACC_CS_S, deg);
    static const int m10[] = { 360, 76, 58, 22, 4, 22, 58, 19, 10, 1, 1, 10, 19 };      /* Example 1 */
    static const int m20[] = { 592, 294, 130, -8, 18, -8, 130, 79, 8, -1, -1, 8, 79 };  /* eq. (28) */
    static const int m11[] = { 5016, 1512, 1512, 258, 144, 144, 258, 604, 185, 43, -4, 43, 185 };
    check_mask(m, cp, 1, 0, m10, 660, "Example 1 M_{1,0}");
    check_mask(m, cp, 2, 0, m20, 1320, "Example 2 M_{2,0}");
    check_mask(m, cp, 1, 1, m11, 9900, "Example 2 M_{1,1}");
    /* ACC5 corner mask, eq. (1): [N^2, 4.., 1..]/(N(N+5)) */
    static const int m00[] = { 36, 4, 4, 4, 4, 4, 4, 1, 1, 1, 1, 1, 1 };
    check_mask(m, cp, 0, 0, m00, 66, "eq. (1) M_{0,0}");
    /* every point of every patch is an affine combination */
    double worst = 0;
    for (int f = 0; f < m->nf; f++)
        for (int p = 0; p < (deg[f] + 1) * (deg[f] + 1); p++) {
            double s = 0;
            for (int v = 0; v < m->nv; v++) s += cp[(size_t)f * 36 * m->nv + (size_t)p * m->nv + v];
            if (fabs(s - 1) > worst) worst = fabs(s - 1);
        }
    CHECK(worst < 1e-13, "mask sums: worst |sum-1| = %.3g", worst);
    free(cp);
    q2n_mesh_free(m);
}

/* Max weight difference between the G1 and the ACC5 mask of EV-local point (i,j) of sector 0. */
static double g1_vs_acc5(const q2n_mesh *m, const double *g1, const double *a3, int i, int j)
{
    int nv = m->nv, h = m->vert_he[0], f = m->he_face[h], c = h - m->face_start[f];
    double *e5 = malloc(36 * (size_t)nv * sizeof *e5), d = 0;
    q2n_bezier_elevate(3, 3, 5, 5, nv, a3 + (size_t)f * 36 * nv, e5);
    int q = q2n_acc_local_index(c, 5, i, j);
    for (int w = 0; w < nv; w++) d = fmax(d, fabs(e5[(size_t)q * nv + w] - g1[(size_t)f * 36 * nv + (size_t)q * nv + w]));
    free(e5);
    return d;
}

/* Remarks of §5.1 and §5.3: for N = 3 the order-1 system (5) is already satisfied by ACC5, so
 * M_{1,0} stays the ACC5 mask; for odd N with CS, M_{3,0} from (11) equals the ACC5 mask again
 * (M_{2,0} came from the same equation); for even N (projected M_{2,0}) it does not. */
static void test_remarks(void)
{
    static const int Ns[] = { 3, 5, 6 };
    for (int t = 0; t < 3; t++) {
        q2n_mesh *m = carpet(Ns[t], 0, 40 + t);
        if (!m) continue;
        int d3[64], d5[64];
        double *a3 = masks(m, Q2N_ACC_3, Q2N_ACC_CS_S, d3), *g1 = masks(m, Q2N_ACC_G1, Q2N_ACC_CS_S, d5);
        double d10 = g1_vs_acc5(m, g1, a3, 1, 0), d30 = g1_vs_acc5(m, g1, a3, 3, 0);
        if (Ns[t] == 3) CHECK(d10 < 1e-15, "N = 3: M_{1,0} differs from ACC5 by %.3g", d10);
        else CHECK(d10 > 1e-3, "N = %d: M_{1,0} should differ from ACC5 (%.3g)", Ns[t], d10);
        if (Ns[t] % 2) CHECK(d30 < 1e-15, "N = %d (CS, odd): M_{3,0} differs from ACC5 by %.3g", Ns[t], d30);
        else CHECK(d30 > 1e-4, "N = %d (CS, even): M_{3,0} should differ from ACC5 (%.3g)", Ns[t], d30);
        free(a3);
        free(g1);
        q2n_mesh_free(m);
    }
}

/* ---------------------------------------------------------------- regular closed mesh */

static void bspline_basis(double t, double b[4])
{
    double s = 1 - t;
    b[0] = s * s * s / 6;
    b[1] = (3 * t * t * t - 6 * t * t + 4) / 6;
    b[2] = (-3 * t * t * t + 3 * t * t + 3 * t + 1) / 6;
    b[3] = t * t * t / 6;
}

static void test_regular_torus(void)
{
    int n = 7, mm = 5;
    q2n_mesh *m = mg_torus(n, mm, 3.0, 1.0, 0.2, 1, 11);
    CHECK(m != NULL, "torus");
    if (!m) return;
    double diag = q2n_mesh_bbox_diag(m);
    for (int me = 0; me < 2; me++) {
        q2n_acc_options o = { (q2n_acc_method)me, Q2N_ACC_CS_S, 0 };
        q2n_surface *s = NULL;
        q2n_acc_info info;
        q2n_error err;
        q2n_status st = q2n_acc_build(m, &o, &s, &info, &err);
        CHECK(st == Q2N_OK, "torus build: %s", err.message);
        if (st != Q2N_OK) continue;
        CHECK(info.subdiv_steps == 0 && info.n_bicubic == n * mm, "torus: %d steps, %d bicubic",
              info.subdiv_steps, info.n_bicubic);
        double maxe = 0;
        for (int i = 0; i < n; i++)
            for (int j = 0; j < mm; j++)
                for (int q = 0; q < 16; q++) {
                    double u = (q % 4 + 0.37) / 4.0, v = (q / 4 + 0.21) / 4.0, bu[4], bv[4], ref[3] = { 0, 0, 0 }, e[3];
                    bspline_basis(u, bu);
                    bspline_basis(v, bv);
                    for (int a = 0; a < 4; a++)
                        for (int b = 0; b < 4; b++) {
                            int vi = ((i + a - 1 + n) % n) * mm + (j + b - 1 + mm) % mm;
                            for (int t = 0; t < 3; t++) ref[t] += bu[a] * bv[b] * m->pos[3 * vi + t];
                        }
                    q2n_surface_eval(s, i * mm + j, u, v, 0, e);
                    for (int t = 0; t < 3; t++) maxe = fmax(maxe, fabs(e[t] - ref[t]));
                }
        CHECK(maxe <= 1e-13 * diag, "%s on a regular torus: max |S - B-spline| = %.3g (diag %.3g)",
              q2n_acc_method_name(o.method), maxe, diag);
        printf("regular torus, %s: max |S - bicubic B-spline| = %.2e\n", q2n_acc_method_name(o.method), maxe);
        q2n_surface_free(s);
        q2n_acc_info_free(&info);
    }
    q2n_mesh_free(m);
}

/* ---------------------------------------------------------------- G1 */

static const char *STRAT[4] = { "ncs-s", "ncs-as", "cs-as", "cs-s" }; /* Table 1 row order */
static const q2n_acc_strategy STRAT_ID[4] = { Q2N_ACC_NCS_S, Q2N_ACC_NCS_AS, Q2N_ACC_CS_AS, Q2N_ACC_CS_S };

/* Build acc-g1 with strategy st on m, measure; returns the quality (normal_jump_max < 0 on failure). */
static q2n_acc_quality g1_quality(const q2n_mesh *m, q2n_acc_method me, q2n_acc_strategy st, int *steps)
{
    q2n_acc_quality q;
    memset(&q, 0, sizeof q);
    q.normal_jump_max = -1;
    q2n_acc_options o = { me, st, 0 };
    q2n_surface *s = NULL;
    q2n_acc_info info;
    q2n_error err;
    if (q2n_acc_build(m, &o, &s, &info, &err) != Q2N_OK) {
        CHECK(0, "build %s: %s", m->name, err.message);
        return q;
    }
    if (steps) *steps = info.subdiv_steps;
    q2n_status r = q2n_acc_quality_measure(s, q2n_acc_info_mesh(&info, m), 9, &q, &err);
    CHECK(r == Q2N_OK, "quality %s: %s", m->name, err.message);
    q2n_surface_free(s);
    q2n_acc_info_free(&info);
    return q;
}

static void test_g1_carpets(void)
{
    static const int vals[] = { 3, 5, 6, 7, 8, 12, 16, 45 };
    for (int t = 0; t < 8; t++)
        for (int half = 0; half < 2; half++) {
            int N = vals[t]; /* interior valence, or number of faces at the boundary */
            if (half && (N < 3 || N > 8)) continue;
            q2n_mesh *m = carpet(N, half, 100 + N);
            if (!m) { CHECK(0, "carpet %d", N); continue; }
            for (int s = 0; s < 4; s++) {
                q2n_acc_quality q = g1_quality(m, Q2N_ACC_G1, STRAT_ID[s], NULL);
                CHECK(q.normal_jump_max >= 0 && q.normal_jump_max <= 1e-10,
                      "%s EV %d, %s: normal jump %.3g rad", half ? "boundary" : "interior", N, STRAT[s],
                      q.normal_jump_max);
            }
            q2n_acc_quality q3 = g1_quality(m, Q2N_ACC_3, Q2N_ACC_CS_S, NULL);
            CHECK(q3.normal_jump_max > 1e-4, "%s EV %d: ACC3 should not be G1 (jump %.3g)",
                  half ? "boundary" : "interior", N, q3.normal_jump_max);
            q2n_mesh_free(m);
        }
}

static void test_g1_shared(void)
{
    static const char *files[] = {
        "osd_catmark_cube.obj", "osd_catmark_torus.obj", "osd_catmark_righthanded.obj",
        "osd_catmark_flap.obj", "osd_catmark_tent.obj", "osd_catmark_square_hedit0.obj",
        "osd_catmark_gregory_test0.obj", "osd_catmark_gregory_test1.obj",
        "osd_catmark_gregory_test6.obj", "osd_catmark_fvar_bound3.obj",
        "osd_catmark_xord_boundary.obj", "osd_catmark_helmet.obj", "osd_catmark_pawn.obj",
        "gismo_ev_valence3.obj", "gismo_ev_valence3_carpet.obj", "gismo_ev_valence5_carpet.obj",
        "gismo_ev_valence6_carpet.obj", "gismo_ev_valence7_carpet.obj", "gismo_ev_valence8_carpet.obj",
        "gismo_cube_with_boundary.obj", "gismo_octtorus.obj", "gismo_octtorus_hole.obj",
        "gismo_polycube.obj",
    };
    int n = (int)(sizeof files / sizeof *files);
    printf("\n%-32s %-6s %5s %10s %10s %10s %10s\n", "mesh (acc-g1, 9 pts/edge)", "strat", "steps",
           "[n^]", "max rad", "<c_G>", "<c_M>");
    for (int i = 0; i < n; i++) {
        const char *path = chk_shared_mesh(files[i]);
        if (!path) continue;
        q2n_mesh *m = NULL;
        q2n_error err;
        if (q2n_mesh_read_obj(path, &m, &err) != Q2N_OK) { CHECK(0, "%s", err.message); continue; }
        for (int s = 0; s < 4; s++) {
            int steps = -1;
            q2n_acc_quality q = g1_quality(m, Q2N_ACC_G1, STRAT_ID[s], &steps);
            CHECK(q.normal_jump_max >= 0 && q.normal_jump_max <= 1e-10, "%s %s: normal jump %.3g rad",
                  files[i], STRAT[s], q.normal_jump_max);
            printf("%-32s %-6s %5d %10.2e %10.2e %10.2e %10.2e\n", files[i], STRAT[s], steps,
                   q.normal_jump_l2, q.normal_jump_max, q.gauss_jump_max, q.mean_jump_max);
        }
        q2n_acc_quality q3 = g1_quality(m, Q2N_ACC_3, Q2N_ACC_CS_S, NULL);
        printf("%-32s %-6s %5s %10.2e %10.2e %10.2e %10.2e\n", files[i], "acc3", "-", q3.normal_jump_l2,
               q3.normal_jump_max, q3.gauss_jump_max, q3.mean_jump_max);
        q2n_mesh_free(m);
    }
}

/* ---------------------------------------------------------------- boundary limit tangents */

/* P, T_b, T_x at boundary vertex v read off the ACC3 corner and edge points of ring position 1:
 * E_1 = P + (cos θ T_b + sin θ T_x)/3, T_b = (e_0 - e_K)/2, θ = π/K. */
static void boundary_frame(const q2n_mesh *m, int v, double P[3], double Tb[3], double Tx[3])
{
    q2n_acc_rings r;
    q2n_acc_rings_build(m, &r, NULL);
    int K = q2n_acc_ring_size(&r, v);
    double out[12], th = M_PI / K;
    q2n_acc_corner_points(m, &r, r.he[r.start[v] + 1], m->pos, 3, out);
    memcpy(P, out, 3 * sizeof *P);
    q2n_v3_sub(Tb, q2n_mesh_vpos(m, q2n_he_dest(m, r.he[r.start[v]])), q2n_mesh_vpos(m, r.last[v]));
    q2n_v3_scale(Tb, 0.5, Tb);
    for (int t = 0; t < 3; t++) Tx[t] = (3 * (out[3 + t] - out[t]) - cos(th) * Tb[t]) / sin(th);
    q2n_acc_rings_free(&r);
}

/* The masks at a boundary vertex with K faces are left eigenvectors of the actual subdivision
 * (q2n_mesh_subdivide, checked against OpenSubdiv by the mesh tests): after one step the corner
 * point is unchanged, T_b halves and T_x scales by λ = (5 + C + sqrt((1+C)(9+C)))/16, C = cos(π/K).
 * (The Biermann et al. mask of formulas.md §1.4 fails this for K >= 3.) */
static void test_boundary_tangents(void)
{
    for (int K = 2; K <= 7; K++) {
        q2n_mesh *m = carpet(K, 1, 300 + K), *s = NULL;
        q2n_error err;
        if (!m || q2n_mesh_subdivide(m, 1, &s, &err) != Q2N_OK) {
            CHECK(0, "half carpet %d", K);
            q2n_mesh_free(m);
            continue;
        }
        double P0[3], B0[3], X0[3], P1[3], B1[3], X1[3], C = cos(M_PI / K);
        double lam = (5 + C + sqrt((1 + C) * (9 + C))) / 16;
        boundary_frame(m, 0, P0, B0, X0);
        boundary_frame(s, 0, P1, B1, X1);
        double dp = q2n_v3_dist(P0, P1), db = 0, dx = 0;
        for (int t = 0; t < 3; t++) {
            db = fmax(db, fabs(B1[t] - 0.5 * B0[t]));
            dx = fmax(dx, fabs(X1[t] - lam * X0[t]));
        }
        CHECK(dp < 1e-14 && db < 1e-14 && dx < 1e-14,
              "boundary vertex with %d faces: |dP| %.3g, |T_b' - T_b/2| %.3g, |T_x' - λ T_x| %.3g", K, dp, db, dx);
        CHECK(q2n_v3_norm(X0) > 0.1, "T_x vanishes");
        q2n_mesh_free(s);
        q2n_mesh_free(m);
    }
}

/* ---------------------------------------------------------------- distance measure */

typedef struct nbctx { const q2n_surface *s; const q2n_mesh *m; } nbctx;

/* A "limit" that returns, for face k, the centre of the patch across k's first edge (or of k
 * itself on the boundary), with its normal: its closest-point distance to the patches is 0, but
 * only if the search continues onto the neighbouring patches. */
static q2n_status neighbour_centre(void *ctx, int face, double u, double v, double p[3], double n[3])
{
    const nbctx *c = ctx;
    int t = c->m->he_twin[c->m->face_start[face]], g = t < 0 ? face : c->m->he_face[t];
    double e[9];
    (void)u; (void)v;
    q2n_status st = q2n_surface_eval(c->s, g, 0.5, 0.5, 1, e);
    memcpy(p, e, 3 * sizeof *p);
    q2n_v3_cross(n, e + 3, e + 6);
    return st;
}

static void test_distance(void)
{
    q2n_mesh *m = carpet(5, 0, 9);
    if (!m) return;
    q2n_acc_options o = { Q2N_ACC_G1, Q2N_ACC_CS_S, 0 };
    q2n_surface *s = NULL;
    q2n_error err;
    if (q2n_acc_build(m, &o, &s, NULL, &err) != Q2N_OK) { CHECK(0, "%s", err.message); q2n_mesh_free(m); return; }
    nbctx c = { s, m };
    q2n_acc_distance near, own, par;
    CHECK(q2n_acc_limit_distance(s, m, 2, neighbour_centre, &c, 1, &near, &err) == Q2N_OK, "%s", err.message);
    q2n_acc_limit_distance(s, NULL, 2, neighbour_centre, &c, 1, &own, &err);
    q2n_acc_limit_distance(s, m, 2, neighbour_centre, &c, 0, &par, &err);
    CHECK(near.geom_max < 1e-9 && near.normal_max < 1e-6, "closest point on the neighbours: %.3g, normal %.3g",
          near.geom_max, near.normal_max);
    CHECK(own.geom_max > 0.1 && par.geom_max >= own.geom_max && near.n_samples == 4 * m->nf,
          "own patch only %.3g, same (u,v) %.3g, %d samples", own.geom_max, par.geom_max, near.n_samples);
    /* exact limit samples (no external evaluator): zero on a mesh without EVs */
    q2n_mesh *t = mg_torus(6, 5, 3.0, 1.0, 0.2, 1, 5);
    q2n_surface *ts = NULL;
    q2n_acc_limit_samples ls;
    q2n_acc_distance dt;
    if (t && q2n_acc_build(t, &o, &ts, NULL, &err) == Q2N_OK && q2n_acc_limit_samples_make(t, 2, &ls, &err) == Q2N_OK) {
        CHECK(q2n_acc_limit_distance_samples(ts, t, &ls, 1, &dt, &err) == Q2N_OK, "%s", err.message);
        CHECK(dt.n_samples == ls.n && ls.n == 16 * 30 && dt.geom_max < 1e-13 && dt.normal_max < 1e-13,
              "torus: %d samples, distance %.3g, normal %.3g", dt.n_samples, dt.geom_max, dt.normal_max);
        q2n_acc_limit_samples_free(&ls);
    } else CHECK(0, "torus samples: %s", err.message);
    q2n_acc_limit_samples_free(NULL);
    q2n_surface_free(ts);
    q2n_mesh_free(t);
    q2n_surface_free(s);
    q2n_mesh_free(m);
}

/* ---------------------------------------------------------------- quality measure, closed form */

/* Two bicubic patches across the edge x = 0: the plane z = 0 (x in [-1,0]) and the paraboloid
 * z = x^2 + y^2 (x in [0,1]), y in [0,1].  Along the edge: n_B = (0,-2y,1)/sqrt(1+4y^2),
 * K_B = 4/(1+4y^2)^2, H_B = (2+4y^2)/(1+4y^2)^(3/2), so [n̂]^2 = ∫_0^1 2 - 2/sqrt(1+4y^2) dy
 * = 2 - asinh(2), and <c_G>, <c_M> are attained at the smallest 9-point Gauss node. */
static void test_quality_closed_form(void)
{
    static const double pos[] = { -1, 0, 0, 0, 0, 0, 0, 1, 0, -1, 1, 0, 1, 0, 0, 1, 1, 0 };
    static const int fs[] = { 0, 4, 8 }, fv[] = { 0, 1, 2, 3, 1, 4, 5, 2 };
    q2n_mesh *m = NULL;
    q2n_error err;
    if (q2n_mesh_from_arrays(6, pos, 2, fs, fv, "two", &m, &err) != Q2N_OK) { CHECK(0, "%s", err.message); return; }
    q2n_surface *s = q2n_surface_create(2);
    double a[48], b[48];
    static const double t2[4] = { 0, 0, 1.0 / 3, 1 }; /* Bernstein coefficients of t^2 */
    for (int j = 0; j < 4; j++)
        for (int i = 0; i < 4; i++) {
            double *pa = a + 3 * (j * 4 + i), *pb = b + 3 * (j * 4 + i);
            pa[0] = -1 + i / 3.0; pa[1] = j / 3.0; pa[2] = 0;
            pb[0] = i / 3.0; pb[1] = j / 3.0; pb[2] = t2[i] + t2[j];
        }
    q2n_surface_set_bezier(s, 0, 3, 3, a);
    q2n_surface_set_bezier(s, 1, 3, 3, b);
    q2n_acc_quality q;
    CHECK(q2n_acc_quality_measure(s, m, 9, &q, &err) == Q2N_OK, "%s", err.message);
    const double y0 = (1 - 0.9681602395076261) / 2, y8 = (1 + 0.9681602395076261) / 2; /* GL9 ends */
    CHECK(q.n_edges == 1 && q.n_points == 9, "edges %d", q.n_edges);
    /* the integral itself, and its 9-point Gauss–Legendre value (tabulated nodes and weights;
     * the rule's own error is 1.6e-9 here: poles of the integrand at y = +-i/2) */
    static const double gx[5] = { 0.0, 0.3242534234038089, 0.6133714327005904, 0.8360311073266358, 0.9681602395076261 };
    static const double gw[5] = { 0.3302393550012598, 0.3123470770400029, 0.2606106964029354, 0.1806481606948574,
                                  0.0812743883615744 };
    double gl = 0;
    for (int i = 0; i < 5; i++)
        for (int sg = -1; sg <= (i ? 1 : -1); sg += 2) {
            double y = (1 + sg * gx[i]) / 2;
            gl += gw[i] / 2 * (2 - 2 / sqrt(1 + 4 * y * y));
        }
    CHECK_NEAR(q.normal_jump_l2, sqrt(gl), 1e-14, "[n^] = 9-point rule of the closed form");
    CHECK_NEAR(q.normal_jump_l2, sqrt(2 - asinh(2.0)), 5e-9, "[n^] closed form");
    CHECK_NEAR(q.normal_jump_max, atan(2 * y8), 1e-14, "max normal angle");
    CHECK_NEAR(q.gauss_jump_max, 4 / pow(1 + 4 * y0 * y0, 2), 1e-13, "<c_G>");
    CHECK_NEAR(q.mean_jump_max, (2 + 4 * y0 * y0) / pow(1 + 4 * y0 * y0, 1.5), 1e-13, "<c_M>");
    q2n_surface_free(s);
    q2n_mesh_free(m);
}

/* ---------------------------------------------------------------- API: preparation, options */

static void test_api(void)
{
    /* closed pyramid: one quad + four triangles -> needs a Catmull–Clark step */
    static const double pos[] = { 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5, 0.5, 0.8 };
    static const int fs[] = { 0, 4, 7, 10, 13, 16 };
    static const int fv[] = { 0, 3, 2, 1, 0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4 };
    q2n_mesh *m = NULL;
    q2n_error err;
    CHECK(q2n_mesh_from_arrays(5, pos, 5, fs, fv, "pyramid", &m, &err) == Q2N_OK, "pyramid: %s", err.message);
    if (!m) return;
    for (int me = 0; me < 2; me++) {
        q2n_acc_options o = { (q2n_acc_method)me, Q2N_ACC_CS_S, 0 };
        q2n_surface *s = NULL;
        q2n_acc_info info;
        q2n_status st = q2n_acc_build(m, &o, &s, &info, &err);
        CHECK(st == Q2N_OK, "pyramid %s: %s", q2n_acc_method_name(o.method), err.message);
        if (st != Q2N_OK) continue;
        const q2n_mesh *bm = q2n_acc_info_mesh(&info, m);
        /* one step makes quads; acc-g1 needs a second one (the apex and base corners are EVs
         * sharing faces after one step) */
        CHECK(info.subdiv_steps == (me ? 2 : 1) && info.mesh && bm->all_quads,
              "pyramid %s: %d steps", q2n_acc_method_name(o.method), info.subdiv_steps);
        CHECK(q2n_surface_npatches(s) == bm->nf && info.n_patches == bm->nf, "patch count");
        CHECK(strstr(info.reason, "face 1 has 3 vertices") == info.reason &&
                  (me == 0 || strstr(info.reason, "; then face 4 of the 1-step mesh has two or more EVs")),
              "reason: '%s'", info.reason);
        char line[512];
        q2n_acc_describe(&info, &o, line, sizeof line);
        CHECK(strstr(line, "Catmull-Clark step") && strstr(line, "subdivided mesh") && strlen(line) < 256,
              "describe: %s", line);
        printf("%s\n", line);
        q2n_surface_free(s);
        q2n_acc_info_free(&info);
        q2n_acc_info_free(&info); /* idempotent */
    }
    q2n_acc_options none = { Q2N_ACC_3, Q2N_ACC_CS_S, -1 };
    q2n_surface *s = NULL;
    CHECK(q2n_acc_build(m, &none, &s, NULL, &err) == Q2N_ERR_UNSUPPORTED && s == NULL &&
          strstr(err.message, "pyramid: face 1 has 3 vertices"), "no subdivision allowed: %s", err.message);
    double lim[15];
    CHECK(q2n_acc_limit_points(m, lim, NULL, &err) == Q2N_ERR_UNSUPPORTED, "limit points on triangles");
    q2n_acc_options bad = { (q2n_acc_method)7, Q2N_ACC_CS_S, 0 };
    CHECK(q2n_acc_build(m, &bad, &s, NULL, &err) == Q2N_ERR_ARG, "bad method accepted");
    q2n_mesh_free(m);
    q2n_acc_info_free(NULL);

    /* option names round trip */
    for (int i = 0; i < 2; i++) {
        q2n_acc_method me;
        CHECK(q2n_acc_parse_method(q2n_acc_method_name((q2n_acc_method)i), &me, &err) == Q2N_OK && (int)me == i,
              "method %d", i);
    }
    for (int i = 0; i < 4; i++) {
        q2n_acc_strategy st;
        CHECK(q2n_acc_parse_strategy(q2n_acc_strategy_name((q2n_acc_strategy)i), &st, &err) == Q2N_OK &&
                  (int)st == i, "strategy %d", i);
    }
    q2n_acc_method me;
    q2n_acc_strategy st;
    CHECK(q2n_acc_parse_method("acc5", &me, &err) == Q2N_ERR_ARG && strstr(err.message, "acc5"), "bad method");
    CHECK(q2n_acc_parse_strategy("cs", &st, &err) == Q2N_ERR_ARG && strstr(err.message, "cs-s"), "bad strategy");

    /* acc-g1 keeps the ACC3 bicubic patches on faces without EVs, and its biquintic patches
     * away from the EV edges are the degree-elevated ACC3 points (rows/columns 4, 5) */
    q2n_mesh *c = carpet(5, 0, 77);
    if (!c) return;
    int d3[32], d5[32];
    double *m3 = masks(c, Q2N_ACC_3, Q2N_ACC_CS_S, d3), *m5 = masks(c, Q2N_ACC_G1, Q2N_ACC_CS_S, d5);
    int same = 0, quint = 0;
    double worst = 0;
    for (int f = 0; f < c->nf; f++) {
        size_t blk = 36 * (size_t)c->nv;
        if (d5[f] == 3) {
            same += memcmp(m3 + f * blk, m5 + f * blk, 16 * (size_t)c->nv * sizeof(double)) == 0;
            continue;
        }
        quint++;
        double e5[36 * 64];
        if (c->nv > 64) continue;
        q2n_bezier_elevate(3, 3, 5, 5, c->nv, m3 + f * blk, e5);
        int cv = -1;
        for (int k = 0; k < 4; k++) if (c->face_vert[c->face_start[f] + k] == 0) cv = k;
        for (int j = 0; j < 6; j++)
            for (int i = 0; i < 6; i++) {
                if (i < 4 && j < 4) continue; /* the G1 construction changes only points with i,j <= 3 */
                int q = q2n_acc_local_index(cv, 5, i, j);
                for (int w = 0; w < c->nv; w++)
                    worst = fmax(worst, fabs(e5[q * c->nv + w] - m5[f * blk + (size_t)q * c->nv + w]));
            }
    }
    CHECK(quint == 5 && same == c->nf - 5, "carpet 5: %d biquintic, %d identical bicubic", quint, same);
    CHECK(worst < 1e-15, "ACC5 points away from the EV edges changed by %.3g", worst);
    free(m3);
    free(m5);
    q2n_mesh_free(c);
}

int main(void)
{
    clock_t t0 = clock();
    (void)mg_grid;
    test_examples();
    test_api();
    test_remarks();
    test_distance();
    test_quality_closed_form();
    test_regular_torus();
    test_boundary_tangents();
    test_g1_carpets();
    test_g1_shared();
    printf("test_acc_masks: %.2f s CPU\n", (double)(clock() - t0) / CLOCKS_PER_SEC);
    CHECK_DONE("test_acc_masks");
}
