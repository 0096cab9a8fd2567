/* outputs.c — the CLI's text outputs: an OBJ tessellation (n x n points per covered patch, with
 * normals, one group per patch) and the `sample` listing "k u v x y z xu yu zu xv yv zv". */
#include <stdlib.h>

#include "cli/cli.h"
#include "core/outfile.h"
#include "core/vec3.h"

static double *grid_params(int n)
{
    double *t = malloc((size_t)n * sizeof *t);
    if (t)
        for (int i = 0; i < n; i++) t[i] = n == 1 ? 0.5 : (double)i / (n - 1);
    return t;
}

q2n_status cli_write_tessellation(const cli_result *r, int n, const char *path, q2n_error *err)
{
    q2n_outfile of;
    q2n_status st;
    double *t = grid_params(n), *buf = malloc(9 * (size_t)n * n * sizeof *buf);
    if (!t || !buf) {
        free(t); free(buf);
        return q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (tessellation)");
    }
    if ((st = q2n_outfile_open(&of, path, err))) { free(t); free(buf); return st; }
    fprintf(of.f, "# quad2nurbs %s tessellation of %s: %d x %d points per patch\n", Q2N_VERSION_STRING,
            r->mesh->name, n, n);
    long base = 1;
    for (int k = 0; k < r->mesh->nf; k++) {
        if (q2n_surface_kind(r->surface, k) == Q2N_PATCH_UNCOVERED) continue;
        if ((st = q2n_surface_eval_grid(r->surface, k, n, t, n, t, buf))) {
            q2n_error_set(err, st, "patch %d: evaluation failed", k);
            break;
        }
        fprintf(of.f, "g patch_%d\n", k);
        for (int p = 0; p < n * n; p++) {
            const double *e = buf + 9 * p;
            double nrm[3];
            q2n_v3_cross(nrm, e + 3, e + 6);
            double len = q2n_v3_norm(nrm);
            if (len > 0) q2n_v3_scale(nrm, 1 / len, nrm);
            fprintf(of.f, "v %.17g %.17g %.17g\nvn %.9g %.9g %.9g\n", e[0], e[1], e[2], nrm[0], nrm[1], nrm[2]);
        }
        for (int j = 0; j + 1 < n; j++)
            for (int i = 0; i + 1 < n; i++) {
                long a = base + j * n + i, b = a + 1, c = a + n + 1, d = a + n;
                fprintf(of.f, "f %ld//%ld %ld//%ld %ld//%ld %ld//%ld\n", a, a, b, b, c, c, d, d);
            }
        base += (long)n * n;
    }
    free(t);
    free(buf);
    if (st) { q2n_outfile_abort(&of); return st; }
    return q2n_outfile_commit(&of, err);
}

q2n_status cli_write_samples(const cli_result *r, int n, FILE *out, q2n_error *err)
{
    double *t = grid_params(n), *buf = malloc(9 * (size_t)n * n * sizeof *buf);
    q2n_status st = Q2N_OK;
    if (!t || !buf) {
        free(t); free(buf);
        return q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (samples)");
    }
    for (int k = 0; k < r->mesh->nf && !st; k++) {
        if (q2n_surface_kind(r->surface, k) == Q2N_PATCH_UNCOVERED) continue;
        if ((st = q2n_surface_eval_grid(r->surface, k, n, t, n, t, buf))) {
            q2n_error_set(err, st, "patch %d: evaluation failed", k);
            break;
        }
        for (int j = 0; j < n; j++)
            for (int i = 0; i < n; i++) {
                const double *e = buf + 9 * ((size_t)j * n + i);
                fprintf(out, "%d %.17g %.17g", k, t[i], t[j]);
                for (int c = 0; c < 9; c++) fprintf(out, " %.17g", e[c]);
                fputc('\n', out);
            }
    }
    free(t);
    free(buf);
    if (!st && ferror(out)) st = q2n_error_set(err, Q2N_ERR_IO, "error writing samples");
    return st;
}
