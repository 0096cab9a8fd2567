/* acc.c — q2n_acc_build: prepares the mesh (Catmull–Clark steps when the masks' assumptions do
 * not hold), computes the ACC3 / G1 Bézier control points (acc_masks.c, acc_g1.c) and fills a
 * q2n_surface; plus option parsing and the one-line description the CLI prints. */
#include "acc/acc.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "acc/acc_masks.h"

static void count_evs(const q2n_mesh *m, const q2n_acc_rings *r, q2n_acc_info *info)
{
    info->n_ev_interior = info->n_ev_boundary = 0;
    info->max_valence = 0;
    for (int v = 0; v < m->nv; v++) {
        if (!r->ev[v]) continue;
        if (r->bnd[v]) info->n_ev_boundary++;
        else info->n_ev_interior++;
        if (m->valence[v] > info->max_valence) info->max_valence = m->valence[v];
    }
}

/* Why the mesh m cannot be used as it is (NULL when it can). */
static const char *needs_step(const q2n_mesh *m, int step, q2n_acc_method method, char *why, size_t n)
{
    char where[48] = "";
    if (step) snprintf(where, sizeof where, " of the %d-step mesh", step);
    for (int f = 0; f < m->nf; f++)
        if (q2n_face_size(m, f) != 4) {
            snprintf(why, n, "face %d%s has %d vertices", f, where, q2n_face_size(m, f));
            return why;
        }
    if (method != Q2N_ACC_G1) return NULL;
    q2n_acc_rings r;
    if (q2n_acc_rings_build(m, &r, NULL) != Q2N_OK) return NULL; /* reported by the caller */
    int bad = -1, ok = q2n_acc_evs_isolated(m, &r, &bad);
    q2n_acc_rings_free(&r);
    if (ok) return NULL;
    snprintf(why, n, "face %d%s has two or more EVs", bad, where);
    return why;
}

void q2n_acc_info_free(q2n_acc_info *info)
{
    if (!info) return;
    q2n_mesh_free(info->mesh);
    info->mesh = NULL;
}

const q2n_mesh *q2n_acc_info_mesh(const q2n_acc_info *info, const q2n_mesh *input)
{
    return (info && info->mesh) ? info->mesh : input;
}

static q2n_status fill_surface(const q2n_mesh *m, const q2n_acc_options *o, q2n_surface **out,
                               q2n_acc_info *info, q2n_error *err)
{
    q2n_acc_rings r;
    q2n_status s = q2n_acc_rings_build(m, &r, err);
    if (s != Q2N_OK) return s;
    count_evs(m, &r, info);
    int *deg = malloc((size_t)m->nf * sizeof *deg);
    double *cp = malloc((size_t)m->nf * 36 * 3 * sizeof *cp);
    q2n_surface *surf = q2n_surface_create(m->nf);
    if (!deg || !cp || !surf) s = q2n_error_set(err, Q2N_ERR_NOMEM, "%s: out of memory", m->name);
    if (s == Q2N_OK) s = q2n_acc_control_points(m, &r, o->method, o->strategy, m->pos, 3, deg, cp, err);
    for (int f = 0; f < m->nf && s == Q2N_OK; f++) {
        s = q2n_surface_set_bezier(surf, f, deg[f], deg[f], cp + (size_t)f * 108);
        if (deg[f] == 3) info->n_bicubic++;
        else info->n_biquintic++;
    }
    q2n_acc_rings_free(&r);
    free(deg);
    free(cp);
    if (s != Q2N_OK) {
        q2n_surface_free(surf);
        return s;
    }
    info->n_patches = m->nf;
    *out = surf;
    return Q2N_OK;
}

