/* test_frame.c — the isotropic frame (docs/extraordinary.md, "The isotropic frame"):
 *   - q2n_mesh_isotropic_frame: 1 on a symmetric isotropic mesh; on its image under a known linear map
 *     S (a stretch along a rotated axis) the estimate undoes S up to a rotation (A S orthogonal up to
 *     scale), a flat mesh keeps its normal direction;
 *   - q2n_surface_map_linear: every evaluation path of a mapped surface is L times the unmapped one;
 *   - q2n_surface_fairness against closed forms on a paraboloid patch (the mean curvature along its
 *     diagonals, the diagonals' arc length) and against a fine independent quadrature of its energy;
 *   - the model: on a stretched mesh with extraordinary vertices the surface is built in the frame
 *     and mapped back — every vertex interpolated, smoother and of less energy by tests/fairness.h's
 *     independent figures (129 samples a diagonal, 12 x 12 Gauss points a face) than the build in the
 *     mesh's own frame; an isotropic mesh is built once, as with --frame off;
 *   - the extraordinary regions alone in the frame (stop 53): q2n_augmented_map_points makes every
 *     regular patch L times what it was; the regions built in the frame against the mesh's own regular
 *     patches mapped there, then mapped back, keep those patches (to rounding), interpolate every vertex
 *     and are G1 and G2 across every edge (normals and mean curvature from both sides); on shared meshes
 *     stretched along an axis whose regular region gets rougher in the frame (the helmet 8 x, the pawn
 *     4 x) the model keeps that build, smoother than its own frame's. */
#include "check.h"
#include "fairness.h"
#include "meshgen.h"

#include "api/model.h"
#include "param/param.h"
#include "patch/augmented.h"
#include "patch/extraordinary.h"
#include "core/vec3.h"
#include "mesh/mesh.h"
#include "patch/fairness.h"
#include "patch/surface.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void mat_mul(const double A[3][3], const double B[3][3], double C[3][3])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) C[i][j] = A[i][0] * B[0][j] + A[i][1] * B[1][j] + A[i][2] * B[2][j];
}

/* Condition number of M^T M's square root (M's singular values' ratio), by the power method on
 * M^T M and on its inverse through the closed-form 3 x 3 inverse. */
static double cond3(const double M[3][3])
{
    double T[3][3], Mt[3][3], Ti[3][3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) Mt[i][j] = M[j][i];
    mat_mul(Mt, M, T);
    double det = T[0][0] * (T[1][1] * T[2][2] - T[1][2] * T[2][1]) - T[0][1] * (T[1][0] * T[2][2] - T[1][2] * T[2][0]) +
                 T[0][2] * (T[1][0] * T[2][1] - T[1][1] * T[2][0]);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            int a = (j + 1) % 3, b = (j + 2) % 3, c = (i + 1) % 3, d = (i + 2) % 3;
            Ti[i][j] = (T[a][c] * T[b][d] - T[a][d] * T[b][c]) / det;
        }
    double hi = 0, lo = 0;
    for (int pass = 0; pass < 2; pass++) {
        const double(*P)[3] = pass ? (const double(*)[3])Ti : (const double(*)[3])T;
        double x[3] = {1, 0.7, 0.3}, l = 0;
        for (int it = 0; it < 500; it++) {
            double y[3] = {0, 0, 0};
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++) y[i] += P[i][j] * x[j];
            l = sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
            for (int i = 0; i < 3; i++) x[i] = y[i] / l;
        }
        if (pass) lo = 1 / l;
        else hi = l;
    }
    return sqrt(hi / lo);
}

static q2n_mesh *mapped(q2n_mesh *m, const double S[3][3])
{
    q2n_mesh *o = NULL;
    q2n_error err;
    CHECK(q2n_mesh_mapped(m, S, &o, &err) == Q2N_OK, "q2n_mesh_mapped: %s", err.message);
    q2n_mesh_free(m);
    return o;
}

/* A rotation about (1, 2, 3) by 0.7 rad, times a stretch by s along x. */
static void rotated_stretch(double s, double S[3][3])
{
    double k[3] = {1, 2, 3}, l = sqrt(14), a = 0.7, R[3][3], D[3][3] = {{s, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int i = 0; i < 3; i++) k[i] /= l;
    double K[3][3] = {{0, -k[2], k[1]}, {k[2], 0, -k[0]}, {-k[1], k[0], 0}};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double K2 = 0;
            for (int q = 0; q < 3; q++) K2 += K[i][q] * K[q][j];
            R[i][j] = (i == j) + sin(a) * K[i][j] + (1 - cos(a)) * K2;
        }
    mat_mul(R, D, S);
}

