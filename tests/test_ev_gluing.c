/* test_ev_gluing.c — polynomial gluing of the fair construction's G1 and G2 patches (ev_fair_gluing.c, ev_fair_gluing2.c,
 * docs/extraordinary.md "Polynomial gluing of G1 patches", "... of G2 patches"), against references
 * that know nothing of it:
 *   - corners: no corner of any patch needs a Gregory blend (the two sides' mixed derivatives agree
 *     to EV_FAIR_COMPAT_REL), so the twist corrections solve their equations;
 *   - degree: where every edge of a mesh is glued by polynomials, every patch is a bi-quintic
 *     polynomial: sixth finite differences along both parameter lines vanish to rounding (a
 *     degree-7 side, the smoothsteps' χ_G, leaves them at 1e-4 of the patch's size and more);
 *   - the fit (G1 mode): one span per patch, the construction to 1e-12 of the diagonal, and the normal
 *     jump across every edge at most 1e-6 degrees, by the report and by fit_check.h's independent
 *     sampling (the smoothsteps: least squares, 1e-4..1e-2 degrees, 16 spans and more);
 *   - regions bordering regular patches: the edges between free vertices still take the gluing;
 *   - fairness: on closed meshes glued by polynomials everywhere the surface ripples less along the
 *     faces' diagonals than with the smoothsteps, with no more bending energy (tests/fairness.h);
 *   - G2 patches (stop 54): no Gregory corner, G1 and G2 across every edge down to 1e-3 from the
 *     corners (where sides that disagree at a corner would show), less ripple than the smoothsteps.
 * The meshes are generated here (tests/meshgen.h): closed ones whose every face touches an
 * extraordinary vertex, and open and mixed ones. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "api/model.h"
#include "check.h"
#include "core/vec3.h"
#include "fit/fit.h"
#include "fairness.h"
#include "fit_check.h"
#include "meshgen.h"
#include "param/param.h"
#include "patch/augmented.h"
#include "patch/ev_fair.h"
#include "patch/fairness.h"
#include "patch/surface.h"
#include "spline/spline.h"

/* measured (stop 54): 0.27, 0.83, 0.90 of the smoothsteps' ripple */
#define G2_RATIO_ICOSA 0.4
#define G2_RATIO_ICOSA_NOISY 0.9
#define G2_RATIO_TRIAC 0.95

/* Edge intervals, the regular patches, and the fair construction with patches of order K (poly:
 * polynomial gluing). */
static q2n_surface *build_k(const q2n_mesh *m, int K, int poly, ev_fair_stats *st);
static q2n_surface *build(const q2n_mesh *m, int poly, ev_fair_stats *st) { return build_k(m, 1, poly, st); }
static q2n_surface *build_k(const q2n_mesh *m, int K, int poly, ev_fair_stats *st)
{
    q2n_param_options po = {0};
    q2n_augmented_options ao = {NULL, po};
    q2n_error err = {0, ""};
    double *iv = NULL;
    q2n_surface *s = NULL;
    int ok = q2n_param_edge_intervals(m, &po, &iv, &err) == Q2N_OK && q2n_augmented_build(m, &ao, iv, &s, &err) == Q2N_OK &&
             q2n_ev_fair_build(m, NULL, s, iv, q2n_spline_class_find(Q2N_SPLINE_CLASS_DEFAULT), K, 0, poly, NULL, 2, st, &err) == Q2N_OK;
    CHECK(ok, "%s: build: %s", m->name, err.message);
    free(iv);
    if (!ok) {
        q2n_surface_free(s);
        return NULL;
    }
    return s;
}

/* Largest sixth finite difference of patch k along u and v lines (7 points at spacing 1/6, 5 lines
 * each way), relative to the patch's size (its corners' bounding box). */
static double sixth_difference(const q2n_surface *s, int k)
{
    static const double c[7] = {1, -6, 15, -20, 15, -6, 1};
    double P[7][7][3], lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, worst = 0;
    for (int a = 0; a < 7; a++)
        for (int b = 0; b < 7; b++) {
            if (q2n_surface_eval(s, k, a / 6.0, b / 6.0, 0, P[a][b])) return INFINITY;
            for (int x = 0; x < 3; x++) lo[x] = fmin(lo[x], P[a][b][x]), hi[x] = fmax(hi[x], P[a][b][x]);
        }
    double size = fmax(hi[0] - lo[0], fmax(hi[1] - lo[1], hi[2] - lo[2]));
    for (int l = 0; l < 7; l += 1)
        for (int x = 0; x < 3; x++) {
            double du = 0, dv = 0;
            for (int i = 0; i < 7; i++) du += c[i] * P[i][l][x], dv += c[i] * P[l][i][x];
            worst = fmax(worst, fmax(fabs(du), fabs(dv)) / size);
        }
    return worst;
}

/* Edges of m with a face on both sides. */
static int interior_edges(const q2n_mesh *m)
{
    int n = 0;
    for (int e = 0; e < m->ne; e++) n += m->he_twin[m->edge_he[e]] >= 0;
    return n;
}

/* The G1 fit of s: its report and the independent largest normal jump (degrees). */
static int fit_g1(const q2n_mesh *m, const q2n_surface *s, q2n_fit_report *r, double *ang)
{
    q2n_fit_options o;
    q2n_fit_options_default(&o);
    o.continuity = 1;
    o.threads = 2;
    q2n_nurbs_model *md = NULL;
    q2n_error err = {0, ""};
    int ok = q2n_fit_surface(s, m, &o, &md, r, &err) == Q2N_OK;
    CHECK(ok, "%s: fit: %s", m->name, err.message);
    *ang = md ? fit_random_angle(md, 8) : INFINITY;
    q2n_nurbs_model_free(md);
    return ok;
}

/* m built with the polynomial gluing (s, st) and with the smoothsteps (s0, st0), both fitted G1
 * (ok: both built and fitted). */
typedef struct both_run {
    ev_fair_stats st, st0;
    q2n_surface *s, *s0;
    q2n_fit_report r, r0;
    double ang, ang0;
    int ok;
} both_run;

static int build_both(q2n_mesh *m, both_run *b)
{
    memset(b, 0, sizeof *b);
    b->ang = b->ang0 = INFINITY;
    b->s = build(m, 1, &b->st), b->s0 = build(m, 0, &b->st0);
    if (!b->s || !b->s0) return 0;
    b->ok = fit_g1(m, b->s, &b->r, &b->ang) && fit_g1(m, b->s0, &b->r0, &b->ang0);
    return 1;
}

static void both_free(both_run *b)
{
    q2n_surface_free(b->s);
    q2n_surface_free(b->s0);
}

