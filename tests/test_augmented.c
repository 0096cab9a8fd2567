/* test_augmented.c — regular augmented patches (seed 003 §3) against independent references:
 *  - every mesh vertex interpolated (corners = mesh vertices), relative to the bbox diagonal;
 *  - first and second partial derivatives vs central finite differences;
 *  - Proposition 1: a patch boundary equals the univariate spline of its section polyline,
 *    the polyline found by walking the mesh (q2n_mesh_continue), not by the patch's stencil;
 *  - Proposition 2: cross-boundary derivatives of neighbours satisfy eq. (13)-(14) for r <= k,
 *    with the scaling Δ built from the mesh's edge intervals (eq. 7, 14);
 *  - the mean parametrization gives rectangles (tensor-product patches: δ constant);
 *  - the face parametrization of patch/surface.h (corner and side tables, side frames and their
 *    chain rule) against the table written out and finite differences;
 *  - the exact corner hook (mixed partials up to ∂u²∂v²) against converging one-sided differences. */
#include "check.h"
#include "meshgen.h"
#include "core/vec3.h"
#include "param/param.h"
#include "patch/augmented.h"

/* The face parametrization of patch/surface.h, checked against the table written out here
 * (corners (0,0), (1,0), (1,1), (0,1); side i from corner i to i+1; inward = towards corner i+3)
 * and its chain rule against finite differences of a polynomial in (u, v). */
static void poly_uv(double u, double v, double e[Q2N_EVAL_MAX])
{
    for (int c = 0; c < 3; c++) { /* S = (u^3 v + 2 u^2, u v^2 - v^3 + u, 3 u v + v^2), component c */
        double P[3] = {u * u * u * v + 2 * u * u, u * v * v - v * v * v + u, 3 * u * v + v * v};
        double Pu[3] = {3 * u * u * v + 4 * u, v * v + 1, 3 * v}, Pv[3] = {u * u * u, 2 * u * v - 3 * v * v, 3 * u + 2 * v};
        double Puu[3] = {6 * u * v + 4, 0, 0}, Puv[3] = {3 * u * u, 2 * v, 3}, Pvv[3] = {0, 2 * u - 6 * v, 2};
        e[c] = P[c], e[Q2N_EV_U + c] = Pu[c], e[Q2N_EV_V + c] = Pv[c];
        e[Q2N_EV_UU + c] = Puu[c], e[Q2N_EV_UV + c] = Puv[c], e[Q2N_EV_VV + c] = Pvv[c];
    }
}

