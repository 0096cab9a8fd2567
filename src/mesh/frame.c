/* frame.c — the mesh's isotropic frame: the linear map under which its faces are most nearly
 * isotropic (docs/extraordinary.md, "The isotropic frame").
 *
 * At a vertex v, T_v = sum e e^T over the edges e of the faces at v, projected on the tangent
 * plane (normal: the faces' summed vector area), is the second moment of the mesh's edges there;
 * with an orthonormal tangent basis B = [t1 t2] and M_v the 2 x 2 moment in that basis, normalised
 * to trace 1, C_v = B M_v^(1/2) is a 3 x 2 factor of T_v / tr.  The edges mapped by a linear A
 * are isotropic in their plane (their moment a multiple of the plane's identity) exactly when
 *     X_v = C_v^T G C_v,  G = A^T A,
 * is a multiple of the 2 x 2 identity: X_11 - X_22 = 0 and X_12 = 0, two equations linear in the
 * six entries of G.  Each vertex's pair is divided by tr X_v, so that it weighs the same whatever
 * its size in the mapped frame (|r_v|^2 = 1 - 4 det X_v / tr^2 X_v: 0 isotropic, 1 collinear), and
 * the sum over all vertices is minimised over G = exp(S), S symmetric and traceless (det G = 1:
 * the residuals do not see G's scale), by Gauss–Newton, with a ridge on S of weight
 * Q2N_FRAME_RIDGE per vertex: directions the faces leave free (a flat mesh's normal) stay as they
 * are.  A = G^(1/2) = exp(S / 2), symmetric, determinant 1.
 *
 * If the mesh is the image S p of a mesh whose vertex moments are all isotropic, G = S^-T S^-1 solves
 * every equation exactly and A undoes S up to a rotation; the estimate is covariant: the frame of S
 * times a mesh is the frame of the mesh composed with S^-1 (up to the ridge). */
#include "mesh/mesh.h"
#include "mesh/mesh_policy.h"

#include "core/dense.h"
#include "core/vec3.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Eigen-decomposition of a symmetric 3 x 3 matrix by cyclic Jacobi rotations: S = V diag(w) V^T,
 * V's columns the eigenvectors. */
static void sym3_eigen(const double S[3][3], double w[3], double V[3][3])
{
    double a[3][3];
    memcpy(a, S, sizeof a);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) V[i][j] = i == j;
    for (int sweep = 0; sweep < 50; sweep++) {
        double off = fabs(a[0][1]) + fabs(a[0][2]) + fabs(a[1][2]);
        if (!(off > 1e-300)) break;
        for (int p = 0; p < 2; p++)
            for (int q = p + 1; q < 3; q++) {
                if (a[p][q] == 0) continue;
                double th = 0.5 * (a[q][q] - a[p][p]) / a[p][q];
                double t = (th >= 0 ? 1 : -1) / (fabs(th) + sqrt(th * th + 1)), c = 1 / sqrt(t * t + 1), s = t * c;
                for (int k = 0; k < 3; k++) { /* a <- J^T a J, J the rotation in the (p, q) plane */
                    double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < 3; k++) {
                    double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 3; k++) {
                    double vkp = V[k][p], vkq = V[k][q];
                    V[k][p] = c * vkp - s * vkq;
                    V[k][q] = s * vkp + c * vkq;
                }
            }
    }
    for (int i = 0; i < 3; i++) w[i] = a[i][i];
}

/* C_v of vertex v (above) into C (3 x 2); 0 where v has no faces, no tangent plane or its edges
 * are (nearly) collinear in it. */