/* Every interior edge of m, all of whose faces are extraordinary, is glued by polynomials: the patches
 * are bi-quintic, the fit exact. */
static void all_polynomial(q2n_mesh *m)
{
    CHECK(m != NULL, "generator");
    if (!m) return;
    both_run b;
    if (build_both(m, &b)) {
        double d6 = 0, d60 = 0;
        for (int k = 0; k < m->nf; k++) d6 = fmax(d6, sixth_difference(b.s, k)), d60 = fmax(d60, sixth_difference(b.s0, k));
        printf("%-40s edges %3d polynomial %3d  gregory corners %d  6th differences %.1e (smoothsteps %.1e)\n", m->name, b.st.edges,
               b.st.polynomial_edges, b.st.gregory_corners, d6, d60);
        if (b.ok)
            printf("   fit G1: spans max %d, max_dev %.1e, G1 %.1e deg (independent %.1e); smoothsteps: spans max %d, G1 %.1e deg\n",
                   b.r.spans_max, b.r.max_dev_rel, b.r.g1_max_deg, b.ang, b.r0.spans_max, b.r0.g1_max_deg);
        int interior = interior_edges(m);
        CHECK(b.st.polynomial_edges == interior && interior > 0, "%s: %d of %d interior edges polynomial", m->name,
              b.st.polynomial_edges, interior);
        CHECK(b.st.gregory_corners == 0, "%s: %d Gregory corners (mismatch %.3g)", m->name, b.st.gregory_corners,
              b.st.corner_mismatch_max);
        CHECK(d6 <= 1e-9, "%s: sixth differences %.3g: not bi-quintic", m->name, d6);
        CHECK(d60 >= 1e-7, "%s: the smoothsteps' patches pass the degree check too (%.3g): the check cannot fail", m->name, d60);
        if (b.ok) {
            CHECK(b.r.spans_max == 1, "%s: %d spans in a patch, expected one", m->name, b.r.spans_max);
            CHECK(b.r.max_dev_rel <= 1e-12, "%s: max_dev %.3g", m->name, b.r.max_dev_rel);
            CHECK(b.r.g1_max_deg <= 1e-6 && b.ang <= 1e-6, "%s: G1 %.3g deg (independent %.3g)", m->name, b.r.g1_max_deg, b.ang);
            CHECK(b.r.g1_rounding_edges == interior && b.r0.g1_rounding_edges < interior,
                  "%s: the report counts %d of %d edges within rounding (smoothsteps %d)", m->name, b.r.g1_rounding_edges, interior,
                  b.r0.g1_rounding_edges);
            CHECK(b.r0.g1_max_deg > 1e-6 && b.r0.spans_max > 1, "%s: the smoothsteps' fit is exact too (G1 %.3g deg, %d spans)",
                  m->name, b.r0.g1_max_deg, b.r0.spans_max);
        }
    }
    both_free(&b);
    q2n_mesh_free(m);
}

/* A region bordering regular patches or the mesh boundary: the edges between free vertices take
 * the gluing (at least want of them), every corner stays compatible, and the fit meets its targets. */
static void partly_polynomial(q2n_mesh *m, int want)
{
    CHECK(m != NULL, "generator");
    if (!m) return;
    ev_fair_stats st = {0};
    q2n_surface *s = build(m, 1, &st);
    if (s) {
        q2n_fit_report r;
        double ang = INFINITY;
        int ok = fit_g1(m, s, &r, &ang);
        printf("%-40s edges %3d polynomial %3d  gregory corners %d", m->name, st.edges, st.polynomial_edges, st.gregory_corners);
        if (ok) printf("  fit: spans max %d, G1 %.1e deg (independent %.1e), dev %.1e", r.spans_max, r.g1_max_deg, ang, r.max_dev_rel);
        printf("\n");
        CHECK(st.polynomial_edges >= want, "%s: %d polynomial edges, expected at least %d", m->name, st.polynomial_edges, want);
        CHECK(st.gregory_corners == 0, "%s: %d Gregory corners (mismatch %.3g)", m->name, st.gregory_corners, st.corner_mismatch_max);
        if (ok) CHECK(r.tol_met && ang <= 0.01, "%s: targets %d, independent G1 %.3g deg", m->name, r.tol_met, ang);
    }
    q2n_surface_free(s);
    q2n_mesh_free(m);
}

/* A region bordering regular patches (docs/extraordinary.md, "Exact at the border"): its first ring's
 * vertices are charted with opposite edges opposite, the edges from them to the regular patches'
 * corners glued flat there, and where a component's equations fall short, bumps in β along edges
 * whose β vanishes at both ends.  The whole surface is then G1 to rounding, by the report and by
 * fit_check.h's independent sampling; the smoothsteps' fit of the same mesh is not (the check can
 * fail). */
static void border_exact(q2n_mesh *m)
{
    CHECK(m != NULL, "generator");
    if (!m) return;
    both_run b;
    if (build_both(m, &b)) {
        int interior = interior_edges(m);
        printf("%-40s edges %3d polynomial %3d  gregory corners %d", m->name, b.st.edges, b.st.polynomial_edges, b.st.gregory_corners);
        if (b.ok)
            printf("  fit: %d of %d edges within rounding, G1 %.1e deg (independent %.1e); smoothsteps %d, %.1e deg",
                   b.r.g1_rounding_edges, interior, b.r.g1_max_deg, b.ang, b.r0.g1_rounding_edges, b.r0.g1_max_deg);
        printf("\n");
        CHECK(b.st.gregory_corners == 0, "%s: %d Gregory corners (mismatch %.3g)", m->name, b.st.gregory_corners,
              b.st.corner_mismatch_max);
        if (b.ok) {
            CHECK(b.r.g1_rounding_edges == interior && b.r.g1_max_deg <= 1e-6 && b.ang <= 1e-6,
                  "%s: %d of %d edges within rounding, G1 %.3g deg (independent %.3g)", m->name, b.r.g1_rounding_edges, interior,
                  b.r.g1_max_deg, b.ang);
            CHECK(b.r0.g1_rounding_edges < interior && b.r0.g1_max_deg > 1e-6,
                  "%s: the smoothsteps' fit is exact too (%d edges, %.3g deg)", m->name, b.r0.g1_rounding_edges, b.r0.g1_max_deg);
        }
    }
    both_free(&b);
    q2n_mesh_free(m);
}

/* Shared mesh `path` in G1 mode (G1 patches) through the model, glued by polynomials or, with smooth,
 * by the smoothsteps; 1 when built. */