static void test_estimate(void)
{
    double A[3][3], Ai[3][3], S[3][3], AS[3][3], P[3][3];
    /* the icosahedron's triangles split into quads, on the unit sphere: its symmetry makes any
     * estimate a multiple of the identity */
    q2n_mesh *m = mg_icosa_quad(0, 1);
    double st = q2n_mesh_isotropic_frame(m, A, Ai);
    CHECK_NEAR(st, 1, 1e-9, "icosahedral mesh: no stretch");
    for (int s = 0; s < 3; s++) { /* stretched along a rotated axis: A undoes it up to a rotation */
        double sx[3] = {2, 3, 8};
        rotated_stretch(sx[s], S);
        q2n_mesh *ms = mapped(mg_icosa_quad(0, 1), S);
        st = q2n_mesh_isotropic_frame(ms, A, Ai);
        mat_mul(A, S, AS);
        mat_mul(A, Ai, P);
        char what[96];
        snprintf(what, sizeof what, "stretch %g: the estimate's stretch", sx[s]);
        /* exact but for the tangent projection (the sphere's fans are not planar) and the ridge */
        CHECK(fabs(st / sx[s] - 1) < 0.01 * sx[s] / 2, "%s: %.6g", what, st);
        CHECK(cond3(AS) < 1 + 0.01 * sx[s] / 2, "stretch %g: A S is a rotation times a scale (condition %.6g)", sx[s], cond3(AS));
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) CHECK_NEAR(P[i][j], i == j, 1e-12, "A times its inverse");
        q2n_mesh_free(ms);
    }
    q2n_mesh_free(m);

    /* a flat grid of squares stretched 2 x along x: the stretch is found in the plane, the normal
     * direction (which no equation sees) stays where it was */
    int n = 6, nv = (n + 1) * (n + 1), nf = n * n;
    double *pos = malloc(3 * (size_t)nv * sizeof *pos);
    int *fs = malloc((size_t)(nf + 1) * sizeof *fs), *fv = malloc(4 * (size_t)nf * sizeof *fv);
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++) {
            double *p = pos + 3 * (j * (n + 1) + i);
            p[0] = 2.0 * i, p[1] = j, p[2] = 0;
        }
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            int f = j * n + i, v = j * (n + 1) + i;
            fs[f] = 4 * f;
            fv[4 * f] = v, fv[4 * f + 1] = v + 1, fv[4 * f + 2] = v + n + 2, fv[4 * f + 3] = v + n + 1;
        }
    fs[nf] = 4 * nf;
    q2n_mesh *g = mg_finish(nv, pos, nf, fs, fv, "stretched grid");
    st = q2n_mesh_isotropic_frame(g, A, Ai);
    CHECK(fabs(st - 2) < 0.02, "flat 2:1 grid: stretch %.6g", st);
    CHECK(fabs(A[0][0] / A[1][1] - 0.5) < 0.01 && fabs(A[2][2] - sqrt(A[0][0] * A[1][1])) < 0.02 * A[2][2] &&
              fabs(A[0][2]) + fabs(A[1][2]) < 1e-12,
          "flat 2:1 grid: x shrunk against y, the normal as the plane's mean scale (A diagonal %.6g %.6g %.6g)", A[0][0],
          A[1][1], A[2][2]);
    q2n_mesh_free(g);
}

/* The surface's map against L times the unmapped evaluation, on a model's patches (augmented and
 * extraordinary) and on a Bézier patch. */
static void test_surface_map(void)
{
    q2n_model_options o;
    memset(&o, 0, sizeof o);
    o.frame = -1;
    q2n_model *m = NULL;
    q2n_error err;
    static const int pinch[2] = {5, 40}; /* two quads collapsed: extraordinary regions amid regular ones */
    if (q2n_model_build_mesh(mg_torus_pinched(12, 8, 3, 1, pinch, 2), &o, &m, &err)) {
        CHECK(0, "build: %s", err.message);
        return;
    }
    double L[3][3] = {{1.5, 0.2, -0.1}, {0.3, 0.8, 0.05}, {-0.2, 0.1, 1.1}};
    int np = q2n_surface_npatches(m->surface);
    double us[3] = {0, 0.3, 1}, vs[2] = {0.6, 1};
    double (*e0)[18] = malloc((size_t)np * sizeof *e0), (*g0)[54] = malloc((size_t)np * sizeof *g0),
           (*c0)[24] = malloc((size_t)np * sizeof *c0);
    int *hasc = calloc((size_t)np, sizeof *hasc);
    for (int k = 0; k < np; k++) {
        q2n_surface_eval(m->surface, k, 0.3, 0.7, 2, e0[k]);
        q2n_surface_eval_grid(m->surface, k, 3, us, 2, vs, g0[k]);
        hasc[k] = q2n_surface_corner_mixed(m->surface, k, 1, 0, (double(*)[2][2][3])c0[k]) == Q2N_OK;
    }
    q2n_surface_map_linear(m->surface, L);
    double worst = 0;
    int kinds[4] = {0, 0, 0, 0};
    for (int k = 0; k < np; k++) {
        double e[18], g[54], gp[18], c[24];
        kinds[q2n_surface_kind(m->surface, k)]++;
        q2n_surface_eval(m->surface, k, 0.3, 0.7, 2, e);
        q2n_surface_eval_grid(m->surface, k, 3, us, 2, vs, g);
        q2n_surface_eval_grid_pos(m->surface, k, 3, us, 2, vs, gp);
        int hc = q2n_surface_corner_mixed(m->surface, k, 1, 0, (double(*)[2][2][3])c) == Q2N_OK;
        for (int q = 0; q < 6; q++)
            for (int i = 0; i < 3; i++) {
                double want = L[i][0] * e0[k][3 * q] + L[i][1] * e0[k][3 * q + 1] + L[i][2] * e0[k][3 * q + 2];
                worst = fmax(worst, fabs(e[3 * q + i] - want) / (1 + fabs(want)));
            }
        for (int q = 0; q < 18; q++)
            for (int i = 0; i < 3; i++) {
                double want = L[i][0] * g0[k][3 * q] + L[i][1] * g0[k][3 * q + 1] + L[i][2] * g0[k][3 * q + 2];
                worst = fmax(worst, fabs(g[3 * q + i] - want) / (1 + fabs(want)));
                if (q % 3 == 0) worst = fmax(worst, fabs(gp[q + i] - want) / (1 + fabs(want)));
            }
        CHECK(hc == hasc[k], "patch %d: corner partials as before the map", k);
        for (int q = 0; hc && q < 8; q++)
            for (int i = 0; i < 3; i++) {
                double want = L[i][0] * c0[k][3 * q] + L[i][1] * c0[k][3 * q + 1] + L[i][2] * c0[k][3 * q + 2];
                worst = fmax(worst, fabs(c[3 * q + i] - want) / (1 + fabs(want)));
            }
    }
    CHECK(worst < 1e-13, "mapped evaluations are L times the unmapped ones (worst relative %.3g)", worst);
    CHECK(kinds[Q2N_PATCH_AUGMENTED] > 0 && kinds[Q2N_PATCH_COONS_GREGORY] > 0,
          "both patch kinds mapped (%d augmented, %d extraordinary)", kinds[Q2N_PATCH_AUGMENTED], kinds[Q2N_PATCH_COONS_GREGORY]);
    free(e0);
    free(g0);
    free(c0);
    free(hasc);
    q2n_model_free(m);

    /* a Bézier patch: its control points are mapped in place, once; maps compose */
    q2n_surface *s = q2n_surface_create(1);
    double cp[12] = {0, 0, 0, 1, 0, 0.5, 0, 1, 0.25, 1, 1, 1}, e0b[18], eb[18];
    q2n_surface_set_bezier(s, 0, 1, 1, cp);
    q2n_surface_eval(s, 0, 0.4, 0.9, 2, e0b);
    double Li[3][3] = {{2, 0, 0}, {0, 0.5, 0}, {0, 0, 1}}, LL[3][3];
    q2n_surface_map_linear(s, L);
    q2n_surface_map_linear(s, Li);
    mat_mul(Li, L, LL);
    q2n_surface_eval(s, 0, 0.4, 0.9, 2, eb);
    worst = 0;
    for (int q = 0; q < 6; q++)
        for (int i = 0; i < 3; i++)
            worst = fmax(worst, fabs(eb[3 * q + i] - (LL[i][0] * e0b[3 * q] + LL[i][1] * e0b[3 * q + 1] + LL[i][2] * e0b[3 * q + 2])));
    CHECK(worst < 1e-14, "Bézier patch through two maps: their product (worst %.3g)", worst);
    q2n_surface_free(s);
}

