/* choices.c — the string forms of the public enums (include/quad2nurbs.h): the command line's
 * option values.  Where a stage already parses its own names (units, ACC strategies,
 * parametrizations, extraordinary-vertex options, formats) this delegates to it. */
#include "quad2nurbs.h"

#include <string.h>
#include <strings.h>

#include "acc/acc.h"
#include "api/model.h"
#include "iges/export.h"
#include "param/param.h"
#include "patch/extraordinary.h"
#include "spline/spline.h"

/* Names by value; NULL-terminated.  "default" stands for a zero value that means "the default". */
static const char *const SURFACE[] = {"augmented", "acc3", "acc-g1", NULL};
static const char *const CLASS[] = {"default", "D5C2P4S6", "D5C2P2S4", "D3C1P2S4", "D2C1P2S4", "D3C2P2S4", NULL};
static const char *const PARAM[] = {"centripetal", "chordal", "uniform", "mean", NULL};
static const char *const EV_PATCH[] = {"default", "g1", "g2", NULL};
static const char *const EV_METHOD[] = {"default", "fair", "paper", NULL};
static const char *const STRATEGY[] = {"cs-s", "ncs-s", "cs-as", "ncs-as", NULL};
static const char *const UNITS[] = {"mm", "in", "cm", "m", "ft", NULL};
static const char *const FORMAT[] = {"none", "obj", "step", "iges", "json", NULL};
static const char *const CONTINUITY[] = {"default", "g1", "g2", NULL};
static const char *const SOLVER[] = {"ceres", "direct", NULL};
static const char *const GLUING[] = {"exact", "least-squares", NULL};

static const struct {
    const char *const *names;
    const char *list;
} CHOICES[Q2N_CHOICE_COUNT] = {
    [Q2N_CHOICE_SURFACE] = {SURFACE, "augmented, acc3 or acc-g1"},
    [Q2N_CHOICE_CLASS] = {CLASS, "D5C2P4S6, D5C2P2S4, D3C1P2S4, D2C1P2S4 or D3C2P2S4"},
    [Q2N_CHOICE_PARAM] = {PARAM, "centripetal, chordal, uniform or mean"},
    [Q2N_CHOICE_EV_PATCH] = {EV_PATCH, "g1 or g2"},
    [Q2N_CHOICE_EV_CONSTRUCTION] = {EV_METHOD, "fair or paper"},
    [Q2N_CHOICE_ACC_STRATEGY] = {STRATEGY, "cs-s, ncs-s, cs-as or ncs-as"},
    [Q2N_CHOICE_UNITS] = {UNITS, "mm, cm, m, in or ft"},
    [Q2N_CHOICE_FORMAT] = {FORMAT, "obj, step, iges or json"},
    [Q2N_CHOICE_CONTINUITY] = {CONTINUITY, "g1 or g2"},
    [Q2N_CHOICE_SOLVER] = {SOLVER, "ceres or direct"},
    [Q2N_CHOICE_GLUING] = {GLUING, "exact or least-squares"},
};

static int valid(q2n_choice what) { return (int)what >= 0 && what < Q2N_CHOICE_COUNT; }

const char *q2n_choice_name(q2n_choice what, int value)
{
    if (!valid(what) || value < 0) return NULL;
    for (int i = 0; CHOICES[what].names[i]; i++)
        if (i == value) return CHOICES[what].names[i];
    return NULL;
}

const char *q2n_choice_list(q2n_choice what) { return valid(what) ? CHOICES[what].list : ""; }

/* Exact match among the names (not "default"), else -1. */
static int lookup(const char *const *names, const char *s)
{
    for (int i = 0; names[i]; i++)
        if (strcmp(names[i], "default") && !strcmp(names[i], s)) return i;
    return -1;
}

q2n_status q2n_parse_choice(q2n_choice what, const char *s, int *value)
{
    if (!valid(what) || !s || !value) return Q2N_ERR_ARG;
    int v = -1;
    switch (what) {
    case Q2N_CHOICE_CLASS: { /* any case, as the spline stage's registry finds them */
        const q2n_spline_class *c = q2n_spline_class_find(s);
        for (int i = 1; c && CLASS[i]; i++)
            if (!strcasecmp(CLASS[i], c->name)) v = i;
        break;
    }
    case Q2N_CHOICE_PARAM: {
        q2n_param_method p;
        if (!q2n_param_method_parse(s, &p)) v = (int)p;
        break;
    }
    case Q2N_CHOICE_EV_PATCH: {
        q2n_ev_patch_kind k;
        if (!q2n_ev_patch_parse(s, &k)) v = (int)k;
        break;
    }
    case Q2N_CHOICE_EV_CONSTRUCTION: {
        q2n_ev_method k;
        if (!q2n_ev_method_parse(s, &k)) v = (int)k;
        break;
    }
    case Q2N_CHOICE_ACC_STRATEGY: {
        q2n_acc_strategy k;
        if (!q2n_acc_parse_strategy(s, &k, NULL)) v = (int)k;
        break;
    }
    case Q2N_CHOICE_UNITS: {
        q2n_units u;
        if (!q2n_units_parse(s, &u)) v = (int)u;
        break;
    }
    case Q2N_CHOICE_FORMAT: {
        q2n_format f = q2n_format_parse(s);
        if (f != Q2N_FORMAT_NONE) v = (int)f;
        break;
    }
    default: v = lookup(CHOICES[what].names, s); break;
    }
    if (v < 0) return Q2N_ERR_ARG;
    *value = v;
    return Q2N_OK;
}