static int build_model_g1(const char *path, int subdivide, int smooth, q2n_model **m, q2n_error *err)
{
    q2n_model_options o = {0};
    o.method = Q2N_SURFACE_AUGMENTED;
    o.ev_patch = Q2N_EV_PATCH_G1;
    o.subdivide = subdivide;
    o.smooth_gluing = smooth;
    o.threads = 2;
    return q2n_model_build(path, &o, m, err) == Q2N_OK;
}

/* The same on shared meshes whose regions border regular patches, in G1 mode through the model:
 * gismo_octtorus_hole (43 of 54 edges exact before stop 46, G1 4.8e-3 deg) and osd_catmark_pawn
 * (1 140 of 1 164, 8.9e-3 deg; its region around adjacent valence-3 and valence-12 vertices needs 16
 * bumps); osd_catmark_helmet (98 of 103 before stop 47, 7.9e-3 deg: five edges whose q had its ends' sign
 * but less than the quarter of the smaller end the old rule also asked for, ev_fair_gluing.c
 * q_keeps_sign). */
static void border_exact_shared(const char *name)
{
    const char *path = chk_shared_mesh(name);
    if (!path) return; /* reported by chk_shared_mesh */
    q2n_model *mp = NULL;
    q2n_error err = {0, ""};
    int ok = build_model_g1(path, 0, 0, &mp, &err);
    CHECK(ok, "%s: %s", name, err.message);
    q2n_fit_report r;
    double ang = INFINITY;
    if (ok && fit_g1(mp->mesh, mp->surface, &r, &ang)) {
        int interior = interior_edges(mp->mesh);
        printf("%s, G1 patches: %d polynomial edges; fit: %d of %d edges within rounding, G1 %.1e deg (independent %.1e)\n", name,
               mp->ev_stats.polynomial_edges, r.g1_rounding_edges, interior, r.g1_max_deg, ang);
        CHECK(r.g1_rounding_edges == interior && r.g1_max_deg <= 1e-6 && ang <= 1e-6,
              "%s: %d of %d edges within rounding, G1 %.3g deg (independent %.3g)", name, r.g1_rounding_edges, interior,
              r.g1_max_deg, ang);
    }
    q2n_model_free(mp);
}

/* The model's fallback: a plate 400 times thinner than wide, whose G1 patches glued by polynomials
 * fold over (the twist corrections are fixed before the energy solve) where the smoothsteps do not;
 * the model keeps the smoothsteps there, and says so. */
static void fold_fallback(void)
{
    q2n_model_options o = {0};
    o.method = Q2N_SURFACE_AUGMENTED;
    o.ev_patch = Q2N_EV_PATCH_G1;
    q2n_model *m = NULL;
    q2n_error err = {0, ""};
    int ok = q2n_model_build_mesh(mg_thin_plate(7, 0.0025), &o, &m, &err) == Q2N_OK;
    CHECK(ok, "thin plate: %s", err.message);
    if (ok) {
        int said = 0;
        for (int i = 0; i < m->nwarnings; i++) said |= strstr(m->warnings[i], "glued by smoothsteps instead") != NULL;
        printf("thin plate 1 x 1 x 0.0025, 7 x 7 quads, G1 patches: %d faces fold, %d polynomial edges, fallback %s\n", m->folded,
               m->ev_stats.polynomial_edges, said ? "said" : "not said");
        CHECK(m->folded == 0 && m->ev_stats.polynomial_edges == 0 && said, "thin plate: %d folded faces, %d polynomial edges, warning %d",
              m->folded, m->ev_stats.polynomial_edges, said);
    }
    q2n_model_free(m);
}

/* A torus of valence-4 vertices built wholly by the fair construction (the internal entry: the
 * regular patches left out): its corner equations are inconsistent around the handles (residual 1e-3,
 * no edge took the gluing) until the gluing pins the vertex of a failed component's largest residual
 * (ev_fair_gluing.c's pin rounds).  Then at least half of its edges are glued by polynomials, every
 * corner stays compatible and the fit meets its targets. */
static void pinned_cycles(q2n_mesh *m)
{
    CHECK(m != NULL, "generator");
    if (!m) return;
    q2n_param_options po = {0};
    q2n_error err = {0, ""};
    double *iv = NULL;
    q2n_surface *s = q2n_surface_create(m->nf);
    ev_fair_stats st = {0};
    int ok = s && q2n_param_edge_intervals(m, &po, &iv, &err) == Q2N_OK &&
             q2n_ev_fair_build(m, NULL, s, iv, q2n_spline_class_find(Q2N_SPLINE_CLASS_DEFAULT), 1, 0, 1, NULL, 2, &st, &err) == Q2N_OK;
    CHECK(ok, "%s: build: %s", m->name, err.message);
    if (ok) {
        q2n_fit_report r;
        double ang = INFINITY;
        int fitted = fit_g1(m, s, &r, &ang);
        printf("%-40s every face fair: edges %3d polynomial %3d  gregory corners %d", m->name, st.edges, st.polynomial_edges,
               st.gregory_corners);
        if (fitted) printf("  fit: spans max %d, G1 %.1e deg (independent %.1e)", r.spans_max, r.g1_max_deg, ang);
        printf("\n");
        CHECK(2 * st.polynomial_edges >= st.edges && st.edges == 2 * m->nf, "%s: %d of %d edges polynomial", m->name,
              st.polynomial_edges, st.edges);
        CHECK(st.gregory_corners == 0, "%s: %d Gregory corners", m->name, st.gregory_corners);
        if (fitted) CHECK(r.tol_met && ang <= 0.01, "%s: targets %d, independent G1 %.3g deg", m->name, r.tol_met, ang);
    }
    free(iv);
    q2n_surface_free(s);
    q2n_mesh_free(m);
}

/* Smallest |Su x Sv| of patch k on a 17 x 17 grid, over its median there. */
static double jacobian_ratio(const q2n_surface *s, int k)
{
    enum { N = 17 };
    double a[N * N];
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++) {
            double o[9], n[3];
            if (q2n_surface_eval(s, k, (double)i / (N - 1), (double)j / (N - 1), 1, o)) return -1;
            n[0] = o[4] * o[8] - o[5] * o[7], n[1] = o[5] * o[6] - o[3] * o[8], n[2] = o[3] * o[7] - o[4] * o[6];
            a[j * N + i] = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        }
    double mn = a[0];
    for (int q = 1; q < N * N; q++) mn = fmin(mn, a[q]);
    for (int x = 0; x <= N * N / 2; x++) /* the median by selection */
        for (int y = x + 1; y < N * N; y++)
            if (a[y] < a[x]) { double t = a[x]; a[x] = a[y]; a[y] = t; }
    return a[N * N / 2] > 0 ? mn / a[N * N / 2] : 0;
}