/* The paraboloid z = x^2 + y^2 over [-1, 1]^2 as a biquadratic Bézier patch. */
static void test_fairness_closed_form(void)
{
    q2n_surface *s = q2n_surface_create(1);
    double cp[27], c[3] = {1, -1, 1};
    for (int j = 0; j < 3; j++)
        for (int i = 0; i < 3; i++) {
            double *p = cp + 3 * (3 * j + i);
            p[0] = i - 1.0, p[1] = j - 1.0, p[2] = c[i] + c[j];
        }
    q2n_surface_set_bezier(s, 0, 2, 2, cp);
    /* along either diagonal x = y = s: H = (2 + 8 s^2) / (1 + 8 s^2)^(3/2), 2 at the middle and 10/27
     * at the ends, monotone on each half: TV - |net| = 2 (2 - 10/27); the diagonal's length is the
     * integral of sqrt(2 + 16 s^2) over [-1, 1] = 8 [s/2 sqrt(s^2 + c) + c/2 ln(s + sqrt(s^2 + c))]_0^1,
     * c = 1/8 */
    double cc = 0.125, len = 8 * (0.5 * sqrt(1 + cc) + 0.5 * cc * (log(1 + sqrt(1 + cc)) - log(sqrt(cc))));
    double osc = 2 * (2 - 10.0 / 27) * len / 2;
    /* energy: an independent midpoint rule in (x, y), 400 x 400 */
    double E = 0;
    int N = 400;
    for (int a = 0; a < N; a++)
        for (int b = 0; b < N; b++) {
            double x = -1 + (a + 0.5) * 2.0 / N, y = -1 + (b + 0.5) * 2.0 / N, w = 1 + 4 * x * x + 4 * y * y;
            double H = (2 + 4 * x * x + 4 * y * y) / pow(w, 1.5), K = 4 / (w * w);
            E += (4 * H * H - 2 * K) * sqrt(w) * (2.0 / N) * (2.0 / N);
        }
    /* 17 samples: the polyline's length 1e-3 short of the arc; 6 Gauss points: 1 % off here (the
     * integrand is rational), 16: to the midpoint rule's own accuracy */
    q2n_fairness f = q2n_surface_fairness(s, 17, 6, 1), f16 = q2n_surface_fairness(s, 17, 16, 1);
    CHECK(fabs(f.ripple / (2 * osc) - 1) < 2e-3, "paraboloid: ripple %.9g against the closed form %.9g", f.ripple, 2 * osc);
    CHECK(fabs(f.energy / E - 1) < 0.02, "paraboloid: energy %.9g against the quadrature's %.9g", f.energy, E);
    CHECK(fabs(f16.energy / E - 1) < 2e-5, "paraboloid: energy (16 points) %.9g against the quadrature's %.9g", f16.energy, E);
    q2n_fairness f2 = q2n_surface_fairness(s, 17, 6, 3);
    CHECK(f2.ripple == f.ripple && f2.energy == f.energy, "the same bits on 3 threads");
    double e[18], H, K;
    q2n_surface_eval(s, 0, 0.5, 0.5, 2, e);
    q2n_curvatures(e, &H, &K);
    CHECK_NEAR(H, 2, 1e-12, "mean curvature at the apex");
    CHECK_NEAR(K, 4, 1e-12, "Gaussian curvature at the apex");
    q2n_surface_free(s);
}

/* Every vertex on the surface: the patch corners against the mesh's vertices. */
static double corner_gap(const q2n_model *m)
{
    double worst = 0;
    for (int f = 0; f < m->mesh->nf; f++)
        for (int i = 0; i < 4; i++) {
            double e[3];
            q2n_surface_eval(m->surface, f, q2n_corner_uv[i][0], q2n_corner_uv[i][1], 0, e);
            worst = fmax(worst, q2n_v3_dist(e, q2n_mesh_vpos(m->mesh, m->mesh->face_vert[m->mesh->face_start[f] + i])));
        }
    return worst;
}

