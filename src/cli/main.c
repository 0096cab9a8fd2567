/* main.c — `quad2nurbs` command line (getopt_long conventions; see usage()). */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "api/model.h"
#include "patch/extraordinary.h"

#define Q2N_VERSION_STRING "0.1.0"
#define MAX_OUTPUTS 8

/* Command-line settings (the library options plus what only the CLI has). */
typedef struct cli_options {
    const char *input;
    const char *outputs[MAX_OUTPUTS];
    int noutputs, sample, grid, tess, quiet;
    q2n_model_options model;
    q2n_fit_options fit;
    q2n_export_options xopt;
} cli_options;

static void usage(FILE *f)
{
    fputs("usage: quad2nurbs [options] MESH.obj -o OUT [-o OUT ...]\n"
          "       quad2nurbs sample [options] MESH.obj [--grid N]\n"
          "\n"
          "Builds a smooth surface on a quad mesh (patch k on face k, domain [0,1]^2, u along the\n"
          "face's first edge v0->v1, v along v0->v3) and writes it; the output format follows the\n"
          "extension: .obj tessellation (--tess N points per patch side); .step/.stp STEP AP214 and\n"
          "           .igs/.iges IGES 5.3 of the fitted B-spline patches; .json the fit report.\n"
          "`sample` prints one line per patch k and grid point: k u v x y z xu yu zu xv yv zv.\n"
          "\n"
          "options:\n"
          "  -o, --output FILE     output file (repeatable)\n"
          "      --surface M       augmented (default: interpolates every vertex), acc3 or acc-g1\n"
          "                        (Catmull-Clark approximations, exact polynomial patches)\n"
          "      --acc-strategy S  acc-g1 masks: cs-s (default), ncs-s, cs-as, ncs-as\n"
          "      --class C         spline class of the augmented surface: D5C2P2S4 (default, C2),\n"
          "                        D3C1P2S4 (Catmull-Rom, C1), D2C1P2S4, D3C2P2S4, D5C2P4S6\n"
          "      --ev-patch G      patches at extraordinary vertices: g2 (default for C2 classes,\n"
          "                        biquintic Coons-Gregory) or g1 (bicubic; default for C1 classes)\n"
          "      --param P         edge parameter intervals: centripetal (default), chordal,\n"
          "                        uniform, mean (ribbon-averaged baseline of the paper)\n"
          "      --alpha A         exponent of |edge|^A for centripetal/mean (default 0.5)\n"
          "      --subdivide N     apply N Catmull-Clark steps first (needed for non-quad faces)\n"
          "      --tess N          tessellation points per patch side (default 9)\n"
          "      --tol T           fit tolerance relative to the bounding-box diagonal (default 1e-5)\n"
          "      --threads N       fit threads (default 1; results do not depend on it)\n"
          "      --solver S        fit solver: ceres (default) or direct (own QR, same result, faster)\n"
          "      --continuity C    continuity the fit imposes: g1 or g2 (default: the construction's)\n"
          "      --units U         CAD file units: mm (default) or in\n"
          "      --grid N          sample points per patch side (default 5)\n"
          "  -q, --quiet           no progress/summary on stderr\n"
          "  -h, --help            this text\n"
          "  -V, --version         version\n"
          "\n"
          "exit status: 0 success, 2 bad input or usage, 1 other failure.\n",
          f);
}

static int parse_int(const char *s, const char *opt, int lo, int hi, int *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || *end || end == s || v < lo || v > hi) {
        fprintf(stderr, "quad2nurbs: %s: expected an integer in [%d, %d], got '%s'\n", opt, lo, hi, s);
        return -1;
    }
    *out = (int)v;
    return 0;
}

static const char *extension(const char *path)
{
    const char *dot = strrchr(path, '.'), *slash = strrchr(path, '/');
    return (dot && (!slash || dot > slash)) ? dot : "";
}