/* Shared mesh `path` in G1 mode through the model, with the polynomial gluing (*mp) and with the
 * smoothsteps (*ms); 0 when either build failed (said). */
static int build_model_pair(const char *path, const char *name, int subdivide, q2n_model **mp, q2n_model **ms)
{
    q2n_error err = {0, ""};
    *mp = *ms = NULL;
    int ok = build_model_g1(path, subdivide, 0, mp, &err) && build_model_g1(path, subdivide, 1, ms, &err);
    CHECK(ok, "%s: %s", name, err.message);
    return ok;
}

/* Faces of mp's fair patches whose Jacobian ratio is below half of what ms's give them; the lowest
 * ratio of the two and its face. */
static int sheared_faces(const q2n_model *mp, const q2n_model *ms, double *wr, int *worst)
{
    int bad = 0;
    *wr = INFINITY, *worst = -1;
    for (int k = 0; k < mp->mesh->nf; k++) {
        if (q2n_surface_kind(mp->surface, k) != Q2N_PATCH_COONS_GREGORY) continue;
        double rp = jacobian_ratio(mp->surface, k), rs = jacobian_ratio(ms->surface, k);
        if (rp < 0.5 * rs) bad++;
        if (rs > 0 && rp / rs < *wr) *wr = rp / rs, *worst = k;
    }
    return bad;
}

/* The near-fold guard (ev_fair.c): on a shared mesh whose nearly inconsistent gluing sheared two
 * trapezoids toward a fold (Jacobian ratio 0.031 against the smoothsteps' 0.097), no face's ratio is
 * below half of what the smoothsteps' construction gives it, and the guard says it acted. */
static void near_fold_guard(void)
{
    const char *path = chk_shared_mesh("osd_catmark_righthanded.obj");
    if (!path) return; /* reported by chk_shared_mesh */
    q2n_model *mp, *ms;
    if (build_model_pair(path, "righthanded", 0, &mp, &ms)) {
        int worst;
        double wr;
        int bad = sheared_faces(mp, ms, &wr, &worst);
        printf("righthanded, G1 patches: %d polynomial edges, guard on %d faces; faces below half the smoothsteps' Jacobian "
               "ratio: %d (lowest ratio %.3f, face %d)\n", mp->ev_stats.polynomial_edges, mp->ev_stats.guard_faces, bad, wr, worst);
        CHECK(bad == 0 && mp->ev_stats.guard_faces > 0 && mp->ev_stats.polynomial_edges > 0,
              "righthanded: %d faces nearly folded by the gluing, guard %d, %d polynomial edges", bad, mp->ev_stats.guard_faces,
              mp->ev_stats.polynomial_edges);
    }
    q2n_model_free(mp);
    q2n_model_free(ms);
}

/* The border guard acts locally (ev_fair.c border_shear): on a shared mesh where the flat border
 * edges shear faces (crane_spot `--subdivide 1`; until stop 48 the guard then dropped them on the whole
 * mesh: no border edge, 1 226 of 1 464 edges within rounding), only the cross-charted vertices near the
 * sheared faces give them up.  Border edges remain, the construction stays G1 to rounding (a mixed
 * state of flat and free-slope edges at neighbouring vertices broke it once), no face's Jacobian ratio
 * is below half of what the smoothsteps' construction gives it, and the fit has more edges within
 * rounding than the smoothsteps' (where none are polynomial but the scale-glued ones). */
static void local_border_guard(void)
{
    const char *path = chk_shared_mesh("crane_spot_control_mesh.obj");
    if (!path) return; /* reported by chk_shared_mesh */
    q2n_model *mp, *ms;
    q2n_fit_report r, r0;
    double ang = INFINITY, ang0 = INFINITY;
    if (build_model_pair(path, "crane_spot", 1, &mp, &ms) && fit_g1(mp->mesh, mp->surface, &r, &ang) &&
        fit_g1(ms->mesh, ms->surface, &r0, &ang0)) {
        int worst;
        double wr;
        int bad = sheared_faces(mp, ms, &wr, &worst);
        printf("crane_spot --subdivide 1, G1 patches: %d polynomial edges, %d flat at a regular corner, %d vertices without; "
               "construction G1 %.1e deg; fit: %d of %d edges within rounding (smoothsteps %d); faces below half the "
               "smoothsteps' Jacobian ratio: %d (lowest ratio %.3f, face %d)\n",
               mp->ev_stats.polynomial_edges, mp->ev_stats.border_edges, mp->ev_stats.noflat_vertices, r.g1_construction_deg,
               r.g1_rounding_edges, interior_edges(mp->mesh), r0.g1_rounding_edges, bad, wr, worst);
        CHECK(mp->ev_stats.border_edges > 0 && mp->ev_stats.noflat_vertices > 0, "crane_spot: %d border edges, %d vertices without",
              mp->ev_stats.border_edges, mp->ev_stats.noflat_vertices);
        CHECK(r.g1_construction_deg <= 1e-8 * 180 / M_PI, "crane_spot: construction G1 %.3g deg", r.g1_construction_deg);
        CHECK(bad == 0, "crane_spot: %d faces below half the smoothsteps' Jacobian ratio (lowest %.3f, face %d)", bad, wr, worst);
        CHECK(r.g1_rounding_edges > r0.g1_rounding_edges && r.tol_met, "crane_spot: %d edges within rounding (smoothsteps %d), targets %d",
              r.g1_rounding_edges, r0.g1_rounding_edges, r.tol_met);
    }
    q2n_model_free(mp);
    q2n_model_free(ms);
}

/* The gluing's fairness (docs/extraordinary.md, "Why G2 patches ripple more than G1 patches"): on a
 * mesh whose every edge takes the polynomials, the surface ripples less along the faces' diagonals
 * than with the smoothsteps (flat at both ends, they turn α and β in the middle of every edge), with
 * no more bending energy, by tests/fairness.h's independent figures.  The mesh is freed. */
static void gluing_fairness(q2n_mesh *m, double ratio)
{
    if (!m) { CHECK(0, "mesh"); return; }
    ev_fair_stats st[2];
    q2n_surface *s[2] = {build(m, 1, &st[0]), build(m, 0, &st[1])};
    if (s[0] && s[1]) {
        fair_figures F[2];
        fair_measure(m, s[0], &F[0]);
        fair_measure(m, s[1], &F[1]);
        printf("%s: polynomials osc %.4g E_ev %.4g, smoothsteps %.4g %.4g\n", m->name, F[0].osc_ev_mean, F[0].E_ev, F[1].osc_ev_mean,
               F[1].E_ev);
        CHECK(F[0].osc_ev_mean < ratio * F[1].osc_ev_mean && F[0].E_ev <= F[1].E_ev * 1.01,
              "%s: glued by polynomials the surface ripples %.4g per EV diagonal (bending %.4g), with the smoothsteps %.4g (%.4g)",
              m->name, F[0].osc_ev_mean, F[0].E_ev, F[1].osc_ev_mean, F[1].E_ev);
    }
    q2n_surface_free(s[0]);
    q2n_surface_free(s[1]);
    q2n_mesh_free(m);
}