static void test_model(void)
{
    /* prolate: the isotropic frame's build is smoother; oblate 1:1:0.3: the rim's curvature is the
     * mesh's own and the mesh's frame is smoother (the choice keeps it); the sphere: built once */
    static const double sc[4][3] = {{3, 1, 1}, {2, 1, 0.5}, {1, 1, 0.3}, {1, 1, 1}};
    double ico[36];
    mg_icosahedron(ico);
    for (int c = 0; c < 4; c++) {
        q2n_model *m[2] = {NULL, NULL};
        fair_figures F[2];
        for (int off = 0; off < 2; off++) {
            q2n_model_options o;
            memset(&o, 0, sizeof o);
            o.frame = off ? -1 : 0;
            q2n_error err;
            q2n_mesh *mesh = mg_tri_to_quad(12, ico, 20, mg_icosa_tri, 1, sc[c], 0.01, 7, "icosahedron on an ellipsoid");
            CHECK(q2n_model_build_mesh(mesh, &o, &m[off], &err) == Q2N_OK, "build: %s", err.message);
            if (!m[off]) return;
            fair_measure(m[off]->mesh, m[off]->surface, &F[off]);
        }
        char what[64];
        snprintf(what, sizeof what, "ellipsoid %g:%g:%g", sc[c][0], sc[c][1], sc[c][2]);
        CHECK(corner_gap(m[0]) < 1e-13, "%s: every vertex interpolated (gap %.3g)", what, corner_gap(m[0]));
        CHECK(m[0]->continuity == m[1]->continuity, "%s: the same continuity (%d)", what, m[0]->continuity);
        double e0[18], e1[18];
        q2n_surface_eval(m[0]->surface, 3, 0.3, 0.6, 2, e0);
        q2n_surface_eval(m[1]->surface, 3, 0.3, 0.6, 2, e1);
        int same = memcmp(e0, e1, sizeof e0) == 0;
        if (c < 2) {
            CHECK(m[0]->frame_used && m[0]->frame_stretch > 2.5, "%s: built in the isotropic frame (stretch %.4g, used %d)",
                  what, m[0]->frame_stretch, m[0]->frame_used);
            CHECK(F[0].osc_ev_mean < 0.85 * F[1].osc_ev_mean && F[0].E_ev <= F[1].E_ev && F[0].jac_min > 0.1,
                  "%s: smoother than in the mesh's frame (osc %.4g against %.4g, E %.4g against %.4g, jac %.3g)", what,
                  F[0].osc_ev_mean, F[1].osc_ev_mean, F[0].E_ev, F[1].E_ev, F[0].jac_min);
        } else if (c == 2) {
            /* the isotropic build is not better on all counts: until stop 53 it rippled more, since the G2
             * patches are glued by polynomials (stop 54) it ripples less but bends more */
            CHECK(m[0]->frame_stretch > 2.5 && !m[0]->frame_used &&
                      (m[0]->frame_ripple[1] > m[0]->frame_ripple[0] || m[0]->frame_energy[1] > m[0]->frame_energy[0]) && same,
                  "%s: built in both frames, the mesh's kept (stretch %.4g, ripple %.5g against %.5g, energy %.5g against %.5g)",
                  what, m[0]->frame_stretch, m[0]->frame_ripple[0], m[0]->frame_ripple[1], m[0]->frame_energy[0],
                  m[0]->frame_energy[1]);
        } else {
            CHECK(m[0]->frame_stretch < 1.05 && !m[0]->frame_used && m[0]->frame_ripple[1] == 0 && same,
                  "%s: isotropic, built once, as with --frame off (stretch %.4g)", what, m[0]->frame_stretch);
        }
        q2n_model_free(m[0]);
        q2n_model_free(m[1]);
    }
}

/* The mesh (taken over) built with the isotropic frame (m[0], on a copy) and without (m[1]), with the
 * CLI's defaults for ev_patch (G1 patches where G2 ones fold unless ev_patch is given), measured by
 * tests/fairness.h; 0 when a build failed. */