q2n_status q2n_acc_build(const q2n_mesh *m, const q2n_acc_options *opt, q2n_surface **out,
                         q2n_acc_info *info_out, q2n_error *err)
{
    static const q2n_acc_options defaults = { Q2N_ACC_3, Q2N_ACC_CS_S, 0 };
    const q2n_acc_options *o = opt ? opt : &defaults;
    if (info_out) memset(info_out, 0, sizeof *info_out);
    if (!m || !out) return q2n_error_set(err, Q2N_ERR_ARG, "acc: no mesh or output pointer");
    if ((int)o->method < 0 || o->method > Q2N_ACC_G1 || (int)o->strategy < 0 || o->strategy > Q2N_ACC_NCS_AS)
        return q2n_error_set(err, Q2N_ERR_ARG, "acc: invalid method %d or strategy %d", (int)o->method,
                             (int)o->strategy);
    *out = NULL;
    q2n_acc_info info;
    memset(&info, 0, sizeof info);
    int max_steps = o->max_subdiv == 0 ? 2 : (o->max_subdiv < 0 ? 0 : o->max_subdiv);
    const q2n_mesh *cur = m;
    q2n_mesh *owned = NULL;
    char why[160];
    const char *reason;
    while ((reason = needs_step(cur, info.subdiv_steps, o->method, why, sizeof why)) != NULL) {
        size_t used = strlen(info.reason); /* one reason per step, "; then ..." */
        snprintf(info.reason + used, sizeof info.reason - used, "%s%s", used ? "; then " : "", reason);
        if (info.subdiv_steps >= max_steps) {
            q2n_mesh_free(owned);
            return q2n_error_set(err, Q2N_ERR_UNSUPPORTED, "%s: %s%s", m->name, reason,
                                 info.subdiv_steps ? " after automatic subdivision" : "");
        }
        q2n_mesh *next = NULL;
        q2n_status s = q2n_mesh_subdivide(cur, 1, &next, err);
        q2n_mesh_free(owned);
        if (s != Q2N_OK) return s;
        owned = next;
        cur = next;
        info.subdiv_steps++;
    }
    q2n_status s = fill_surface(cur, o, out, &info, err);
    if (s != Q2N_OK) {
        q2n_mesh_free(owned);
        return s;
    }
    info.mesh = owned;
    if (info_out) *info_out = info;
    else q2n_mesh_free(owned);
    return Q2N_OK;
}

static const char *const METHOD_NAMES[] = { "acc3", "acc-g1" };
static const char *const STRATEGY_NAMES[] = { "cs-s", "ncs-s", "cs-as", "ncs-as" };

q2n_status q2n_acc_parse_method(const char *s, q2n_acc_method *out, q2n_error *err)
{
    for (int i = 0; i < 2; i++)
        if (s && strcmp(s, METHOD_NAMES[i]) == 0) {
            *out = (q2n_acc_method)i;
            return Q2N_OK;
        }
    return q2n_error_set(err, Q2N_ERR_ARG, "unknown ACC surface '%s' (acc3 | acc-g1)", s ? s : "");
}

q2n_status q2n_acc_parse_strategy(const char *s, q2n_acc_strategy *out, q2n_error *err)
{
    for (int i = 0; i < 4; i++)
        if (s && strcmp(s, STRATEGY_NAMES[i]) == 0) {
            *out = (q2n_acc_strategy)i;
            return Q2N_OK;
        }
    return q2n_error_set(err, Q2N_ERR_ARG, "unknown ACC strategy '%s' (cs-s | ncs-s | cs-as | ncs-as)",
                         s ? s : "");
}

const char *q2n_acc_method_name(q2n_acc_method m)
{
    return ((int)m >= 0 && m <= Q2N_ACC_G1) ? METHOD_NAMES[m] : "?";
}

const char *q2n_acc_strategy_name(q2n_acc_strategy s)
{
    return ((int)s >= 0 && s <= Q2N_ACC_NCS_AS) ? STRATEGY_NAMES[s] : "?";
}

const char *q2n_acc_describe(const q2n_acc_info *info, const q2n_acc_options *opt, char *buf, int size)
{
    q2n_acc_method me = opt ? opt->method : Q2N_ACC_3;
    char steps[400] = "";
    if (info->subdiv_steps)
        snprintf(steps, sizeof steps, "%d Catmull-Clark step%s (%s), patches on the subdivided mesh: ",
                 info->subdiv_steps, info->subdiv_steps > 1 ? "s" : "", info->reason);
    snprintf(buf, (size_t)size, "%s%s%s: %s%d bicubic + %d biquintic, EVs %d interior + %d boundary "
                                "(max valence %d)",
             q2n_acc_method_name(me), me == Q2N_ACC_G1 ? " " : "",
             me == Q2N_ACC_G1 ? q2n_acc_strategy_name(opt->strategy) : "", steps, info->n_bicubic,
             info->n_biquintic, info->n_ev_interior, info->n_ev_boundary, info->max_valence);
    return buf;
}

q2n_status q2n_acc_limit_points(const q2n_mesh *m, double *out, double *nrm, q2n_error *err)
{
    q2n_acc_rings r;
    q2n_status s = q2n_acc_rings_build(m, &r, err);
    if (s != Q2N_OK) return s;
    for (int v = 0; v < m->nv; v++) {
        double n[3];
        q2n_acc_limit_frame(m, &r, v, out + 3 * (size_t)v, n);
        if (nrm) memcpy(nrm + 3 * (size_t)v, n, sizeof n);
    }
    q2n_acc_rings_free(&r);
    return Q2N_OK;
}