/* Normal-angle and mean-curvature jumps across every interior edge (fair_edge_jumps) at points down to
 * 1e-3 of the edge from its corners, where sides that disagree at a corner would show (the Coons patch
 * then interpolates neither side's data there). */
static void edge_jumps(const q2n_mesh *m, const q2n_surface *s, double *g1, double *g2)
{
    static const double xs[] = {1e-3, 1e-2, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95, 0.99, 0.999};
    fair_edge_jumps(m, s, xs, (int)(sizeof xs / sizeof xs[0]), g1, g2);
}

/* G2 patches glued by polynomials (ev_fair_gluing2.c, docs/extraordinary.md "Polynomial gluing of G2
 * patches"), on a mesh whose every face touches an extraordinary vertex: every edge takes the gluing
 * (want 1) or some do (want 0), no corner keeps a Gregory blend (both sides agree to EV_FAIR_COMPAT_REL
 * up to order (2, 2)), the surface is G1 and G2 across every edge down to 1e-3 from the corners, and it
 * differs from the smoothsteps' (the gluing acted).  The mesh is freed. */
static void g2_polynomial(q2n_mesh *m, int want_all)
{
    if (!m) { CHECK(0, "mesh"); return; }
    ev_fair_stats st[2];
    q2n_surface *s[2] = {build_k(m, 2, 1, &st[0]), build_k(m, 2, 0, &st[1])};
    if (s[0] && s[1]) {
        int ne = interior_edges(m);
        double g1, g2, e0[18], e1[18];
        edge_jumps(m, s[0], &g1, &g2);
        q2n_surface_eval(s[0], 0, 0.3, 0.6, 2, e0);
        q2n_surface_eval(s[1], 0, 0.3, 0.6, 2, e1);
        printf("%s, G2 patches: %d of %d edges polynomial, %d Gregory corners (mismatch %.2g), G1 %.2g rad, G2 %.2g\n", m->name,
               st[0].polynomial_edges, ne, st[0].gregory_corners, st[0].corner_mismatch_max, g1, g2);
        CHECK(want_all ? st[0].polynomial_edges == ne : st[0].polynomial_edges > 0,
              "%s, G2 patches: %d of %d edges glued by polynomials", m->name, st[0].polynomial_edges, ne);
        CHECK(st[0].gregory_corners == 0 && st[0].corner_mismatch_max <= 1e-9, "%s, G2 patches: %d Gregory corners (mismatch %.3g)",
              m->name, st[0].gregory_corners, st[0].corner_mismatch_max);
        CHECK(g1 <= 1e-8 && g2 <= 1e-6, "%s, G2 patches glued by polynomials: G1 %.3g rad, G2 %.3g across the edges", m->name, g1, g2);
        CHECK(st[1].polynomial_edges == 0 && q2n_v3_dist(e0, e1) > 1e-6, "%s, G2 patches: the smoothsteps' surface differs (%.3g)",
              m->name, q2n_v3_dist(e0, e1));
    }
    q2n_surface_free(s[0]);
    q2n_surface_free(s[1]);
    q2n_mesh_free(m);
}

/* The G2 gluing's fairness (stop 54): on closed meshes whose every face touches an extraordinary vertex
 * the G2 surface glued by polynomials ripples less along the faces' diagonals than glued by the
 * smoothsteps, with at most 1 % more bending energy (tests/fairness.h).  The mesh is freed. */
static void g2_fairness(q2n_mesh *m, double ratio)
{
    if (!m) { CHECK(0, "mesh"); return; }
    ev_fair_stats st[2];
    q2n_surface *s[2] = {build_k(m, 2, 1, &st[0]), build_k(m, 2, 0, &st[1])};
    if (s[0] && s[1]) {
        fair_figures F[2];
        fair_measure(m, s[0], &F[0]);
        fair_measure(m, s[1], &F[1]);
        printf("%s, G2 patches: polynomials osc %.4g E_ev %.4g jac %.3g, smoothsteps %.4g %.4g %.3g\n", m->name, F[0].osc_ev_mean,
               F[0].E_ev, F[0].jac_min, F[1].osc_ev_mean, F[1].E_ev, F[1].jac_min);
        CHECK(F[0].osc_ev_mean < ratio * F[1].osc_ev_mean && F[0].E_ev <= F[1].E_ev * 1.01 && F[0].jac_min > 0.1,
              "%s, G2 patches: glued by polynomials the surface ripples %.4g per EV diagonal (bending %.4g, Jacobian %.3g), with the "
              "smoothsteps %.4g (%.4g)", m->name, F[0].osc_ev_mean, F[0].E_ev, F[0].jac_min, F[1].osc_ev_mean, F[1].E_ev);
    }
    q2n_surface_free(s[0]);
    q2n_surface_free(s[1]);
    q2n_mesh_free(m);
}

static const double cube_v[24] = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1, -1, -1, 1, 1, -1, 1, 1, 1, 1, -1, 1, 1};
static const int cube_f[24] = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7};

/* The cube of six quads (eight valence-3 vertices). */
static q2n_mesh *cube_alone(void)
{
    double *pos = malloc(sizeof cube_v);
    int *fs = malloc(sizeof(int) * 7), *fvv = malloc(sizeof cube_f);
    if (!pos || !fs || !fvv) { free(pos), free(fs), free(fvv); return NULL; }
    memcpy(pos, cube_v, sizeof cube_v);
    memcpy(fvv, cube_f, sizeof cube_f);
    for (int f = 0; f <= 6; f++) fs[f] = 4 * f;
    return mg_finish(8, pos, 6, fs, fvv, "cube");
}

/* Two shells in one mesh: b moved by shift along x after a's vertices and faces (both freed); NULL if
 * either is. */