static int vertex_factor(const q2n_mesh *m, int v, double C[3][2])
{
    int h0 = m->vert_he[v];
    if (h0 < 0) return 0;
    double n[3] = {0, 0, 0}, t1[3], t2[3], M[3] = {0, 0, 0}; /* M: xx, xy, yy */
    int faces[Q2N_FRAME_FAN_MAX], nfc = 0;
    for (int h = h0; h >= 0 && nfc < Q2N_FRAME_FAN_MAX;) { /* the faces at v: its outgoing half-edges' faces */
        faces[nfc++] = m->he_face[h];
        h = q2n_mesh_rotate(m, h);
        if (h == h0) break;
    }
    for (int q = 0; q < nfc; q++) {
        double a[3];
        q2n_mesh_face_area(m, faces[q], a);
        q2n_v3_add(n, n, a);
    }
    double nl = q2n_v3_norm(n);
    if (!(nl > 0)) return 0;
    q2n_v3_scale(n, 1 / nl, n);
    double x[3] = {1, 0, 0};
    if (fabs(n[0]) > 0.6) x[0] = 0, x[1] = 1; /* any direction well away from n */
    q2n_v3_cross(t1, n, x);
    q2n_v3_scale(t1, 1 / q2n_v3_norm(t1), t1);
    q2n_v3_cross(t2, n, t1);
    for (int q = 0; q < nfc; q++) {
        int s0 = m->face_start[faces[q]], ns = m->face_start[faces[q] + 1] - s0;
        for (int i = 0; i < ns; i++) {
            double e[3];
            q2n_v3_sub(e, q2n_mesh_vpos(m, m->face_vert[s0 + (i + 1) % ns]), q2n_mesh_vpos(m, m->face_vert[s0 + i]));
            double ex = q2n_v3_dot(e, t1), ey = q2n_v3_dot(e, t2);
            M[0] += ex * ex, M[1] += ex * ey, M[2] += ey * ey;
        }
    }
    double tr = M[0] + M[2];
    if (!(tr > 0)) return 0;
    for (int i = 0; i < 3; i++) M[i] /= tr;
    double det = M[0] * M[2] - M[1] * M[1];
    if (!(det > Q2N_FRAME_MIN_DET)) return 0;
    /* M^(1/2) = (M + sqrt(det) I) / sqrt(tr M + 2 sqrt(det)) for a symmetric positive 2 x 2 M */
    double sd = sqrt(det), d = sqrt(1 + 2 * sd), R[3] = {(M[0] + sd) / d, M[1] / d, (M[2] + sd) / d};
    for (int i = 0; i < 3; i++) {
        C[i][0] = t1[i] * R[0] + t2[i] * R[1];
        C[i][1] = t1[i] * R[1] + t2[i] * R[2];
    }
    return 1;
}

/* The six entries of a symmetric G, in the order (00, 11, 22, 01, 02, 12). */
static const int sym_i[6] = {0, 1, 2, 0, 0, 1}, sym_j[6] = {0, 1, 2, 1, 2, 2};

/* Coefficients of X_ab = C_a^T G C_b in the six entries of G. */
static void x_coeffs(const double C[3][2], int a, int b, double c[6])
{
    for (int k = 0; k < 6; k++) {
        int i = sym_i[k], j = sym_j[k];
        c[k] = i == j ? C[i][a] * C[i][b] : C[i][a] * C[j][b] + C[j][a] * C[i][b];
    }
}

/* G = exp(S), S = sum x_k D_k over an orthonormal (Frobenius) basis of the traceless symmetric
 * matrices, in the entries (00, 11, 22, 01, 02, 12): det G = 1 (the residuals are invariant under
 * scaling G, so its scale is free to fix), G stays positive definite, and the ridge on x = the
 * departure of log G from 0 makes a vanishing stretch (a flat mesh's normal) cost without bound. */
static const double basis[5][6] = {{0.70710678118654752, -0.70710678118654752, 0, 0, 0, 0},
                                   {0.40824829046386302, 0.40824829046386302, -0.81649658092772603, 0, 0, 0},
                                   {0, 0, 0, 0.70710678118654752, 0, 0},
                                   {0, 0, 0, 0, 0.70710678118654752, 0},
                                   {0, 0, 0, 0, 0, 0.70710678118654752}};

/* From x: G = exp(S) into G (six entries), A = exp(S / 2) and its inverse into R and Ri, and A's
 * stretch (its largest eigenvalue over its smallest) into *stretch, each where not NULL. */
static void g_of(const double x[5], double G[6], double R[3][3], double Ri[3][3], double *stretch)
{
    double S[3][3] = {{0}}, w[3], E[3][3];
    for (int l = 0; l < 6; l++) {
        double v = 0;
        for (int k = 0; k < 5; k++) v += x[k] * basis[k][l];
        S[sym_i[l]][sym_j[l]] = S[sym_j[l]][sym_i[l]] = v;
    }
    sym3_eigen(S, w, E);
    double lo = INFINITY, hi = -INFINITY;
    for (int l = 0; G && l < 6; l++) {
        G[l] = 0;
        for (int k = 0; k < 3; k++) G[l] += E[sym_i[l]][k] * exp(w[k]) * E[sym_j[l]][k];
    }
    for (int k = 0; R && k < 3; k++) lo = fmin(lo, w[k]), hi = fmax(hi, w[k]);
    for (int i = 0; R && i < 3; i++)
        for (int j = 0; j < 3; j++) {
            R[i][j] = Ri[i][j] = 0;
            for (int k = 0; k < 3; k++) R[i][j] += E[i][k] * exp(0.5 * w[k]) * E[j][k], Ri[i][j] += E[i][k] * exp(-0.5 * w[k]) * E[j][k];
        }
    if (stretch) *stretch = exp(0.5 * (hi - lo));
}

/* Per vertex, the coefficients of X_11, X_22, X_12 in the six entries of G. */
typedef struct vx { double c[3][6]; } vx;