static int parse_args(int argc, char **argv, cli_options *o)
{
    enum { OPT_TESS = 256, OPT_GRID, OPT_CLASS, OPT_PARAM, OPT_ALPHA, OPT_SUBDIV, OPT_SURFACE, OPT_STRAT,
           OPT_TOL, OPT_THREADS, OPT_UNITS, OPT_EVPATCH, OPT_SOLVER, OPT_CONT };
    static const struct option longopts[] = {
        {"output", required_argument, 0, 'o'},   {"tess", required_argument, 0, OPT_TESS},
        {"grid", required_argument, 0, OPT_GRID}, {"class", required_argument, 0, OPT_CLASS},
        {"param", required_argument, 0, OPT_PARAM}, {"alpha", required_argument, 0, OPT_ALPHA},
        {"subdivide", required_argument, 0, OPT_SUBDIV}, {"surface", required_argument, 0, OPT_SURFACE},
        {"acc-strategy", required_argument, 0, OPT_STRAT}, {"quiet", no_argument, 0, 'q'},
        {"tol", required_argument, 0, OPT_TOL},  {"threads", required_argument, 0, OPT_THREADS},
        {"units", required_argument, 0, OPT_UNITS}, {"ev-patch", required_argument, 0, OPT_EVPATCH},
        {"solver", required_argument, 0, OPT_SOLVER}, {"continuity", required_argument, 0, OPT_CONT},
        {"help", no_argument, 0, 'h'},           {"version", no_argument, 0, 'V'},
        {0, 0, 0, 0}};
    int c;
    if (argc > 1 && strcmp(argv[1], "sample") == 0) {
        o->sample = 1;
        argv[1] = argv[0];
        argv++, argc--;
    }
    while ((c = getopt_long(argc, argv, "o:qhV", longopts, NULL)) != -1) {
        switch (c) {
        case 'o':
            if (o->noutputs == MAX_OUTPUTS) {
                fprintf(stderr, "quad2nurbs: at most %d outputs\n", MAX_OUTPUTS);
                return 2;
            }
            o->outputs[o->noutputs++] = optarg;
            break;
        case OPT_TESS: if (parse_int(optarg, "--tess", 2, 10000, &o->tess)) return 2; break;
        case OPT_GRID: if (parse_int(optarg, "--grid", 1, 10000, &o->grid)) return 2; break;
        case OPT_SUBDIV: if (parse_int(optarg, "--subdivide", 0, 6, &o->model.subdivide)) return 2; break;
        case OPT_THREADS: if (parse_int(optarg, "--threads", 1, 256, &o->fit.threads)) return 2; break;
        case OPT_CLASS:
            if (!(o->model.cls = q2n_spline_class_find(optarg))) {
                fprintf(stderr, "quad2nurbs: --class: unknown class '%s' (known:", optarg);
                for (const q2n_spline_class *const *k = q2n_spline_classes(); *k; k++)
                    fprintf(stderr, " %s", (*k)->name);
                fputs(")\n", stderr);
                return 2;
            }
            break;
        case OPT_PARAM:
            if (q2n_param_method_parse(optarg, &o->model.param.method)) {
                fprintf(stderr, "quad2nurbs: --param: expected centripetal, chordal, uniform or mean, got '%s'\n",
                        optarg);
                return 2;
            }
            break;
        case OPT_ALPHA: {
            char *end;
            double a = strtod(optarg, &end);
            if (*end || end == optarg || !(a > 0 && a <= 2)) {
                fprintf(stderr, "quad2nurbs: --alpha: expected a number in (0, 2] (use --param uniform for "
                                "alpha 0), got '%s'\n", optarg);
                return 2;
            }
            o->model.param.alpha = a;
            break;
        }
        case OPT_TOL: {
            char *end;
            double t = strtod(optarg, &end);
            if (*end || end == optarg || !(t >= 1e-12 && t <= 0.1)) {
                fprintf(stderr, "quad2nurbs: --tol: expected a number in [1e-12, 0.1], got '%s'\n", optarg);
                return 2;
            }
            o->fit.tol = t;
            break;
        }
        case OPT_EVPATCH: {
            q2n_ev_patch_kind k;
            if (q2n_ev_patch_parse(optarg, &k)) {
                fprintf(stderr, "quad2nurbs: --ev-patch: expected g1 or g2, got '%s'\n", optarg);
                return 2;
            }
            o->model.ev_patch = (int)k;
            break;
        }
        case OPT_SOLVER:
            if (strcmp(optarg, "ceres") == 0) o->fit.solver = Q2N_FIT_SOLVER_CERES;
            else if (strcmp(optarg, "direct") == 0) o->fit.solver = Q2N_FIT_SOLVER_DIRECT;
            else {
                fprintf(stderr, "quad2nurbs: --solver: expected ceres or direct, got '%s'\n", optarg);
                return 2;
            }
            break;
        case OPT_CONT:
            if (strcmp(optarg, "g1") == 0) o->fit.continuity = 1;
            else if (strcmp(optarg, "g2") == 0) o->fit.continuity = 2;
            else {
                fprintf(stderr, "quad2nurbs: --continuity: expected g1 or g2, got '%s'\n", optarg);
                return 2;
            }
            break;
        case OPT_UNITS:
            if (strcmp(optarg, "mm") == 0) o->xopt.units = Q2N_UNITS_MM;
            else if (strcmp(optarg, "in") == 0) o->xopt.units = Q2N_UNITS_IN;
            else {
                fprintf(stderr, "quad2nurbs: --units: expected mm or in, got '%s'\n", optarg);
                return 2;
            }
            break;
        case OPT_SURFACE:
            if (strcmp(optarg, "augmented") == 0) o->model.method = Q2N_SURFACE_AUGMENTED;
            else if (strcmp(optarg, "acc3") == 0) o->model.method = Q2N_SURFACE_ACC3;
            else if (strcmp(optarg, "acc-g1") == 0) o->model.method = Q2N_SURFACE_ACC_G1;
            else {
                fprintf(stderr, "quad2nurbs: --surface: expected augmented, acc3 or acc-g1, got '%s'\n", optarg);
                return 2;
            }
            break;
        case OPT_STRAT: {
            q2n_error e;
            if (q2n_acc_parse_strategy(optarg, &o->model.acc_strategy, &e)) {
                fprintf(stderr, "quad2nurbs: --acc-strategy: %s\n", e.message);
                return 2;
            }
            break;
        }
        case 'q': o->quiet = 1; break;
        case 'h': usage(stdout); return -1;
        case 'V': printf("quad2nurbs %s\n", Q2N_VERSION_STRING); return -1;
        default: usage(stderr); return 2;
        }
    }
    if (optind != argc - 1) {
        fprintf(stderr, "quad2nurbs: expected exactly one input mesh (try --help)\n");
        return 2;
    }
    o->input = argv[optind];
    if (!o->sample && o->noutputs == 0) {
        fprintf(stderr, "quad2nurbs: no output given (-o FILE.obj|.step|.igs|.json), or use `quad2nurbs sample`\n");
        return 2;
    }
    for (int i = 0; i < o->noutputs; i++) {
        int needs_fit;
        if (!q2n_model_output_kind(o->outputs[i], &needs_fit)) {
            fprintf(stderr,
                    "quad2nurbs: %s: unsupported output format '%s' (supported: .obj .step .stp .igs .iges .json)\n",
                    o->outputs[i], extension(o->outputs[i]));
            return 2;
        }
    }
    return 0;
}