static q2n_mesh *shells(q2n_mesh *a, q2n_mesh *b, double shift, const char *name)
{
    if (!a || !b) { q2n_mesh_free(a), q2n_mesh_free(b); return NULL; }
    int nv = a->nv + b->nv, nf = a->nf + b->nf, na = a->face_start[a->nf], nfv = na + b->face_start[b->nf];
    double *pos = malloc(sizeof(double) * 3 * (size_t)nv);
    int *fs = malloc(sizeof(int) * ((size_t)nf + 1)), *fvv = malloc(sizeof(int) * (size_t)nfv);
    if (pos && fs && fvv) {
        for (int v = 0; v < nv; v++)
            for (int c = 0; c < 3; c++) pos[3 * v + c] = v < a->nv ? q2n_mesh_vpos(a, v)[c] : q2n_mesh_vpos(b, v - a->nv)[c] + (c == 0 ? shift : 0);
        for (int f = 0; f <= a->nf; f++) fs[f] = a->face_start[f];
        for (int f = 0; f <= b->nf; f++) fs[a->nf + f] = na + b->face_start[f];
        for (int i = 0; i < nfv; i++) fvv[i] = i < na ? a->face_vert[i] : a->nv + b->face_vert[i - na];
    }
    q2n_mesh_free(a), q2n_mesh_free(b);
    if (!pos || !fs || !fvv) { free(pos), free(fs), free(fvv); return NULL; }
    return mg_finish(nv, pos, nf, fs, fvv, name);
}

/* Two shells in one mesh, far apart: a cube (six quads, eight valence-3 vertices) and the icosahedron
 * split into quads: two extraordinary regions. */
static q2n_mesh *cube_and_icosahedron(void)
{
    return shells(cube_alone(), mg_icosa_quad(0, 1), 5, "cube and icosahedron");
}

/* The gluing chosen per region (G2 patches, api/model.c gluing_choice, docs/extraordinary.md "The gluing
 * chosen per region"): on a cube alone the smoothsteps ripple less than the polynomials (every edge's β
 * changes sign), on the icosahedron the polynomials do.  With both in one mesh the default (auto) glues
 * the cube's region by smoothsteps and the icosahedron's by polynomials: the report counts two regions and
 * one given the smoothsteps, the cube's twelve edges leave the polynomial count, each shell's patches are
 * those of its fairer gluing's build (since stop 55 a region's construction depends on its own vertices
 * and the regular patches around it only: the variation weights' median and the twists' unit were taken
 * over every region before, and the cube beside the icosahedron rippled 1.32 glued so against 1.09 by
 * the smoothsteps alone) and the surface stays G1 and G2 across every edge. */
static void gluing_choice(void)
{
    static const int how[3] = {Q2N_EV_GLUING_AUTO, Q2N_EV_GLUING_POLYNOMIAL, Q2N_EV_GLUING_SMOOTHSTEP};
    q2n_model *m[3] = {NULL, NULL, NULL};
    int ok = 1;
    for (int k = 0; k < 3; k++) {
        q2n_model_options o = {0};
        o.method = Q2N_SURFACE_AUGMENTED;
        o.smooth_gluing = how[k];
        o.threads = 2;
        q2n_error err = {0, ""};
        ok &= q2n_model_build_mesh(cube_and_icosahedron(), &o, &m[k], &err) == Q2N_OK;
        CHECK(ok, "cube and icosahedron, gluing %d: %s", how[k], err.message);
    }
    if (ok) {
        /* tests/fairness.h per shell (the cube's six faces come first): [auto, polynomials, smoothsteps][cube, icosahedron] */
        fair_figures F[3][2];
        int nf = m[0]->mesh->nf;
        for (int k = 0; k < 3; k++)
            for (int sh = 0; sh < 2; sh++) fair_measure_range(m[k]->mesh, m[k]->surface, sh ? 6 : 0, sh ? nf : 6, &F[k][sh]);
        /* and patch by patch: the cube's those of the smoothsteps' build, the icosahedron's those of the
         * polynomials' (a region's construction depends on its own vertices and the patches around it) */
        double dev[2] = {0, 0}, g1, g2;
        for (int f = 0; f < nf; f++)
            for (int i = 0; i <= 4; i++)
                for (int j = 0; j <= 4; j++) {
                    double a[3], b[3];
                    q2n_surface_eval(m[0]->surface, f, i / 4.0, j / 4.0, 0, a);
                    q2n_surface_eval(m[f < 6 ? 2 : 1]->surface, f, i / 4.0, j / 4.0, 0, b);
                    dev[f >= 6] = fmax(dev[f >= 6], q2n_v3_dist(a, b));
                }
        /* ... and the cube built alone (its default: the smoothsteps) is the same cube: the same ripple and
         * bending energy (dimensionless: the model works on the mesh scaled to a unit diagonal) */
        q2n_model_options oc = {0};
        oc.method = Q2N_SURFACE_AUGMENTED;
        q2n_model *mc = NULL;
        q2n_error errc = {0, ""};
        fair_figures Fc = {0};
        int okc = q2n_model_build_mesh(cube_alone(), &oc, &mc, &errc) == Q2N_OK;
        if (okc) fair_measure(mc->mesh, mc->surface, &Fc);
        CHECK(okc && mc->gluing_regions[1] == 1 && fabs(Fc.osc_ev_mean - F[0][0].osc_ev_mean) <= 1e-9 * Fc.osc_ev_mean &&
                  fabs(Fc.E_ev - F[0][0].E_ev) <= 1e-9 * Fc.E_ev,
              "the cube alone: ripple %.12g, energy %.12g; beside the icosahedron %.12g, %.12g (%s)", Fc.osc_ev_mean, Fc.E_ev,
              F[0][0].osc_ev_mean, F[0][0].E_ev, errc.message);
        q2n_model_free(mc);
        edge_jumps(m[0]->mesh, m[0]->surface, &g1, &g2);
        printf("cube and icosahedron, G2 patches: %d regions, %d given the smoothsteps, %d polynomial edges (polynomial build %d); "
               "ripple per EV diagonal auto / polynomials / smoothsteps: cube %.4g / %.4g / %.4g, icosahedron %.4g / %.4g / %.4g; "
               "patches from those of the fairer gluing's build %.2g, %.2g; G1 %.2g rad, G2 %.2g\n",
               m[0]->gluing_regions[0], m[0]->gluing_regions[1], m[0]->ev_stats.polynomial_edges, m[1]->ev_stats.polynomial_edges,
               F[0][0].osc_ev_mean, F[1][0].osc_ev_mean, F[2][0].osc_ev_mean, F[0][1].osc_ev_mean, F[1][1].osc_ev_mean,
               F[2][1].osc_ev_mean, dev[0], dev[1], g1, g2);
        /* the premise: each shell's fairer gluing */
        CHECK(F[2][0].osc_ev_mean < 0.8 * F[1][0].osc_ev_mean && F[1][1].osc_ev_mean < 0.8 * F[2][1].osc_ev_mean,
              "premise: cube %.4g / %.4g, icosahedron %.4g / %.4g", F[1][0].osc_ev_mean, F[2][0].osc_ev_mean, F[1][1].osc_ev_mean,
              F[2][1].osc_ev_mean);
        CHECK(m[0]->gluing_regions[0] == 2 && m[0]->gluing_regions[1] == 1 && m[1]->gluing_regions[0] == 0 &&
                  m[2]->gluing_regions[0] == 0,
              "regions %d, smoothsteps %d (polynomial build %d, smoothstep build %d)", m[0]->gluing_regions[0], m[0]->gluing_regions[1],
              m[1]->gluing_regions[0], m[2]->gluing_regions[0]);
        CHECK(m[0]->ev_stats.polynomial_edges + 12 == m[1]->ev_stats.polynomial_edges && m[2]->ev_stats.polynomial_edges == 0,
              "%d polynomial edges (%d in the polynomial build, the cube's 12 among them)", m[0]->ev_stats.polynomial_edges,
              m[1]->ev_stats.polynomial_edges);
        for (int sh = 0; sh < 2; sh++) {
            int fair = sh ? 1 : 2;
            CHECK(F[0][sh].osc_ev_mean <= 1.0001 * F[fair][sh].osc_ev_mean && F[0][sh].E_ev <= 1.0001 * F[fair][sh].E_ev,
                  "shell %d: ripple %.4g, energy %.4g against its fairer gluing's %.4g, %.4g", sh, F[0][sh].osc_ev_mean, F[0][sh].E_ev,
                  F[fair][sh].osc_ev_mean, F[fair][sh].E_ev);
        }
        CHECK(dev[0] <= 1e-12 && dev[1] <= 1e-12, "the cube %.3g from the smoothsteps' build, the icosahedron %.3g from the polynomials'",
              dev[0], dev[1]);
        CHECK(g1 <= 1e-8 && g2 <= 1e-6, "the mixed surface: G1 %.3g rad, G2 %.3g across the edges", g1, g2);
    }
    for (int k = 0; k < 3; k++) q2n_model_free(m[k]);
}