static void test_conventions(void)
{
    static const int corner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    int ok_table = 1, ok_fd = 1;
    double worst = 0;
    for (int i = 0; i < 4; i++) {
        const int *c0 = corner[i], *c1 = corner[(i + 1) % 4], *c3 = corner[(i + 3) % 4];
        double u, v;
        ok_table &= q2n_corner_uv[i][0] == c0[0] && q2n_corner_uv[i][1] == c0[1];
        ok_table &= q2n_side_along[i][0] == c1[0] - c0[0] && q2n_side_along[i][1] == c1[1] - c0[1];
        ok_table &= q2n_side_inward[i][0] == c3[0] - c0[0] && q2n_side_inward[i][1] == c3[1] - c0[1];
        q2n_side_uv(i, 0, 0, &u, &v);
        ok_table &= u == c0[0] && v == c0[1];
        q2n_side_uv(i, 1, 0, &u, &v);
        ok_table &= u == c1[0] && v == c1[1];
        q2n_side_uv(i, 0.5, 0.25, &u, &v); /* a quarter of the way towards the opposite side */
        ok_table &= u == 0.5 * (c0[0] + c1[0]) + 0.25 * (c3[0] - c0[0]) && v == 0.5 * (c0[1] + c1[1]) + 0.25 * (c3[1] - c0[1]);
        int au = c1[1] == c0[1]; /* the side runs along u */
        ok_table &= q2n_side_along_u(i) == au;
        /* the cross coordinate: its value on the side and the sign of the inward direction on it */
        int cross = au ? 1 : 0;
        ok_table &= q2n_side_level[i] == c0[cross] && q2n_side_iota[i] == c3[cross] - c0[cross];
        /* the patch-coordinate parameter runs from the corner with the smaller coordinate */
        int first = c0[1 - cross] < c1[1 - cross] ? i : (i + 1) % 4;
        ok_table &= q2n_side_first(i) == first && q2n_side_last(i) == (first == i ? (i + 1) % 4 : i);
        ok_table &= q2n_side_forward(i) == (first == i);
        ok_table &= q2n_corner_at(c0[0], c0[1]) == i;
        /* chain rule: frame derivatives against differences of the polynomial along t and s */
        double t = 0.3, s = 0.2, h = 1e-4, e[Q2N_EVAL_MAX], D[6][3], pp[4][Q2N_EVAL_MAX];
        q2n_side_uv(i, t, s, &u, &v);
        poly_uv(u, v, e);
        q2n_side_derivs(i, 2, e, D);
        static const double st[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
        for (int q = 0; q < 4; q++) {
            q2n_side_uv(i, t + h * st[q][0], s + h * st[q][1], &u, &v);
            poly_uv(u, v, pp[q]);
        }
        for (int c = 0; c < 3; c++) {
            double Dt = (pp[0][Q2N_EV_S + c] - pp[1][Q2N_EV_S + c]) / (2 * h);
            double Ds = (pp[2][Q2N_EV_S + c] - pp[3][Q2N_EV_S + c]) / (2 * h);
            double Dtt = (pp[0][Q2N_EV_S + c] - 2 * e[c] + pp[1][Q2N_EV_S + c]) / (h * h);
            double Dss = (pp[2][Q2N_EV_S + c] - 2 * e[c] + pp[3][Q2N_EV_S + c]) / (h * h);
            /* ∂ts from the t-differences of ∂s */
            double Dts = ((pp[0][Q2N_EV_U + c] - pp[1][Q2N_EV_U + c]) * q2n_side_inward[i][0] +
                          (pp[0][Q2N_EV_V + c] - pp[1][Q2N_EV_V + c]) * q2n_side_inward[i][1]) / (2 * h);
            double err[5] = {fabs(D[1][c] - Dt), fabs(D[2][c] - Ds), fabs(D[3][c] - Dtt), fabs(D[4][c] - Dts),
                             fabs(D[5][c] - Dss)};
            ok_fd &= D[0][c] == e[c];
            for (int k = 0; k < 5; k++) worst = fmax(worst, err[k]);
        }
    }
    CHECK(ok_table, "surface.h conventions match the table (corners, sides, inward, iota, level, first/last)");
    CHECK(ok_fd && worst < 1e-6, "side-frame chain rule vs finite differences: %.3g", worst);
}

/* r-th inward cross derivative (r = 0..2) on side c at t. */
static void cross_deriv(const q2n_surface *S, int f, int c, double t, int r, double out[3])
{
    double u, v, e[Q2N_EVAL_MAX], D[6][3];
    q2n_side_uv(c, t, 0, &u, &v);
    q2n_surface_eval(S, f, u, v, 2, e);
    q2n_side_derivs(c, 2, e, D);
    memcpy(out, D[r == 0 ? 0 : r == 1 ? 2 : 5], sizeof D[0]);
}

/* Local parametrization function across side c of face f at t: blend of the intervals of
 * the two face edges leaving the side's ends (eq. 7), computed from the mesh. */
static double cross_delta(const q2n_mesh *m, const double *iv, int k, int f, int c, double t)
{
    int h = q2n_face_he(m, f, c);
    int a = m->he_edge[q2n_he_prev(m, h)], b = m->he_edge[q2n_he_next(m, h)];
    double o[4];
    q2n_spline_blend_derivs(k, iv[a], iv[b], t, o); /* edge at the side's start, then at its end */
    return o[0];
}

typedef struct stats { double interp, fd1, fd2, prop1, prop2, grid; int covered, edges; } stats;

static void check_mesh(const char *label, const q2n_mesh *m, const char *clsname, q2n_param_method pm,
                       int expect_all, stats *st)
{
    q2n_augmented_options opt = {q2n_spline_class_find(clsname), {pm, -1}};
    q2n_surface *S = NULL;
    q2n_error err;
    double *iv = NULL;
    memset(st, 0, sizeof *st);
    CHECK(q2n_param_edge_intervals(m, &opt.param, &iv, &err) == Q2N_OK, "intervals %s", label);
    CHECK(q2n_augmented_build(m, &opt, NULL, &S, &err) == Q2N_OK, "build %s: %s", label, err.message);
    if (!S || !iv) { free(iv); return; }
    double diag = q2n_mesh_bbox_diag(m);
    int k = opt.cls->k;
    st->covered = q2n_surface_count(S, Q2N_PATCH_AUGMENTED);
    if (expect_all) CHECK(st->covered == m->nf, "%s: %d of %d faces covered", label, st->covered, m->nf);
    unsigned seed = 3;
    for (int f = 0; f < m->nf; f++) {
        /* the surface stores the patch compactly (grid points as indices into a pool of the mesh's
         * vertices and the extrapolated points): expanded, it is the patch q2n_augmented_setup
         * builds, and the surface evaluates exactly as that patch does */
        q2n_augmented_patch A, B;
        memset(&A, 0, sizeof A);
        memset(&B, 0, sizeof B);
        int has = q2n_augmented_setup(m, f, opt.cls, &opt.param, iv, &A);
        int got = q2n_augmented_patch_get(S, f, &B);
        CHECK(has == got && (q2n_surface_kind(S, f) == Q2N_PATCH_AUGMENTED) == got, "%s face %d: stored %d, setup %d", label,
              f, got, has);
        if (has && got) {
            CHECK(!memcmp(&A, &B, sizeof A), "%s face %d: stored patch differs from its setup", label, f);
            double e1[Q2N_EVAL_MAX], e2[Q2N_EVAL_MAX], uu = 0.1 + 0.8 * mg_rnd(&seed), vv = 0.1 + 0.8 * mg_rnd(&seed);
            q2n_surface_eval(S, f, uu, vv, 2, e1);
            q2n_augmented_eval(&A, uu, vv, 2, e2);
            CHECK(!memcmp(e1, e2, sizeof e1), "%s face %d: surface and patch evaluate differently", label, f);
        }
        if (q2n_surface_kind(S, f) != Q2N_PATCH_AUGMENTED) continue;
        for (int c = 0; c < 4; c++) { /* interpolation of the corners */
            double e[Q2N_EVAL_MAX];
            q2n_surface_eval(S, f, q2n_corner_uv[c][0], q2n_corner_uv[c][1], 0, e);
            const double *p = q2n_mesh_vpos(m, m->face_vert[m->face_start[f] + c]);
            st->interp = fmax(st->interp, q2n_v3_dist(e, p) / diag);
        }
        for (int t = 0; t < 2; t++) { /* finite differences */
            double u = 0.05 + 0.9 * mg_rnd(&seed), v = 0.05 + 0.9 * mg_rnd(&seed), hh = 1e-5;
            double e[Q2N_EVAL_MAX], a[Q2N_EVAL_MAX], b[Q2N_EVAL_MAX], c2[Q2N_EVAL_MAX], d2[Q2N_EVAL_MAX];
            q2n_surface_eval(S, f, u, v, 2, e);
            q2n_surface_eval(S, f, u - hh, v, 2, a);
            q2n_surface_eval(S, f, u + hh, v, 2, b);
            q2n_surface_eval(S, f, u, v - hh, 2, c2);
            q2n_surface_eval(S, f, u, v + hh, 2, d2);
            double scale = fmax(q2n_v3_norm(e + 3), q2n_v3_norm(e + 6));
            for (int q = 0; q < 3; q++) {
                st->fd1 = fmax(st->fd1, fabs((b[q] - a[q]) / (2 * hh) - e[3 + q]) / scale);
                st->fd1 = fmax(st->fd1, fabs((d2[q] - c2[q]) / (2 * hh) - e[6 + q]) / scale);
                st->fd2 = fmax(st->fd2, fabs((b[3 + q] - a[3 + q]) / (2 * hh) - e[9 + q]) / scale);
                st->fd2 = fmax(st->fd2, fabs((b[6 + q] - a[6 + q]) / (2 * hh) - e[12 + q]) / scale);
                st->fd2 = fmax(st->fd2, fabs((d2[3 + q] - c2[3 + q]) / (2 * hh) - e[12 + q]) / scale);
                st->fd2 = fmax(st->fd2, fabs((d2[6 + q] - c2[6 + q]) / (2 * hh) - e[15 + q]) / scale);
            }
        }
    }
    /* the grid fast path equals point-by-point evaluation */
    double us[5] = {0, 0.13, 0.5, 0.77, 1}, vs[3] = {0.05, 0.5, 1}, gbuf[9 * 15];
    for (int f = 0; f < m->nf; f++) {
        if (q2n_surface_kind(S, f) != Q2N_PATCH_AUGMENTED) continue;
        q2n_surface_eval_grid(S, f, 5, us, 3, vs, gbuf);
        for (int b = 0; b < 3; b++)
            for (int a = 0; a < 5; a++) {
                double e[Q2N_EVAL_MAX];
                q2n_surface_eval(S, f, us[a], vs[b], 1, e);
                for (int q = 0; q < 9; q++)
                    st->grid = fmax(st->grid, fabs(e[q] - gbuf[9 * (b * 5 + a) + q]) / diag);
            }
    }
    /* Proposition 1 on closed section polylines walked through the mesh */
    const q2n_spline_class *cls = opt.cls;
    double alpha = q2n_param_alpha(&opt.param);
    for (int f = 0; f < m->nf && pm != Q2N_PARAM_MEAN; f++) {
        if (q2n_surface_kind(S, f) != Q2N_PATCH_AUGMENTED) continue;
        int h0 = q2n_face_he(m, f, 0), h = h0, n = 0, cap = m->nh + 1;
        double *pts = malloc(3 * (size_t)cap * sizeof *pts), *ivs = malloc((size_t)cap * sizeof *ivs);
        do {
            memcpy(pts + 3 * n++, q2n_mesh_vpos(m, q2n_he_origin(m, h)), 3 * sizeof(double));
            h = q2n_mesh_continue(m, h);
        } while (h >= 0 && h != h0 && n < cap);
        if (h == h0 && n >= cls->w) {
            for (int j = 0; j < n; j++) ivs[j] = q2n_param_interval(pts + 3 * j, pts + 3 * ((j + 1) % n), alpha);
            for (int t = 0; t <= 8; t++) {
                double u = t / 8.0, ref[3], e[Q2N_EVAL_MAX];
                q2n_spline_curve_eval(cls, n, 3, pts, ivs, 1, 0, u * ivs[0], 0, ref);
                q2n_surface_eval(S, f, u, 0, 0, e);
                st->prop1 = fmax(st->prop1, q2n_v3_dist(ref, e) / diag);
            }
        }
        free(pts);
        free(ivs);
    }
    /* Proposition 2 across every interior edge between two regular patches */
    for (int hA = 0; hA < m->nh; hA++) {
        int hB = m->he_twin[hA];
        if (hB < 0 || hB < hA) continue;
        int fA = m->he_face[hA], fB = m->he_face[hB];
        if (q2n_surface_kind(S, fA) != Q2N_PATCH_AUGMENTED || q2n_surface_kind(S, fB) != Q2N_PATCH_AUGMENTED)
            continue;
        int cA = hA - m->face_start[fA], cB = hB - m->face_start[fB];
        st->edges++;
        for (int t = 0; t <= 8; t++) {
            double tA = t / 8.0, tB = 1 - tA;
            double dA = cross_delta(m, iv, k, fA, cA, tA), dB = cross_delta(m, iv, k, fB, cB, tB);
            double rA[3], rB[3], first = 0;
            for (int r = 0; r <= k && r <= 2; r++) {
                cross_deriv(S, fA, cA, tA, r, rA);
                cross_deriv(S, fB, cB, tB, r, rB);
                /* eq. (13): ∂^r_s S_A / δ_A^r = (-1)^r ∂^r_s S_B / δ_B^r  (s inward on each side) */
                double sa = pow(dA, -r), sb = (r % 2 ? -1 : 1) * pow(dB, -r), res[3], sc;
                for (int q = 0; q < 3; q++) res[q] = sa * rA[q] - sb * rB[q];
                sc = fmax(fmax(q2n_v3_norm(rA) * fabs(sa), q2n_v3_norm(rB) * fabs(sb)), 1e-300);
                if (r == 0) sc = diag;
                if (r == 1) first = sc;
                if (r == 2) sc = fmax(sc, first * first / diag); /* flat regions: curvature ~ 0 */
                st->prop2 = fmax(st->prop2, q2n_v3_norm(res) / sc);
            }
        }
    }
    printf("%-28s %-9s %-11s faces %4d/%-4d interp %.1e  fd1 %.1e fd2 %.1e  prop1 %.1e  prop2 %.1e (%d edges)\n",
           label, clsname, q2n_param_method_name(pm), st->covered, m->nf, st->interp, st->fd1, st->fd2,
           st->prop1, st->prop2, st->edges);
    CHECK(st->interp <= 1e-12, "%s: vertex interpolation %.3g", label, st->interp);
    CHECK(st->fd1 <= 1e-6, "%s: first derivatives vs FD %.3g", label, st->fd1);
    CHECK(st->fd2 <= 1e-5, "%s: second derivatives vs FD %.3g", label, st->fd2);
    CHECK(st->prop1 <= 1e-12, "%s: Proposition 1 %.3g", label, st->prop1);
    CHECK(st->prop2 <= 1e-9, "%s: Proposition 2 %.3g", label, st->prop2);
    CHECK(st->grid <= 1e-13, "%s: grid evaluation vs point evaluation %.3g", label, st->grid);
    free(iv);
    q2n_surface_free(S);
}

/* The mean parametrization yields tensor-product patches: along every edge the cross
 * parametrization function is constant, so Proposition 2 holds with Δ = 1 ... and the patch's
 * opposite intervals agree. */
static void check_mean_rectangles(const q2n_mesh *m)
{
    q2n_param_options po = {Q2N_PARAM_MEAN, -1};
    const q2n_spline_class *cls = q2n_spline_class_find("D5C2P2S4");
    double *iv = NULL;
    q2n_error err;
    CHECK(q2n_param_edge_intervals(m, &po, &iv, &err) == Q2N_OK, "mean intervals");
    double worst = 0;
    for (int f = 0; f < m->nf; f++) {
        q2n_augmented_patch p;
        if (!q2n_augmented_setup(m, f, cls, &po, iv, &p)) continue;
        for (int i = 0; i < p.w - 1; i++) {
            worst = fmax(worst, fabs(p.drow[0][i] - p.drow[1][i]));
            worst = fmax(worst, fabs(p.ecol[0][i] - p.ecol[1][i]));
        }
    }
    CHECK(worst < 1e-14, "mean parametrization: faces are rectangles (%.3g)", worst);
    free(iv);
}

/* The exact corner hook (q2n_surface_corner_mixed): ∂u^a ∂v^b S, a, b = 1, 2, at every corner of
 * every patch against one-sided second-order differences of the evaluated second derivatives
 * (S_uv exact; S_uuv, S_uvv from S_uv by 3 points, S_uuvv from S_uu by 4), at h and h/2: the error
 * must be the differences' own truncation (it falls ~4x when h halves), relative to |S_u| + |S_v|. */
static void check_corner_hook(const char *label, const q2n_surface *s, int nf)
{
    double worst[2] = {0, 0};
    int n = 0, bad = 0;
    for (int k = 0; k < nf; k++) {
        if (q2n_surface_kind(s, k) != Q2N_PATCH_AUGMENTED) continue;
        for (int c = 0; c < 4; c++) {
            int i = c & 1, j = c >> 1;
            double X[2][2][2][3];
            if (q2n_surface_corner_mixed(s, k, i, j, X) != Q2N_OK) { bad++; continue; }
            if (memcmp(X[0], X[1], sizeof X[0])) bad++;
            const double *H[4] = {X[0][0][0], X[0][1][0], X[0][0][1], X[0][1][1]};
            for (int lev = 0; lev < 2; lev++) {
                double h = lev ? 5e-4 : 1e-3, su = i ? -1 : 1, sv = j ? -1 : 1, o[6][Q2N_EVAL_MAX];
                q2n_surface_eval(s, k, i, j, 2, o[0]);
                q2n_surface_eval(s, k, i + su * h, j, 2, o[1]);
                q2n_surface_eval(s, k, i + 2 * su * h, j, 2, o[2]);
                q2n_surface_eval(s, k, i, j + sv * h, 2, o[3]);
                q2n_surface_eval(s, k, i, j + 2 * sv * h, 2, o[4]);
                q2n_surface_eval(s, k, i, j + 3 * sv * h, 2, o[5]);
                double scale = q2n_v3_norm(o[0] + Q2N_EV_U) + q2n_v3_norm(o[0] + Q2N_EV_V), e = 0;
                for (int q = 0; q < 3; q++) {
                    double F[4] = {o[0][Q2N_EV_UV + q],
                                   su * (-3 * o[0][Q2N_EV_UV + q] + 4 * o[1][Q2N_EV_UV + q] - o[2][Q2N_EV_UV + q]) / (2 * h),
                                   sv * (-3 * o[0][Q2N_EV_UV + q] + 4 * o[3][Q2N_EV_UV + q] - o[4][Q2N_EV_UV + q]) / (2 * h),
                                   (2 * o[0][Q2N_EV_UU + q] - 5 * o[3][Q2N_EV_UU + q] + 4 * o[4][Q2N_EV_UU + q] -
                                    o[5][Q2N_EV_UU + q]) / (h * h)};
                    for (int t = 0; t < 4; t++) e = fmax(e, fabs(H[t][q] - F[t]) / scale);
                }
                worst[lev] = fmax(worst[lev], e);
            }
            n++;
        }
    }
    printf("  %s: corner hook at %d corners vs differences: %.2e (h 1e-3), %.2e (h 5e-4)\n", label, n, worst[0],
           worst[1]);
    CHECK(bad == 0 && n > 0, "%s: %d corners without the hook or with disagreeing sides", label, bad);
    CHECK(worst[1] < 1e-3 && (worst[1] < 1e-9 || worst[1] < 0.35 * worst[0]),
          "%s: corner hook vs differences %g (h) / %g (h/2): not converging to it", label, worst[0], worst[1]);
}

int main(void)
{
    test_conventions();
    stats st;
    /* zeroed options are the defaults: centripetal, alpha 1/2 (eq. 6) */
    q2n_param_options zero;
    memset(&zero, 0, sizeof zero);
    CHECK(zero.method == Q2N_PARAM_CENTRIPETAL && q2n_param_alpha(&zero) == 0.5, "zeroed options: alpha 1/2");
    q2n_param_options uni = {Q2N_PARAM_UNIFORM, 0.7}, cho = {Q2N_PARAM_CHORDAL, 0.7};
    CHECK(q2n_param_alpha(&uni) == 0 && q2n_param_alpha(&cho) == 1, "uniform / chordal exponents");
    double a[3] = {0, 0, 0}, b[3] = {3, 4, 0};
    CHECK_NEAR(q2n_param_interval(a, b, 0.5), sqrt(5.0), 1e-15, "centripetal interval |5|^1/2");
    /* regular meshes by others; gismo_octtorus_hole has extraordinary boundary vertices, whose
     * faces the regular construction leaves uncovered */
    static const struct { const char *file; int all_covered; } shared_regular[] = {
        {"osd_catmark_torus.obj", 1}, {"gismo_octtorus.obj", 1},           {"osd_catmark_flap.obj", 1},
        {"osd_catmark_tent.obj", 1},  {"osd_catmark_square_hedit0.obj", 1}, {"gismo_octtorus_hole.obj", 0}};
    static const struct { const char *cls; q2n_param_method pm; } variants[] = {
        {"D5C2P2S4", Q2N_PARAM_CENTRIPETAL}, {"D3C1P2S4", Q2N_PARAM_CENTRIPETAL}, {"D5C2P2S4", Q2N_PARAM_MEAN}};
    for (size_t i = 0; i < sizeof shared_regular / sizeof *shared_regular; i++) {
        const char *file = shared_regular[i].file, *path = chk_shared_mesh(file);
        if (!path) continue;
        q2n_mesh *m = NULL;
        q2n_error err;
        CHECK(q2n_mesh_read_obj(path, &m, &err) == Q2N_OK, "read %s: %s", path, err.message);
        if (!m) continue;
        int all = shared_regular[i].all_covered;
        for (size_t k = 0; k < sizeof variants / sizeof *variants; k++)
            check_mesh(file, m, variants[k].cls, variants[k].pm, all, &st);
        if (!all) CHECK(st.covered > 0 && st.covered < m->nf, "%s: partial coverage reported", file);
        check_mean_rectangles(m);
        q2n_mesh_free(m);
    }
    for (unsigned seed = 1; seed <= 3; seed++) { /* randomly perturbed tori */
        q2n_mesh *m = mg_torus(12, 8, 3.0, 1.0, 0.15, 1, seed);
        CHECK(m != NULL, "torus");
        if (!m) continue;
        char label[64];
        snprintf(label, sizeof label, "perturbed torus #%u", seed);
        for (const q2n_spline_class *const *c = q2n_spline_classes(); *c; c++) {
            check_mesh(label, m, (*c)->name, Q2N_PARAM_CENTRIPETAL, 1, &st);
            double *iv = NULL;
            q2n_surface *s = NULL;
            q2n_param_options po = {Q2N_PARAM_CENTRIPETAL, 0.5};
            q2n_augmented_options ao = {*c, po};
            q2n_error err;
            if (q2n_param_edge_intervals(m, &po, &iv, &err) == Q2N_OK && q2n_augmented_build(m, &ao, iv, &s, &err) == Q2N_OK) {
                char l2[96];
                snprintf(l2, sizeof l2, "%s, %s", label, (*c)->name);
                check_corner_hook(l2, s, m->nf);
            } else CHECK(0, "%s: build: %s", label, err.message);
            q2n_surface_free(s);
            free(iv);
        }
        check_mesh(label, m, "D5C2P2S4", Q2N_PARAM_CHORDAL, 1, &st);
        check_mesh(label, m, "D5C2P2S4", Q2N_PARAM_MEAN, 1, &st);
        q2n_mesh_free(m);
    }
    q2n_mesh *g = mg_grid(6, 5, 9); /* open regular grid: extrapolated layer */
    CHECK(g != NULL, "grid");
    if (g) {
        for (const q2n_spline_class *const *c = q2n_spline_classes(); *c; c++)
            check_mesh("open grid 6x5", g, (*c)->name, Q2N_PARAM_CENTRIPETAL, 1, &st);
        check_mesh("open grid 6x5", g, "D5C2P2S4", Q2N_PARAM_MEAN, 1, &st);
        check_mean_rectangles(g);
        q2n_mesh_free(g);
    }
    CHECK_DONE("test_augmented");
}