static int build_both(q2n_mesh *mesh, int ev_patch, q2n_model *m[2], fair_figures F[2])
{
    static const double I[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    char name[sizeof mesh->name];
    snprintf(name, sizeof name, "%s", mesh->name); /* the build takes the mesh over */
    m[0] = m[1] = NULL;
    for (int off = 0; off < 2; off++) {
        q2n_mesh *own = off ? mesh : NULL;
        q2n_error err;
        if (!off && q2n_mesh_mapped(mesh, I, &own, &err)) { CHECK(0, "copy: %s", err.message); q2n_mesh_free(mesh); return 0; }
        q2n_model_options o;
        memset(&o, 0, sizeof o);
        o.frame = off ? -1 : 0;
        o.ev_patch = ev_patch;
        o.fold_fallback = !ev_patch; /* the CLI's default */
        CHECK(q2n_model_build_mesh(own, &o, &m[off], &err) == Q2N_OK, "%s: build: %s", name, err.message);
        if (!m[off]) { if (!off) q2n_mesh_free(mesh); return 0; }
        fair_measure(m[off]->mesh, m[off]->surface, &F[off]);
    }
    return 1;
}

/* A shared mesh scaled by the diagonal s, through build_both; 0 when the mesh is absent (skipped,
 * said) or a build failed. */
static int build_scaled(const char *file, const double s[3], int ev_patch, q2n_model *m[2], fair_figures F[2])
{
    const char *path = chk_shared_mesh(file);
    m[0] = m[1] = NULL;
    if (!path) return 0;
    double S[3][3] = {{s[0], 0, 0}, {0, s[1], 0}, {0, 0, s[2]}};
    q2n_mesh *mesh = NULL;
    q2n_error err;
    if (q2n_mesh_read(path, &mesh, NULL, &err)) { CHECK(0, "%s: %s", path, err.message); return 0; }
    if (!build_both(mapped(mesh, S), ev_patch, m, F)) return 0;
    return 1;
}

/* Shared meshes scaled along an axis (stop 50's finding): their own frame folded the G2 patches (G1 ones
 * replaced them); built in the isotropic frame, no fold, G2 patches, and far smoother by
 * tests/fairness.h.  Since the G2 patches are glued by polynomials (stop 54) octtorus_hole's own frame
 * keeps its G2 patches too (no fold), and gregory_test6's isotropic frame keeps G2 patches (before: G1
 * patches in both frames). */
static void test_shared_stretched(void)
{
    static const struct { const char *file; double s[3], osc_ratio; int own_fold; } cases[] = {
        {"gismo_octtorus_hole.obj", {3, 1, 1}, 0.35, 0},      /* measured 0.91 against 3.66 (G1 patches) at stop 53 */
        {"osd_catmark_gregory_test6.obj", {1, 1, 0.1}, 0.15, 1}, /* 19.9 against 237 at stop 53 */
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        q2n_model *m[2];
        fair_figures F[2];
        if (!build_scaled(cases[c].file, cases[c].s, 0, m, F)) { q2n_model_free(m[0]); q2n_model_free(m[1]); continue; }
        printf("%s scaled %g %g %g: osc %.4g against %.4g in its own frame, E_ev %.4g against %.4g, jac %.3g; own frame G2 folded on %d\n",
               cases[c].file, cases[c].s[0], cases[c].s[1], cases[c].s[2], F[0].osc_ev_mean, F[1].osc_ev_mean, F[0].E_ev, F[1].E_ev,
               F[0].jac_min, m[1]->g2_folded);
        CHECK(m[0]->frame_used && m[0]->continuity == 2 && m[0]->folded == 0 && (m[1]->g2_folded > 0) == cases[c].own_fold,
              "%s scaled %g %g %g: no fold in the isotropic frame (used %d, continuity %d, folded %d; own frame: "
              "G2 folded on %d faces, G1 patches)", cases[c].file, cases[c].s[0], cases[c].s[1], cases[c].s[2], m[0]->frame_used,
              m[0]->continuity, m[0]->folded, m[1]->g2_folded);
        CHECK(F[0].osc_ev_mean < cases[c].osc_ratio * F[1].osc_ev_mean && F[0].E_ev < F[1].E_ev && F[0].jac_min > 0.1,
              "%s scaled: osc %.4g against %.4g in its own frame, E_ev %.4g against %.4g, jac %.3g", cases[c].file,
              F[0].osc_ev_mean, F[1].osc_ev_mean, F[0].E_ev, F[1].E_ev, F[0].jac_min);
        CHECK(corner_gap(m[0]) < 1e-13, "%s scaled: every vertex interpolated (gap %.3g)", cases[c].file, corner_gap(m[0]));
        q2n_model_free(m[0]);
        q2n_model_free(m[1]);
    }
    /* the helmet 8 x along x in G1 mode: built in the isotropic frame its dome gets rougher (the
     * regular patches), but its extraordinary regions smoother, so only their vertex charts are
     * measured there */
    static const double s8[3] = {8, 1, 1};
    q2n_model *m[2];
    fair_figures F[2];
    if (build_scaled("osd_catmark_helmet.obj", s8, Q2N_EV_PATCH_G1, m, F)) {
        CHECK(m[0]->frame_used == 2 && m[0]->frame_ripple[1] > m[0]->frame_ripple[0] && m[0]->frame_ripple[2] < m[0]->frame_ripple[0],
              "helmet 8 x, G1: the vertex charts of the isotropic frame (used %d, ripple %.5g, %.5g, %.5g)", m[0]->frame_used,
              m[0]->frame_ripple[0], m[0]->frame_ripple[1], m[0]->frame_ripple[2]);
        CHECK(F[0].osc_ev_mean < 0.85 * F[1].osc_ev_mean && F[0].E_ev < F[1].E_ev && F[0].E_reg <= F[1].E_reg * (1 + 1e-9) &&
                  m[0]->ev_stats.polynomial_edges >= m[1]->ev_stats.polynomial_edges,
              "helmet 8 x, G1: osc %.4g against %.4g, E_ev %.4g against %.4g, E_reg %.4g against %.4g, polynomial edges %d "
              "against %d", F[0].osc_ev_mean, F[1].osc_ev_mean, F[0].E_ev, F[1].E_ev, F[0].E_reg, F[1].E_reg,
              m[0]->ev_stats.polynomial_edges, m[1]->ev_stats.polynomial_edges);
        CHECK(corner_gap(m[0]) < 1e-13, "helmet 8 x: every vertex interpolated (gap %.3g)", corner_gap(m[0]));
    }
    q2n_model_free(m[0]);
    q2n_model_free(m[1]);
    /* gregory_test6 3 x along y (G2): its own frame ripples less than the build in the isotropic frame,
     * which is refused, and the vertex charts of that frame are still tried and kept (stop 54: until
     * then they were tried only where the build in the frame rippled less, and with the G2 patches glued
     * by polynomials this mesh kept its own frame, 2.24 per EV diagonal and E_ev 243 by these figures) */
    static const double s3[3] = {1, 3, 1};
    if (build_scaled("osd_catmark_gregory_test6.obj", s3, 0, m, F)) {
        printf("gregory_test6 3 x along y: used %d, ripple %.5g %.5g %.5g; osc %.4g against %.4g, E_ev %.4g against %.4g\n",
               m[0]->frame_used, m[0]->frame_ripple[0], m[0]->frame_ripple[1], m[0]->frame_ripple[2], F[0].osc_ev_mean,
               F[1].osc_ev_mean, F[0].E_ev, F[1].E_ev);
        CHECK(m[0]->frame_used == 2 && m[0]->frame_ripple[1] > m[0]->frame_ripple[0] && m[0]->frame_ripple[2] < m[0]->frame_ripple[0],
              "gregory_test6 3 x along y: the vertex charts of the isotropic frame (used %d, ripple %.5g, %.5g, %.5g)",
              m[0]->frame_used, m[0]->frame_ripple[0], m[0]->frame_ripple[1], m[0]->frame_ripple[2]);
        CHECK(F[0].osc_ev_mean < 0.8 * F[1].osc_ev_mean && F[0].E_ev < 0.7 * F[1].E_ev && F[0].jac_min > 0.1,
              "gregory_test6 3 x along y: osc %.4g against %.4g, E_ev %.4g against %.4g, jac %.3g", F[0].osc_ev_mean,
              F[1].osc_ev_mean, F[0].E_ev, F[1].E_ev, F[0].jac_min);
    }
    q2n_model_free(m[0]);
    q2n_model_free(m[1]);
}

/* A chart mesh that is the mesh itself (the identity map) gives the surface bit for bit. */
static void test_chart_identity(void)
{
    static const int pinch[2] = {5, 40};
    double I[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int k = 1; k <= 2; k++) {
        q2n_mesh *m = mg_torus_pinched(12, 8, 3, 1, pinch, 2), *cm = NULL;
        q2n_surface *s[2] = {NULL, NULL};
        q2n_error err;
        CHECK(q2n_mesh_mapped(m, I, &cm, &err) == Q2N_OK, "identity map");
        for (int c = 0; c < 2; c++) {
            q2n_augmented_options ao = {NULL, {0}};
            q2n_extraordinary_options eo = {NULL, {0}, k == 1 ? Q2N_EV_PATCH_G1 : Q2N_EV_PATCH_G2, Q2N_EV_METHOD_FAIR, 1, 0, 0,
                                            c ? cm : NULL, NULL};
            double *iv = NULL;
            CHECK(q2n_param_edge_intervals(m, &ao.param, &iv, &err) == Q2N_OK && q2n_augmented_build(m, &ao, iv, &s[c], &err) == Q2N_OK &&
                      q2n_extraordinary_build(m, &eo, iv, s[c], &err) == Q2N_OK,
                  "build: %s", err.message);
            free(iv);
        }
        int same = s[0] && s[1];
        for (int f = 0; same && f < m->nf; f++) {
            double e0[18], e1[18];
            q2n_surface_eval(s[0], f, 0.3, 0.8, 2, e0);
            q2n_surface_eval(s[1], f, 0.3, 0.8, 2, e1);
            same = memcmp(e0, e1, sizeof e0) == 0;
        }
        CHECK(same, "G%d: charts measured on an identical chart mesh give the same surface", k);
        q2n_surface_free(s[0]);
        q2n_surface_free(s[1]);
        q2n_mesh_free(cm);
        q2n_mesh_free(m);
    }
}

/* q2n_augmented_map_points: every regular patch (point evaluation to second order, grid, corner
 * partials) becomes L times what it was, through its points, with no output map on the surface. */
static void test_map_points(void)
{
    static const int pinch[2] = {5, 40};
    q2n_mesh *mesh = mg_torus_pinched(12, 8, 3, 1, pinch, 2);
    q2n_augmented_options ao;
    memset(&ao, 0, sizeof ao);
    q2n_surface *s = NULL;
    q2n_error err;
    if (!mesh || q2n_augmented_build(mesh, &ao, NULL, &s, &err)) {
        CHECK(0, "augmented build: %s", mesh ? err.message : "no mesh");
        q2n_mesh_free(mesh);
        return;
    }
    double L[3][3] = {{1.5, 0.2, -0.1}, {0.3, 0.8, 0.05}, {-0.2, 0.1, 1.1}};
    int np = q2n_surface_npatches(s), naug = 0;
    double us[3] = {0, 0.3, 1}, vs[2] = {0.6, 1};
    double (*e0)[18] = malloc((size_t)np * sizeof *e0), (*g0)[54] = malloc((size_t)np * sizeof *g0),
           (*c0)[24] = malloc((size_t)np * sizeof *c0);
    for (int k = 0; k < np; k++) {
        if (q2n_surface_kind(s, k) != Q2N_PATCH_AUGMENTED) continue;
        q2n_surface_eval(s, k, 0.3, 0.7, 2, e0[k]);
        q2n_surface_eval_grid(s, k, 3, us, 2, vs, g0[k]);
        CHECK(q2n_surface_corner_mixed(s, k, 1, 0, (double(*)[2][2][3])c0[k]) == Q2N_OK, "patch %d: corner partials", k);
    }
    q2n_augmented_map_points(s, L);
    double worst = 0;
    for (int k = 0; k < np; k++) {
        if (q2n_surface_kind(s, k) != Q2N_PATCH_AUGMENTED) continue;
        naug++;
        double e[18], g[54], c[24];
        q2n_surface_eval(s, k, 0.3, 0.7, 2, e);
        q2n_surface_eval_grid(s, k, 3, us, 2, vs, g);
        q2n_surface_corner_mixed(s, k, 1, 0, (double(*)[2][2][3])c);
        const double *have[3] = {e, g, c}, *was[3] = {e0[k], g0[k], c0[k]};
        const int nvec[3] = {6, 18, 8};
        for (int t = 0; t < 3; t++)
            for (int q = 0; q < nvec[t]; q++)
                for (int i = 0; i < 3; i++) {
                    const double *x = was[t] + 3 * q;
                    double want = L[i][0] * x[0] + L[i][1] * x[1] + L[i][2] * x[2];
                    worst = fmax(worst, fabs(have[t][3 * q + i] - want) / (1 + fabs(want)));
                }
    }
    CHECK(naug > 40 && worst < 1e-13, "%d regular patches with mapped points: L times the patches they were (worst relative %.3g)",
          naug, worst);
    free(e0);
    free(g0);
    free(c0);
    q2n_surface_free(s);
    q2n_mesh_free(mesh);
}

/* Across every interior edge of s on m (9 points each, ends excluded): fair_edge_jumps. */
static void edge_continuity(const q2n_mesh *m, const q2n_surface *s, double *g1, double *g2)
{
    static const double xs[9] = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9};
    fair_edge_jumps(m, s, xs, 9, g1, g2);
}