/* The fold fallback where the faces fold (ev_fair.c, docs/extraordinary.md "Where the gluing folds"):
 * a plate 100 times thinner than wide beside a quad icosahedron, G2 patches.  Glued by polynomials the
 * plate folds on 12 faces (the twist corrections of its thin rim) and the smoothsteps fold none; the
 * icosahedron folds nowhere.  Until stop 56 the construction then took the smoothsteps everywhere, the
 * icosahedron's too.  Now the folded faces' neighbourhood leaves the gluing and the rest keeps it: no
 * face folds, the icosahedron keeps every polynomial edge and its patches are those it has alone (its
 * region is solved apart), the plate's are those of its smoothsteps, and the surface is G1 and G2
 * across every edge. */
static void fold_regions(void)
{
    q2n_mesh *u = shells(mg_thin_plate(4, 0.01), mg_icosa_quad(0, 1), 5, "thin plate and icosahedron");
    q2n_mesh *plate = mg_thin_plate(4, 0.01), *ico = mg_icosa_quad(0, 1);
    CHECK(u && plate && ico, "generators");
    ev_fair_stats st[4] = {{0}};
    q2n_surface *s[4] = {NULL, NULL, NULL, NULL}; /* the two shells glued; the icosahedron alone glued; the plate alone, both gluings */
    if (u && plate && ico)
        s[0] = build_k(u, 2, 1, &st[0]), s[1] = build_k(ico, 2, 1, &st[1]), s[2] = build_k(plate, 2, 0, &st[2]), s[3] = build_k(plate, 2, 1, &st[3]);
    if (s[0] && s[1] && s[2] && s[3]) {
        double dev[2] = {0, 0}, g1, g2;
        for (int f = 0; f < u->nf; f++)
            for (int i = 0; i <= 4; i++)
                for (int j = 0; j <= 4; j++) {
                    int ic = f >= plate->nf;
                    double a[3], b[3];
                    q2n_surface_eval(s[0], f, i / 4.0, j / 4.0, 0, a);
                    q2n_surface_eval(s[ic ? 1 : 2], ic ? f - plate->nf : f, i / 4.0, j / 4.0, 0, b);
                    if (ic) a[0] -= 5;
                    dev[ic] = fmax(dev[ic], q2n_v3_dist(a, b));
                }
        edge_jumps(u, s[0], &g1, &g2);
        printf("thin plate 1 x 1 x 0.01 and icosahedron, G2 patches glued by polynomials: %d faces fold, %d polynomial edges "
               "(the icosahedron alone %d, the plate alone %d); patches from the shells' own: plate %.2g, icosahedron %.2g; G1 %.2g "
               "rad, G2 %.2g\n",
               st[0].folded_faces, st[0].polynomial_edges, st[1].polynomial_edges, st[3].polynomial_edges, dev[0], dev[1], g1, g2);
        /* the premise: alone, the plate gives every edge up (its gluing folds), the icosahedron none */
        CHECK(st[3].polynomial_edges == 0 && st[3].folded_faces == 0 && st[2].folded_faces == 0 && st[1].folded_faces == 0 &&
                  st[1].polynomial_edges > 0,
              "premise: the plate alone glued has %d polynomial edges and %d folded faces (%d by smoothsteps); the icosahedron "
              "%d (%d polynomial edges)", st[3].polynomial_edges, st[3].folded_faces, st[2].folded_faces, st[1].folded_faces,
              st[1].polynomial_edges);
        CHECK(st[0].folded_faces == 0 && st[0].polynomial_edges == st[1].polynomial_edges,
              "thin plate and icosahedron: %d faces fold, %d polynomial edges (the icosahedron alone %d)", st[0].folded_faces,
              st[0].polynomial_edges, st[1].polynomial_edges);
        CHECK(dev[0] <= 1e-12 && dev[1] <= 1e-12, "patches against the shells' own: plate %.3g, icosahedron %.3g", dev[0], dev[1]);
        CHECK(g1 <= 1e-8 && g2 <= 1e-6, "thin plate and icosahedron: G1 %.3g rad, G2 %.3g across the edges", g1, g2);
    }
    for (int k = 0; k < 4; k++) q2n_surface_free(s[k]);
    q2n_mesh_free(u), q2n_mesh_free(plate), q2n_mesh_free(ico);
}

/* The same on a shared mesh (G2 patches, the model's defaults): one face of a thin rim folds with the
 * gluing, and until stop 56 every edge then took the smoothsteps.  Now the ring around that face
 * leaves the gluing and the rest keeps it: edges glued by polynomials, no folded face, and the faces at
 * the extraordinary vertices ripple less and bend less than with the smoothsteps everywhere (the
 * model built with --ev-gluing smoothstep: tests/fairness.h, 129 points per diagonal). */
