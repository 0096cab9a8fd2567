/* param.c — edge parameter intervals (see param.h). */
#include "param/param.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/vec3.h"

double q2n_param_alpha(const q2n_param_options *opt)
{
    switch (opt->method) {
    case Q2N_PARAM_CHORDAL: return 1.0;
    case Q2N_PARAM_UNIFORM: return 0.0;
    default: return (opt->alpha > 0) ? opt->alpha : 0.5; /* zero or NaN: the default */
    }
}

double q2n_param_interval(const double a[3], const double b[3], double alpha)
{
    double len = q2n_v3_dist(a, b);
    if (alpha == 0) return 1.0;
    if (alpha == 1) return len;
    if (alpha == 0.5) return sqrt(len);
    return pow(len, alpha);
}

q2n_status q2n_param_edge_intervals(const q2n_mesh *m, const q2n_param_options *opt, double **iv,
                                    q2n_error *err)
{
    double alpha = q2n_param_alpha(opt);
    double *d = malloc((m->ne > 0 ? (size_t)m->ne : 1) * sizeof *d);
    if (!d) return q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (edge intervals)");
    for (int e = 0; e < m->ne; e++) {
        int h = m->edge_he[e];
        d[e] = q2n_param_interval(q2n_mesh_vpos(m, q2n_he_origin(m, h)),
                                  q2n_mesh_vpos(m, q2n_he_dest(m, h)), alpha);
    }
    if (opt->method == Q2N_PARAM_MEAN) { /* §3.1: one interval per edge ribbon, averaged */
        int *rib = NULL, nr = 0;
        q2n_status st = q2n_mesh_ribbons(m, &rib, &nr, err);
        if (st) { free(d); return st; }
        double *sum = calloc((size_t)nr + 1, sizeof *sum);
        int *cnt = calloc((size_t)nr + 1, sizeof *cnt);
        if (!sum || !cnt) {
            free(sum); free(cnt); free(rib); free(d);
            return q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (ribbons)");
        }
        for (int e = 0; e < m->ne; e++) sum[rib[e]] += d[e], cnt[rib[e]]++;
        for (int e = 0; e < m->ne; e++) d[e] = sum[rib[e]] / cnt[rib[e]];
        free(sum); free(cnt); free(rib);
    }
    *iv = d;
    return Q2N_OK;
}

static const char *const method_names[] = {"centripetal", "chordal", "uniform", "mean"};

int q2n_param_method_parse(const char *s, q2n_param_method *out)
{
    for (int i = 0; i < 4; i++)
        if (strcmp(s, method_names[i]) == 0) { *out = (q2n_param_method)i; return 0; }
    return -1;
}

const char *q2n_param_method_name(q2n_param_method m)
{
    return ((unsigned)m < 4) ? method_names[m] : "?";
}