/* The extraordinary regions of a stretched pinched torus built in its isotropic frame against its own
 * regular patches (api/model.c's third build, step by step): the regular patches stay the mesh's own,
 * every vertex is interpolated, the surface is G1 and G2 across every edge, and the regions differ
 * from those built in the mesh's own frame (the frame mattered). */
static void test_regions_build(void)
{
    static const int pinch[2] = {5, 40};
    double S[3][3], A[3][3], Ai[3][3];
    rotated_stretch(4, S);
    q2n_mesh *own = mapped(mg_torus_pinched(12, 8, 3, 1, pinch, 2), S), *fm = NULL;
    if (!own) return;
    double stretch = q2n_mesh_isotropic_frame(own, A, Ai);
    q2n_error err;
    CHECK(stretch > 2.5 && q2n_mesh_mapped(own, A, &fm, &err) == Q2N_OK, "the frame (stretch %.4g)", stretch);
    q2n_augmented_options ao;
    memset(&ao, 0, sizeof ao);
    q2n_extraordinary_options eo;
    memset(&eo, 0, sizeof eo);
    double *iv = NULL;
    q2n_surface *s[2] = {NULL, NULL}; /* the mesh's own frame; the regions in the isotropic one */
    int ok = fm && q2n_param_edge_intervals(own, &ao.param, &iv, &err) == Q2N_OK;
    for (int r = 0; r < 2 && ok; r++) {
        ok = q2n_augmented_build(own, &ao, iv, &s[r], &err) == Q2N_OK;
        if (ok && r) q2n_augmented_map_points(s[r], A);
        if (ok) ok = q2n_extraordinary_build(r ? fm : own, &eo, iv, s[r], &err) == Q2N_OK;
        if (ok && r) q2n_surface_map_linear(s[r], Ai);
    }
    CHECK(ok, "the two builds: %s", ok ? "" : err.message);
    if (ok) {
        double reg = 0, ev = 0, gap = 0, g1, g2;
        int nreg = 0, nev = 0;
        for (int k = 0; k < own->nf; k++) {
            int aug = q2n_surface_kind(s[0], k) == Q2N_PATCH_AUGMENTED;
            nreg += aug, nev += !aug;
            for (int a = 0; a <= 4; a++)
                for (int b = 0; b <= 4; b++) {
                    double e0[18], e1[18];
                    q2n_surface_eval(s[0], k, a / 4.0, b / 4.0, 1, e0);
                    q2n_surface_eval(s[1], k, a / 4.0, b / 4.0, 1, e1);
                    for (int c = 0; c < 9; c++) {
                        double d = fabs(e0[c] - e1[c]) / (1 + fabs(e0[c]));
                        if (aug) reg = fmax(reg, d);
                        else ev = fmax(ev, d);
                    }
                    if ((a == 0 || a == 4) && (b == 0 || b == 4)) {
                        int corner = a ? (b ? 2 : 1) : (b ? 3 : 0);
                        gap = fmax(gap, q2n_v3_dist(e1, q2n_mesh_vpos(own, own->face_vert[own->face_start[k] + corner])));
                    }
                }
        }
        edge_continuity(own, s[1], &g1, &g2);
        CHECK(nreg > 40 && nev > 10 && reg < 1e-13, "%d regular patches the mesh's own (worst relative %.3g)", nreg, reg);
        CHECK(ev > 1e-3, "%d extraordinary patches built in the frame differ from the own frame's (%.3g)", nev, ev);
        CHECK(gap < 1e-13, "every vertex interpolated (gap %.3g)", gap);
        CHECK(g1 < 1e-8 && g2 < 1e-6, "G1 and G2 across every edge (normals %.3g rad, mean curvature %.3g)", g1, g2);
    }
    q2n_surface_free(s[0]);
    q2n_surface_free(s[1]);
    free(iv);
    q2n_mesh_free(own);
    q2n_mesh_free(fm);
}