static void fold_ring_shared(void)
{
    const char *path = chk_shared_mesh("osd_catmark_righthanded.obj");
    if (!path) return; /* reported by chk_shared_mesh */
    q2n_model *m[2] = {NULL, NULL};
    int ok = 1;
    for (int k = 0; k < 2; k++) {
        q2n_model_options o = {0};
        o.method = Q2N_SURFACE_AUGMENTED;
        o.smooth_gluing = k ? Q2N_EV_GLUING_SMOOTHSTEP : Q2N_EV_GLUING_AUTO;
        o.threads = 2;
        q2n_error err = {0, ""};
        ok &= q2n_model_build(path, &o, &m[k], &err) == Q2N_OK;
        CHECK(ok, "righthanded, gluing %d: %s", o.smooth_gluing, err.message);
    }
    if (ok) {
        fair_figures F[2];
        for (int k = 0; k < 2; k++) fair_measure(m[k]->mesh, m[k]->surface, &F[k]);
        printf("righthanded, G2 patches: %d polynomial edges, %d folded faces; ripple per EV diagonal %.4g (smoothsteps "
               "everywhere %.4g), E_ev %.4g (%.4g)\n", m[0]->ev_stats.polynomial_edges, m[0]->folded, F[0].osc_ev_mean,
               F[1].osc_ev_mean, F[0].E_ev, F[1].E_ev);
        CHECK(m[0]->continuity == 2 && m[0]->ev_stats.polynomial_edges > 0 && m[0]->folded == 0,
              "righthanded: G%d, %d polynomial edges, %d folded faces", m[0]->continuity, m[0]->ev_stats.polynomial_edges,
              m[0]->folded);
        CHECK(F[0].osc_ev_mean < F[1].osc_ev_mean && F[0].E_ev < F[1].E_ev,
              "righthanded: ripple %.4g against the smoothsteps' %.4g, E_ev %.4g against %.4g", F[0].osc_ev_mean,
              F[1].osc_ev_mean, F[0].E_ev, F[1].E_ev);
    }
    q2n_model_free(m[0]);
    q2n_model_free(m[1]);
}

int main(void)
{
    /* closed, every face at an extraordinary vertex (valences 3, 4, 5 / 3, 4) */
    all_polynomial(mg_icosa_quad(0, 1));
    all_polynomial(mg_icosa_quad(0.05, 3));
    all_polynomial(mg_octa_quad(3, 1, 0.5));
    /* open fans whose rim vertices have two faces (their corners take the twist along the rim, and
     * the spokes' γ are quartics there): straight, convex and reflex rims, odd and even valence */
    all_polynomial(mg_rim_pyramid(5, 1, 1));
    all_polynomial(mg_rim_pyramid(5, 0.5, 1.15));
    all_polynomial(mg_rim_pyramid(7, 1.5, 0.9));
    all_polynomial(mg_rim_pyramid(8, 0.5, 1.15));
    /* two rings around a vertex of valence 5, 6 and 8, open: the rim vertices of two faces keep a free q
     * (flat α, β there leave the even-valence vertices of the first ring without the freedom they need) */
    static const int two_ring_valences[] = {5, 6, 8};
    for (size_t i = 0; i < sizeof two_ring_valences / sizeof two_ring_valences[0]; i++)
        all_polynomial(mg_polar_star(two_ring_valences[i], 2, 1));
    /* a valence-7 vertex with its two rings (open: its rim vertices have three faces and more) and a
     * third ring of regular patches around it: the spokes and the first ring's edges, 3 x 7 */
    partly_polynomial(mg_polar_star(7, 3, 1), 21);
    partly_polynomial(mg_polar_star(5, 3, 4), 15);
    /* two rings around a vertex of valence 3, 4, 5, 7, 8, 12 and a third and fourth of regular patches:
     * exactly G1 through the border (some need bumps in β: the valence-8 one nine) */
    static const struct { int n; double h; } border_stars[] = {{3, 1}, {4, 1.5}, {5, 1}, {7, 1.5}, {8, 1}, {12, 1}};
    for (size_t i = 0; i < sizeof border_stars / sizeof border_stars[0]; i++)
        border_exact(mg_polar_star(border_stars[i].n, 4, border_stars[i].h));
    border_exact_shared("gismo_octtorus_hole.obj");
    border_exact_shared("osd_catmark_pawn.obj");
    border_exact_shared("osd_catmark_helmet.obj");
    /* the gluing's fairness, closed meshes glued by polynomials everywhere (measured, per EV diagonal:
     * 0.186 against 0.220, 0.679 / 0.740, 0.108 / 0.319, 0.363 / 0.379, 0.117 / 0.195) */
    gluing_fairness(mg_icosa_quad(0.05, 3), 0.9);
    gluing_fairness(mg_icosa_quad(0.15, 5), 0.95);
    gluing_fairness(mg_octa_quad(3, 1, 0.5), 0.45);
    gluing_fairness(mg_triacontahedron(2, 1, 0.5, 1), 1);
    {
        double ico[36];
        mg_icosahedron(ico);
        static const double sc[3] = {2, 1, 0.5};
        gluing_fairness(mg_tri_to_quad(12, ico, 20, mg_icosa_tri, 1, sc, 0.03, 11, "icosahedron on a 2:1:0.5 ellipsoid"), 0.7);
    }
    /* G2 patches glued by polynomials: closed meshes whose every face touches an extraordinary vertex
     * (valences 3-5; 3, 4 on an ellipsoid; 3, 5 and 4 on a stretched rhombic polyhedron), and regions
     * around one vertex of valence 5 and 7 bordering regular quads (some edges) */
    g2_polynomial(mg_icosa_quad(0.05, 3), 1);
    g2_polynomial(mg_octa_quad(3, 1, 0.5), 1);
    g2_polynomial(mg_triacontahedron(2, 1, 0.5, 1), 1);
    g2_polynomial(mg_polar_star(5, 3, 1), 0);
    g2_polynomial(mg_polar_star(7, 3, 1), 0);
    g2_fairness(mg_icosa_quad(0, 1), G2_RATIO_ICOSA);
    g2_fairness(mg_icosa_quad(0.05, 3), G2_RATIO_ICOSA_NOISY);
    g2_fairness(mg_triacontahedron(2, 1, 0.5, 1), G2_RATIO_TRIAC);
    gluing_choice();
    fold_fallback();
    fold_regions();
    fold_ring_shared();
    pinned_cycles(mg_torus(8, 6, 3, 1, 0, 1, 1));
    pinned_cycles(mg_torus(10, 8, 3, 1, 0.15, 1, 7));
    near_fold_guard();
    local_border_guard();
    CHECK_DONE("test_ev_gluing");
}