static int exit_code(q2n_status st)
{
    switch (st) {
    case Q2N_OK: return 0;
    case Q2N_ERR_NOMEM: return 1;
    case Q2N_ERR_NUMERIC: return 1; /* valid input, non-finite evaluation: not the user's fault */
    default: return 2;
    }
}

int main(int argc, char **argv)
{
    cli_options o;
    memset(&o, 0, sizeof o);
    o.grid = 5;
    o.tess = 9;
    o.model.param.method = Q2N_PARAM_CENTRIPETAL;
    o.model.param.alpha = NAN;
    q2n_fit_options_default(&o.fit);
    o.fit.continuity = 0; /* follow the construction */
    int rc = parse_args(argc, argv, &o);
    if (rc) return rc < 0 ? 0 : rc;

    q2n_model *m = NULL;
    q2n_error err = {Q2N_OK, ""};
    q2n_status st = q2n_model_build(o.input, &o.model, &m, &err);
    if (st) {
        fprintf(stderr, "quad2nurbs: %s\n", err.message);
        return exit_code(st);
    }
    if (m->note[0] && !o.quiet) fprintf(stderr, "quad2nurbs: %s\n", m->note);
    if (m->warning[0] && !o.quiet) fprintf(stderr, "quad2nurbs: warning: %s\n", m->warning);
    if (m->uncovered && !o.quiet)
        fprintf(stderr,
                "quad2nurbs: warning: %d of %d faces are in extraordinary regions that the regular "
                "construction does not cover; they are left out of the output\n",
                m->uncovered, m->mesh->nf);
    int fit = 0;
    for (int i = 0; i < o.noutputs; i++) {
        int needs_fit;
        q2n_model_output_kind(o.outputs[i], &needs_fit);
        fit |= needs_fit;
    }
    if (fit && (st = q2n_model_fit(m, &o.fit, &err))) {
        fprintf(stderr, "quad2nurbs: %s: fit: %s\n", o.input, err.message);
        q2n_model_free(m);
        return st == Q2N_ERR_GEOMETRY ? 1 : exit_code(st);
    }
    if (fit && (!m->fit.g1_met || !m->fit.g2_met) && !o.quiet)
        fprintf(stderr, "quad2nurbs: warning: continuity target not met: %s (max G1 %.3g deg, G2 %.3g)\n",
                m->fit.note[0] ? m->fit.note : "see the report", m->fit.g1_max_deg, m->fit.g2_max_rel);
    if (o.sample) st = q2n_model_write_samples(m, o.grid, stdout, &err);
    for (int i = 0; !st && i < o.noutputs; i++) st = q2n_model_write(m, o.outputs[i], o.tess, &o.xopt, &err);
    if (st) {
        fprintf(stderr, "quad2nurbs: %s\n", err.message);
        q2n_model_free(m);
        return exit_code(st);
    }
    if (!o.quiet && !o.sample) {
        fprintf(stderr, "quad2nurbs: %s: %d faces, %d patches, read %.3f s, build %.3f s", o.input, m->mesh->nf,
                m->mesh->nf - m->uncovered, m->t_read, m->t_build);
        if (fit)
            fprintf(stderr, ", fit %.3f s (max dev %.2e, G1 %.2e deg, G2 %.2e, spans %d..%d)", m->t_fit,
                    m->fit.max_dev_rel, m->fit.g1_max_deg, m->fit.g2_max_rel, m->fit.spans_min, m->fit.spans_max);
        fprintf(stderr, ", write %.3f s\n", m->t_write);
    }
    q2n_model_free(m);
    return 0;
}