/* The same on a generated mesh (a plain clone tests it too): a torus with two quads collapsed (two
 * pairs of valence-3 and valence-5 vertices amid regular patches) stretched 3 x along its axis
 * (measured: in G2 mode the regions' build, 0.156 per EV diagonal against 0.188 in its own frame; in
 * G1 mode the charts' build, 0.165 against 0.206, which the regions' build, 0.153 but bending more,
 * does not beat).  Its regular patches are the own frame's to rounding. */
static void test_generated_regions(void)
{
    static const int pinch[2] = {5, 40};
    static const double S[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 3}};
    for (int g = 0; g < 2; g++) {
        q2n_model *m[2] = {NULL, NULL};
        fair_figures F[2];
        if (build_both(mapped(mg_torus_pinched(16, 10, 3, 1, pinch, 2), S), g ? Q2N_EV_PATCH_G1 : 0, m, F)) {
            double g1, g2, reg = 0;
            edge_continuity(m[0]->mesh, m[0]->surface, &g1, &g2);
            for (int k = 0; k < m[0]->mesh->nf; k++) {
                if (q2n_surface_kind(m[0]->surface, k) != Q2N_PATCH_AUGMENTED) continue;
                double e0[9], e1[9];
                q2n_surface_eval(m[0]->surface, k, 0.3, 0.6, 1, e0);
                q2n_surface_eval(m[1]->surface, k, 0.3, 0.6, 1, e1);
                for (int c = 0; c < 9; c++) reg = fmax(reg, fabs(e0[c] - e1[c]) / (1 + fabs(e1[c])));
            }
            printf("pinched torus 3 x along its axis, G%d: kept %d, osc %.4g against %.4g, E_ev %.4g against %.4g\n", g ? 1 : 2,
                   m[0]->frame_used, F[0].osc_ev_mean, F[1].osc_ev_mean, F[0].E_ev, F[1].E_ev);
            /* G2: the charts' build not kept, the regions' is; G1: the charts' build is kept, and the regions'
             * (tried, less ripple) does not beat it on all counts (more bending energy), so it stays */
            const double *rp = m[0]->frame_ripple, *en = m[0]->frame_energy;
            int rule = g ? m[0]->frame_used == 2 && rp[3] > 0 && !(rp[3] < rp[2] && en[3] <= en[2]) : m[0]->frame_used == 3;
            CHECK(rule && F[0].osc_ev_mean < 0.9 * F[1].osc_ev_mean && F[0].jac_min > 0.1,
                  "pinched torus 3 x, G%d: kept build %d (ripple own/charts/regions %.5g %.5g %.5g, energy %.5g %.5g %.5g), osc %.4g "
                  "against %.4g, jac %.3g", g ? 1 : 2, m[0]->frame_used, rp[0], rp[2], rp[3], en[0], en[2], en[3], F[0].osc_ev_mean,
                  F[1].osc_ev_mean, F[0].jac_min);
            CHECK(reg < 1e-13 && corner_gap(m[0]) < 1e-13 && g1 < 1e-8 && (g || g2 < 1e-6),
                  "pinched torus 3 x: regular patches the own frame's (%.3g), gap %.3g, G1 %.3g rad, G2 %.3g", reg,
                  corner_gap(m[0]), g1, g2);
        }
        q2n_model_free(m[0]);
        q2n_model_free(m[1]);
    }
}

