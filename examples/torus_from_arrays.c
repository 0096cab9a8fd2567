/* torus_from_arrays.c — quad2nurbs as a library: a mesh from arrays in memory, the fit, what it
 * gave (patch 0's degrees, knots and first control points, the report), a STEP file.
 *
 *   cc torus_from_arrays.c $(pkg-config --cflags --libs --static quad2nurbs) -o torus_from_arrays
 *   ./torus_from_arrays torus.step
 *
 * Uses only the public header.  Exit status: 0 success, 1 failure (the message on stderr). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include <quad2nurbs.h>

enum { N = 12, M = 6 };   /* quads around the torus and around its tube */

int main(int argc, char **argv)
{
    const char *out = argc > 1 ? argv[1] : "torus.step";
    /* the mesh: an N x M torus of radii 3 and 1, vertex (i, j) at index j * N + i, every face a
     * quad with counter-clockwise corners seen from outside */
    static double pos[3 * N * M];
    static int faces[4 * N * M];
    const double pi = 3.14159265358979323846;
    for (int j = 0; j < M; j++)
        for (int i = 0; i < N; i++) {
            double a = 2 * pi * i / N, b = 2 * pi * j / M, r = 3 + cos(b);
            double *p = pos + 3 * (j * N + i);
            p[0] = r * cos(a), p[1] = r * sin(a), p[2] = sin(b);
            int *f = faces + 4 * (j * N + i), i1 = (i + 1) % N, j1 = (j + 1) % M;
            f[0] = j * N + i, f[1] = j * N + i1, f[2] = j1 * N + i1, f[3] = j1 * N + i;
        }

    char err[512];
    q2n_options opt = {0};        /* zeroed: the defaults */
    opt.tol = 1e-5;               /* fit tolerance, relative to the bounding-box diagonal */
    opt.units = Q2N_UNITS_MM;
    q2n_model *m = NULL;
    q2n_status st = q2n_open_mesh(N * M, pos, N * M, NULL, faces, &opt, &m, err, sizeof err);
    if (st == Q2N_OK) st = q2n_fit(m, err, sizeof err);
    if (st != Q2N_OK) {
        fprintf(stderr, "torus_from_arrays: %s (%s)\n", err, q2n_status_string(st));
        q2n_close(m);
        return 1;
    }

    q2n_patch_spline sp;
    q2n_patch_spline_get(m, 0, &sp);
    printf("quad2nurbs %s: %d patches\n", q2n_version(), q2n_patch_count(m));
    printf("patch 0: degrees %d x %d, %d x %d control points%s\n", sp.deg_u, sp.deg_v, sp.ncp_u, sp.ncp_v,
           sp.weights ? " (rational)" : "");
    printf("knots u:");
    for (int i = 0; i < sp.ncp_u + sp.deg_u + 1; i++) printf(" %g", sp.knots_u[i]);
    printf("\nknots v:");
    for (int i = 0; i < sp.ncp_v + sp.deg_v + 1; i++) printf(" %g", sp.knots_v[i]);
    printf("\n");
    for (int i = 0; i < 3; i++)
        printf("control point (%d, 0): %.9f %.9f %.9f\n", i, sp.cp[3 * i], sp.cp[3 * i + 1], sp.cp[3 * i + 2]);

    if ((st = q2n_write(m, out, err, sizeof err)) != Q2N_OK) {
        fprintf(stderr, "torus_from_arrays: %s (%s)\n", err, q2n_status_string(st));
        q2n_close(m);
        return 1;
    }
    q2n_report r;
    q2n_get_report(m, &r);
    printf("max deviation %.3g %s (%.3g x diagonal, target %.3g): %s\n", r.max_dev,
           q2n_choice_name(Q2N_CHOICE_UNITS, (int)r.units), r.max_dev_rel, r.tol, r.dev_met ? "met" : "NOT met");
    printf("G1: max %.3g deg (target %.3g): %s; G2: max %.3g (target %.3g): %s\n", r.g1_max_deg, r.g1_tol_deg,
           r.g1_met ? "met" : "not met", r.g2_max_rel, r.g2_tol_rel, r.g2_met ? "met" : "not met");
    printf("control points per patch %d/%d/%d min/median/max, %ld in all; %s: %ld bytes\n", r.cp_min, r.cp_median,
           r.cp_max, r.cp_total, out, r.step_bytes);
    for (int i = 0; q2n_warning(m, i); i++) printf("warning: %s\n", q2n_warning(m, i));
    q2n_close(m);
    return 0;
}