/* The residuals r (2 per vertex) at x and the objective sum |r|^2 + ridge |x|^2. */
static double objective(const vx *V, int nc, const double x[5], double ridge, double *r)
{
    double G[6], f = 0;
    g_of(x, G, NULL, NULL, NULL);
    for (int k = 0; k < 5; k++) f += ridge * x[k] * x[k];
    for (int q = 0; q < nc; q++) {
        double X[3] = {0, 0, 0};
        for (int c = 0; c < 3; c++)
            for (int l = 0; l < 6; l++) X[c] += V[q].c[c][l] * G[l];
        double t = X[0] + X[1];
        if (!(t > 0)) return INFINITY;
        r[2 * q] = (X[0] - X[1]) / t;
        r[2 * q + 1] = 2 * X[2] / t;
        f += r[2 * q] * r[2 * q] + r[2 * q + 1] * r[2 * q + 1];
    }
    return f;
}

double q2n_mesh_isotropic_frame(const q2n_mesh *m, double A[3][3], double Ainv[3][3])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) A[i][j] = Ainv[i][j] = i == j;
    size_t nvv = m->nv > 0 ? (size_t)m->nv : 1;
    vx *V = malloc(nvv * sizeof *V);
    double *r = malloc(2 * nvv * sizeof *r), *rn = malloc(2 * nvv * sizeof *rn), *J = malloc(10 * nvv * sizeof *J);
    int nc = 0, ok = V && r && rn && J;
    for (int v = 0; ok && v < m->nv; v++) {
        double C[3][2];
        if (!vertex_factor(m, v, C)) continue;
        x_coeffs(C, 0, 0, V[nc].c[0]);
        x_coeffs(C, 1, 1, V[nc].c[1]);
        x_coeffs(C, 0, 1, V[nc].c[2]);
        nc++;
    }
    double x[5] = {0, 0, 0, 0, 0}, ridge = Q2N_FRAME_RIDGE * Q2N_FRAME_RIDGE * nc;
    ok = ok && nc > 0;
    /* Gauss–Newton (Jacobian by central differences) with step halving: the objective must drop */
    double f = ok ? objective(V, nc, x, ridge, r) : INFINITY;
    for (int it = 0; ok && isfinite(f) && it < Q2N_FRAME_ITERATIONS; it++) {
        for (int k = 0; k < 5; k++) {
            double xp[5], h = 1e-6;
            memcpy(xp, x, sizeof xp);
            xp[k] = x[k] + h;
            objective(V, nc, xp, ridge, rn);
            xp[k] = x[k] - h;
            objective(V, nc, xp, ridge, J + 2 * (size_t)nc * k);
            for (int q = 0; q < 2 * nc; q++) J[2 * (size_t)nc * k + q] = (rn[q] - J[2 * (size_t)nc * k + q]) / (2 * h);
        }
        double N[25] = {0}, g[5] = {0};
        for (int k = 0; k < 5; k++) {
            g[k] = -ridge * x[k];
            N[6 * k] = ridge;
            for (int q = 0; q < 2 * nc; q++) {
                g[k] -= J[2 * (size_t)nc * k + q] * r[q];
                for (int l = 0; l <= k; l++) N[5 * k + l] += J[2 * (size_t)nc * k + q] * J[2 * (size_t)nc * l + q];
            }
            for (int l = 0; l < k; l++) N[5 * l + k] = N[5 * k + l];
        }
        if (q2n_dense_solve(5, 1, N, 5, g, 5)) break;
        double step = 1, xn[5], fn = INFINITY, dn = 0;
        for (int k = 0; k < 5; k++) dn += g[k] * g[k];
        for (int h = 0; h < 30 && !(fn < f); h++, step *= 0.5) {
            for (int k = 0; k < 5; k++) xn[k] = x[k] + step * g[k];
            fn = objective(V, nc, xn, ridge, rn);
        }
        if (!(fn < f)) break;
        memcpy(x, xn, sizeof x);
        f = objective(V, nc, x, ridge, r);
        if (step * step * dn < 1e-20) break; /* converged */
    }
    free(V);
    free(r);
    free(rn);
    free(J);
    if (!ok || !isfinite(f)) return 1;
    double stretch = 1;
    g_of(x, NULL, A, Ainv, &stretch);
    return stretch;
}

q2n_status q2n_mesh_mapped(const q2n_mesh *m, const double A[3][3], q2n_mesh **out, q2n_error *err)
{
    double *pos = malloc(3 * (m->nv > 0 ? (size_t)m->nv : 1) * sizeof *pos);
    if (!pos) return q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory");
    for (int v = 0; v < m->nv; v++) {
        const double *p = q2n_mesh_vpos(m, v);
        for (int i = 0; i < 3; i++) pos[3 * v + i] = A[i][0] * p[0] + A[i][1] * p[1] + A[i][2] * p[2];
    }
    q2n_status st = q2n_mesh_from_arrays_lines(m->nv, pos, m->nf, m->face_start, m->face_vert, m->face_line,
                                               m->name, out, err);
    free(pos);
    if (!st) memcpy((*out)->derived, m->derived, sizeof m->derived);
    return st;
}