/* Shared meshes stretched along an axis whose regular region gets rougher in the isotropic frame
 * while their extraordinary regions get smoother there: the model builds those regions alone in the
 * frame (frame_used 3), which is smoother than its own frame's build with no more energy; G1 and G2
 * across every edge. */
static void test_shared_regions(void)
{
    static const struct { const char *file; double s[3]; int ev_patch; double osc_ratio; } cases[] = {
        {"osd_catmark_helmet.obj", {8, 1, 1}, 0, 0.25},                /* measured 4.36 against 32.7 */
        {"osd_catmark_pawn.obj", {4, 1, 1}, 0, 0.4},                   /* 0.042 against 0.175 */
        {"osd_catmark_pawn.obj", {4, 1, 1}, Q2N_EV_PATCH_G1, 0.6},     /* 0.013 against 0.032 */
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        q2n_model *m[2];
        fair_figures F[2];
        if (!build_scaled(cases[c].file, cases[c].s, cases[c].ev_patch, m, F)) { q2n_model_free(m[0]); q2n_model_free(m[1]); continue; }
        double g1, g2;
        edge_continuity(m[0]->mesh, m[0]->surface, &g1, &g2);
        int G2 = m[0]->continuity == 2;
        CHECK(m[0]->frame_used == 3 && m[0]->frame_ripple[3] < m[0]->frame_ripple[0] && m[0]->frame_energy[3] <= m[0]->frame_energy[0],
              "%s scaled %g %g %g, G%d: the regions in the isotropic frame (used %d, ripple %.5g against %.5g, energy %.5g "
              "against %.5g)", cases[c].file, cases[c].s[0], cases[c].s[1], cases[c].s[2], G2 ? 2 : 1, m[0]->frame_used,
              m[0]->frame_ripple[3], m[0]->frame_ripple[0], m[0]->frame_energy[3], m[0]->frame_energy[0]);
        /* the pawn stretched is below the fold target in its own frame (0.083): no lower */
        CHECK(F[0].osc_ev_mean < cases[c].osc_ratio * F[1].osc_ev_mean && F[0].E_ev < F[1].E_ev &&
                  F[0].jac_min > fmin(0.1, F[1].jac_min),
              "%s scaled: osc %.4g against %.4g in its own frame, E_ev %.4g against %.4g, jac %.3g against %.3g", cases[c].file,
              F[0].osc_ev_mean, F[1].osc_ev_mean, F[0].E_ev, F[1].E_ev, F[0].jac_min, F[1].jac_min);
        CHECK(corner_gap(m[0]) < 1e-13 && g1 < 1e-8 && (!G2 || g2 < 1e-6),
              "%s scaled: every vertex interpolated (gap %.3g), G1 %.3g rad, G2 %.3g", cases[c].file, corner_gap(m[0]), g1, g2);
        q2n_model_free(m[0]);
        q2n_model_free(m[1]);
    }
}

int main(void)
{
    test_estimate();
    test_surface_map();
    test_fairness_closed_form();
    test_model();
    test_shared_stretched();
    test_chart_identity();
    test_map_points();
    test_regions_build();
    test_generated_regions();
    test_shared_regions();
    CHECK_DONE("test_frame");
}
