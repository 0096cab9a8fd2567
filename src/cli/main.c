/* main.c — `quad2nurbs` command line (getopt_long, GNU conventions; see usage()).
 *
 * A run: options -> outputs opened (every temporary created: unwritable places fail in
 * milliseconds) -> mesh read -> estimate checked against the limits -> surface built -> fit (when
 * an output needs it) -> outputs written -> all committed at once.  Exit status: 0 success, 2 bad
 * input or usage, 1 any other failure (writing included); a signal removes the temporaries. */
#include <errno.h>
#include <getopt.h>
#include <langinfo.h>
#include <locale.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "api/model.h"
#include "api/policy.h"
#include "cli.h"
#include "patch/extraordinary.h"

#define MAX_OUTPUTS 8
#define PROG "quad2nurbs"

/* Command-line settings (the library options plus what only the CLI has). */
typedef struct cli_options {
    const char *input;
    const char *outputs[MAX_OUTPUTS];
    int noutputs, sample, grid, tess, quiet, progress;
    unsigned set;                 /* Q2N_GIVEN_* of the options given */
    q2n_format format;            /* --format */
    double max_memory;            /* --max-memory (0: default) */
    q2n_model_options model;
    q2n_fit_options fit;
    q2n_export_options xopt;
} cli_options;

static void usage(FILE *f)
{
    fputs("usage: quad2nurbs [options] MESH -o OUT [-o OUT ...]\n"
          "       quad2nurbs sample [options] MESH [--grid N]\n"
          "\n"
          "Builds a smooth surface on a quad mesh (patch k on face k, domain [0,1]^2, u along the\n"
          "face's first edge v0->v1, v along v0->v3) and writes it; the output format follows the\n"
          "extension: .obj tessellation (--tess N points per patch side); .step/.stp STEP AP214 and\n"
          "           .igs/.iges IGES 5.3 of the fitted B-spline patches; .json the fit report.\n"
          "MESH: Wavefront .obj, .off (ASCII) or .ply (ASCII or binary).\n"
          "`sample` prints one line per patch k and grid point: k u v x y z xu yu zu xv yv zv.\n"
          "\n"
          "options:\n"
          "  -o, --output FILE     output file (repeatable; all are written or none); '-' is\n"
          "                        standard output (needs --format)\n"
          "      --format F        format of outputs without a known extension: obj, step, iges, json\n"
          "      --surface M       augmented (default: interpolates every vertex), acc3 or acc-g1\n"
          "                        (Catmull-Clark approximations, exact polynomial patches)\n"
          "      --acc-strategy S  acc-g1 masks: cs-s (default), ncs-s, cs-as, ncs-as\n"
          "      --class C         spline class of the augmented surface: D5C2P4S6 (default: C2,\n"
          "                        reproduces quartics), D5C2P2S4 (C2, support 4), D3C1P2S4\n"
          "                        (Catmull-Rom, C1), D2C1P2S4, D3C2P2S4\n"
          "      --ev-patch G      patches at extraordinary vertices: g2 (default for C2 classes,\n"
          "                        biquintic Coons-Gregory) or g1 (bicubic; default for C1 classes)\n"
          "      --ev-construction M  extraordinary regions: fair (default: one jet per vertex,\n"
          "                        bending-energy solve) or paper (Coons-Gregory of the paper)\n"
          "      --param P         edge parameter intervals: centripetal (default), chordal,\n"
          "                        uniform, mean (ribbon-averaged baseline of the paper)\n"
          "      --alpha A         exponent of |edge|^A for centripetal/mean (default 0.5)\n"
          "      --subdivide N     apply N Catmull-Clark steps first (needed for non-quad faces)\n"
          "      --scale S         multiply the mesh coordinates by S (default 1)\n"
          "      --units U         unit of the coordinates (after --scale) in the CAD files:\n"
          "                        mm (default), cm, m, in, ft\n"
          "      --tess N          tessellation points per patch side (default 9)\n"
          "      --tol T           fit tolerance relative to the bounding-box diagonal (default 1e-5)\n"
          "      --tol-abs D       fit tolerance in model units (after --scale), e.g. 0.001\n"
          "      --angle-tol DEG   G1 target: normal-angle jump across edges (default 0.01)\n"
          "      --curvature-tol R G2 target: curvature jump relative to the curvature (default 0.01)\n"
          "      --continuity C    continuity the fit imposes: g1 or g2 (default: the construction's)\n"
          "      --max-spans N     at most N knot spans per patch direction (default 64)\n"
          "      --gluing G        G1/G2 across edges: exact (default: equality constraints wherever the\n"
          "                        construction's gluing allows, least squares elsewhere) or least-squares\n"
          "                        (everywhere: fewer spans on strongly non-uniform meshes)\n"
          "      --threads N       threads of the construction and the fit (default 1; results do not\n"
          "                        depend on it; at most 64)\n"
          "      --solver S        fit solver: ceres (default) or direct (LAPACK QR, same result)\n"
          "      --grid N          sample points per patch side (default 5)\n"
          "      --max-memory SIZE refuse runs estimated to need more (bytes, or with K, M, G, T;\n"
          "                        default: half the physical memory; 0: no limit)\n"
          "      --progress        show progress even when stderr is not a terminal\n"
          "  -q, --quiet           no progress, warnings or summary on stderr (errors only)\n"
          "  -h, --help            this text\n"
          "  -V, --version         version\n"
          "\n"
          "Files get today's date, or SOURCE_DATE_EPOCH's when it is set (reproducible output).\n"
          "exit status: 0 success, 2 bad input or usage, 1 other failure (writing included);\n"
          "SIGINT/SIGTERM remove the temporaries and end the program by that signal.\n",
          f);
}

/* Print "quad2nurbs: MESSAGE" with control bytes escaped (messages quote input). */
static void say(const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 1, 2)))
#endif
    ;
static void say(const char *fmt, ...)
{
    char raw[1024], safe[4096];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(raw, sizeof raw, fmt, ap);
    va_end(ap);
    q2n_escape(safe, sizeof safe, raw);
    fprintf(stderr, PROG ": %s\n", safe);
}

static int usage_error(void)
{
    fputs("Try '" PROG " --help' for more information.\n", stderr);
    return 2;
}

static int parse_int(const char *s, const char *opt, int lo, int hi, int *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || *end || end == s || v < lo || v > hi) {
        say("%s: expected an integer in [%d, %d], got '%s'", opt, lo, hi, s);
        return -1;
    }
    *out = (int)v;
    return 0;
}

/* A number in [lo, hi] (lo_open: excluded). */
static int parse_real(const char *s, const char *opt, double lo, int lo_open, double hi, const char *hint, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (errno || *end || end == s || !isfinite(v) || v < lo || (lo_open && v == lo) || v > hi) {
        say("%s: expected a number in %s%g, %g]%s, got '%s'", opt, lo_open ? "(" : "[", lo, hi, hint, s);
        return -1;
    }
    *out = v;
    return 0;
}

/* SIZE: bytes, or a number with K, M, G, T (powers of 1024; an optional trailing B or iB). */
static int parse_size(const char *s, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    double mul = 1;
    if (end != s && *end) {
        const char *u = "KMGT", *k = strchr(u, *end >= 'a' ? *end - 32 : *end);
        if (k && *end) {
            for (const char *q = u; q <= k; q++) mul *= 1024;
            end++;
            if (*end == 'i' && end[1] == 'B') end += 2;
            else if (*end == 'B' || *end == 'b') end++;
        }
    }
    if (errno || end == s || *end || !isfinite(v) || v < 0) {
        say("--max-memory: expected a size such as 8G, 500M or 0 (no limit), got '%s'", s);
        return -1;
    }
    *out = v == 0 ? -1.0 : v * mul;
    return 0;
}

enum {
    OPT_TESS = 256, OPT_GRID, OPT_CLASS, OPT_PARAM, OPT_ALPHA, OPT_SUBDIV, OPT_SURFACE, OPT_STRAT, OPT_TOL,
    OPT_THREADS, OPT_UNITS, OPT_EVPATCH, OPT_SOLVER, OPT_CONT, OPT_FORMAT, OPT_SCALE, OPT_TOLABS, OPT_ANGLE,
    OPT_CURV, OPT_MAXMEM, OPT_PROGRESS, OPT_EVMETHOD, OPT_MAXSPANS, OPT_GLUING
};

static const struct option LONGOPTS[] = {
    {"output", required_argument, 0, 'o'},         {"tess", required_argument, 0, OPT_TESS},
    {"grid", required_argument, 0, OPT_GRID},       {"class", required_argument, 0, OPT_CLASS},
    {"param", required_argument, 0, OPT_PARAM},     {"alpha", required_argument, 0, OPT_ALPHA},
    {"subdivide", required_argument, 0, OPT_SUBDIV}, {"surface", required_argument, 0, OPT_SURFACE},
    {"acc-strategy", required_argument, 0, OPT_STRAT}, {"quiet", no_argument, 0, 'q'},
    {"tol", required_argument, 0, OPT_TOL},         {"threads", required_argument, 0, OPT_THREADS},
    {"units", required_argument, 0, OPT_UNITS},     {"ev-patch", required_argument, 0, OPT_EVPATCH},
    {"solver", required_argument, 0, OPT_SOLVER},   {"continuity", required_argument, 0, OPT_CONT},
    {"format", required_argument, 0, OPT_FORMAT},   {"scale", required_argument, 0, OPT_SCALE},
    {"tol-abs", required_argument, 0, OPT_TOLABS},  {"angle-tol", required_argument, 0, OPT_ANGLE},
    {"curvature-tol", required_argument, 0, OPT_CURV}, {"max-memory", required_argument, 0, OPT_MAXMEM},
    {"ev-construction", required_argument, 0, OPT_EVMETHOD},
    {"max-spans", required_argument, 0, OPT_MAXSPANS}, {"gluing", required_argument, 0, OPT_GLUING},
    {"progress", no_argument, 0, OPT_PROGRESS},     {"help", no_argument, 0, 'h'},
    {"version", no_argument, 0, 'V'},               {0, 0, 0, 0}};

/* One option; 0, 2 (usage error, message printed) or -1 (done: --help, --version). */
static int parse_option(int c, const char *arg, cli_options *o)
{
    switch (c) {
    case 'o':
        if (o->noutputs == MAX_OUTPUTS) { say("at most %d outputs", MAX_OUTPUTS); return 2; }
        o->outputs[o->noutputs++] = arg;
        return 0;
    case OPT_FORMAT:
        if ((o->format = q2n_format_parse(arg)) == Q2N_FORMAT_NONE) {
            say("--format: expected obj, step, iges or json, got '%s'", arg);
            return 2;
        }
        return 0;
    case OPT_TESS: o->set |= Q2N_GIVEN_TESS; return parse_int(arg, "--tess", 2, 10000, &o->tess) ? 2 : 0;
    case OPT_GRID: o->set |= Q2N_GIVEN_GRID; return parse_int(arg, "--grid", 1, 10000, &o->grid) ? 2 : 0;
    case OPT_SUBDIV: return parse_int(arg, "--subdivide", 0, 6, &o->model.subdivide) ? 2 : 0;
    case OPT_THREADS:
        o->set |= Q2N_GIVEN_THREADS;
        if (parse_int(arg, "--threads", 1, 4096, &o->fit.threads)) return 2;
        o->model.threads = o->fit.threads;
        return 0;
    case OPT_MAXSPANS: return parse_int(arg, "--max-spans", 1, 1024, &o->fit.max_spans) ? 2 : 0;
    case OPT_GLUING:
        if (strcmp(arg, "exact") == 0) o->fit.no_exact = 0;
        else if (strcmp(arg, "least-squares") == 0) o->fit.no_exact = 1;
        else { say("--gluing: expected exact or least-squares, got '%s'", arg); return 2; }
        return 0;
    case OPT_EVMETHOD: {
        q2n_ev_method k;
        if (q2n_ev_method_parse(arg, &k)) { say("--ev-construction: expected fair or paper, got '%s'", arg); return 2; }
        o->model.ev_method = (int)k;
        return 0;
    }
    case OPT_CLASS:
        o->set |= Q2N_GIVEN_CLASS;
        if (!(o->model.cls = q2n_spline_class_find(arg))) {
            char known[200] = "";
            for (const q2n_spline_class *const *k = q2n_spline_classes(); *k; k++)
                snprintf(known + strlen(known), sizeof known - strlen(known), " %s", (*k)->name);
            say("--class: unknown class '%s' (known:%s)", arg, known);
            return 2;
        }
        return 0;
    case OPT_PARAM:
        o->set |= Q2N_GIVEN_PARAM;
        if (q2n_param_method_parse(arg, &o->model.param.method)) {
            say("--param: expected centripetal, chordal, uniform or mean, got '%s'", arg);
            return 2;
        }
        return 0;
    case OPT_ALPHA:
        o->set |= Q2N_GIVEN_ALPHA;
        return parse_real(arg, "--alpha", 0, 1, 2, " (use --param uniform for alpha 0)", &o->model.param.alpha) ? 2 : 0;
    case OPT_TOL: o->set |= Q2N_GIVEN_TOL; return parse_real(arg, "--tol", Q2N_TOL_MIN, 0, Q2N_TOL_MAX, "", &o->fit.tol) ? 2 : 0;
    case OPT_TOLABS:
        o->set |= Q2N_GIVEN_TOL;
        return parse_real(arg, "--tol-abs", 0, 1, 1e300, " (model units)", &o->fit.tol_abs) ? 2 : 0;
    case OPT_ANGLE:
        o->set |= Q2N_GIVEN_ANGLE_TOL;
        return parse_real(arg, "--angle-tol", 0, 1, 90, " (degrees)", &o->fit.g1_tol_deg) ? 2 : 0;
    case OPT_CURV:
        o->set |= Q2N_GIVEN_CURVATURE_TOL;
        return parse_real(arg, "--curvature-tol", 0, 1, 10, " (relative)", &o->fit.g2_tol_rel) ? 2 : 0;
    case OPT_SCALE: return parse_real(arg, "--scale", 1e-12, 0, 1e12, "", &o->model.scale) ? 2 : 0;
    case OPT_MAXMEM: return parse_size(arg, &o->max_memory) ? 2 : 0;
    case OPT_EVPATCH: {
        q2n_ev_patch_kind k;
        o->set |= Q2N_GIVEN_EV_PATCH;
        if (q2n_ev_patch_parse(arg, &k)) { say("--ev-patch: expected g1 or g2, got '%s'", arg); return 2; }
        o->model.ev_patch = (int)k;
        return 0;
    }
    case OPT_SOLVER:
        o->set |= Q2N_GIVEN_SOLVER;
        if (strcmp(arg, "ceres") == 0) o->fit.solver = Q2N_FIT_SOLVER_CERES;
        else if (strcmp(arg, "direct") == 0) o->fit.solver = Q2N_FIT_SOLVER_DIRECT;
        else { say("--solver: expected ceres or direct, got '%s'", arg); return 2; }
        return 0;
    case OPT_CONT:
        o->set |= Q2N_GIVEN_CONTINUITY;
        if (strcmp(arg, "g1") == 0) o->fit.continuity = 1;
        else if (strcmp(arg, "g2") == 0) o->fit.continuity = 2;
        else { say("--continuity: expected g1 or g2, got '%s'", arg); return 2; }
        return 0;
    case OPT_UNITS:
        o->set |= Q2N_GIVEN_UNITS;
        if (q2n_units_parse(arg, &o->xopt.units)) { say("--units: expected mm, cm, m, in or ft, got '%s'", arg); return 2; }
        return 0;
    case OPT_SURFACE:
        if (strcmp(arg, "augmented") == 0) o->model.method = Q2N_SURFACE_AUGMENTED;
        else if (strcmp(arg, "acc3") == 0) o->model.method = Q2N_SURFACE_ACC3;
        else if (strcmp(arg, "acc-g1") == 0) o->model.method = Q2N_SURFACE_ACC_G1;
        else { say("--surface: expected augmented, acc3 or acc-g1, got '%s'", arg); return 2; }
        return 0;
    case OPT_STRAT: {
        q2n_error e;
        o->set |= Q2N_GIVEN_ACC_STRATEGY;
        if (q2n_acc_parse_strategy(arg, &o->model.acc_strategy, &e)) { say("--acc-strategy: %s", e.message); return 2; }
        return 0;
    }
    case OPT_PROGRESS: o->progress = 1; return 0;
    case 'q': o->quiet = 1; return 0;
    case 'h': usage(stdout); return -1;
    case 'V': printf(PROG " %s\n", QUAD2NURBS_VERSION); return -1;
    default: return usage_error(); /* getopt printed what was wrong */
    }
}

static int parse_args(int argc, char **argv, cli_options *o)
{
    int c;
    if (argc > 1 && strcmp(argv[1], "sample") == 0) {
        o->sample = 1;
        argv[1] = argv[0];
        argv++, argc--;
    }
    argv[0] = (char *)PROG; /* getopt's messages name the program, not its path */
    while ((c = getopt_long(argc, argv, "o:qhV", LONGOPTS, NULL)) != -1) {
        int rc = parse_option(c, optarg, o);
        if (rc) return rc;
    }
    if (optind != argc - 1) {
        say(optind == argc ? "no input mesh given" : "expected exactly one input mesh, got %d", argc - optind);
        return usage_error();
    }
    o->input = argv[optind];
    if (!o->sample && o->noutputs == 0) {
        say("no output given (-o FILE.obj|.step|.igs|.json), or use `quad2nurbs sample`");
        return usage_error();
    }
    if (o->fit.tol > 0 && o->fit.tol_abs > 0) {
        say("--tol and --tol-abs are alternatives: give one");
        return usage_error();
    }
    for (int i = 0; i < o->noutputs; i++)
        if (o->sample && !strcmp(o->outputs[i], "-")) {
            say("-o - and `sample` would both write to standard output");
            return usage_error();
        }
    return 0;
}

/* Exit code of a library status: input problems are the user's (2), the rest is 1. */
/* Exit code of a failed read or build: 1 for what is not the input's fault (memory; valid input
 * whose evaluation gave a non-finite number), 2 for bad input (an unreadable file included). */
static int input_exit(q2n_status st) { return st == Q2N_ERR_NOMEM || st == Q2N_ERR_NUMERIC ? 1 : 2; }

/* "0.13 µm" in the model's unit (SI prefixes for metric units); ASCII without UTF-8. */
static void fmt_length(double v, q2n_units u, int utf8, char *out, size_t n)
{
    double mm = q2n_units_in_mm(u);
    if (u == Q2N_UNITS_IN || u == Q2N_UNITS_FT) { snprintf(out, n, "%.2g %s", v, q2n_units_name(u)); return; }
    double m = v * mm / 1000.0;
    static const struct { double f; const char *s, *a; } P[] = {
        {1, "m", "m"}, {1e-3, "mm", "mm"}, {1e-6, "\xc2\xb5m", "um"}, {1e-9, "nm", "nm"}};
    int i = 0;
    while (i < 3 && fabs(m) < P[i].f) i++;
    snprintf(out, n, "%.2g %s", m / P[i].f, utf8 ? P[i].s : P[i].a);
}

static void summary(const cli_options *o, const q2n_model *m, int fit, int utf8)
{
    char line[1024];
    int n = snprintf(line, sizeof line, "%s: %d faces, %d patches, read %.3f s, build %.3f s", o->input, m->mesh->nf,
                     m->mesh->nf - m->uncovered, m->t_read, m->t_build);
    if (fit) {
        char abs[48];
        const q2n_fit_report *r = &m->fit;
        fmt_length(r->max_dev_rel * r->diag, o->xopt.units, utf8, abs, sizeof abs);
        n += snprintf(line + n, sizeof line - (size_t)n, ", fit %.3f s (max dev %.2g %s diag = %s, G1 %.2g%s", m->t_fit,
                      r->max_dev_rel, utf8 ? "\xc3\x97" : "x", abs, r->g1_max_deg, utf8 ? "\xc2\xb0" : " deg");
        if (r->continuity == 2) n += snprintf(line + n, sizeof line - (size_t)n, ", G2 %.2g %%", 100 * r->g2_max_rel);
        n += snprintf(line + n, sizeof line - (size_t)n, ", control points per face %d/%d/%d min/median/max",
                      r->cp_min, r->cp_median, r->cp_max);
        if (r->step_bytes)
            n += snprintf(line + n, sizeof line - (size_t)n, ", STEP %.1f KB/face", r->step_bytes / 1024.0 / m->mesh->nf);
        if (r->iges_bytes)
            n += snprintf(line + n, sizeof line - (size_t)n, ", IGES %.1f KB/face", r->iges_bytes / 1024.0 / m->mesh->nf);
        n += snprintf(line + n, sizeof line - (size_t)n, ")");
    }
    snprintf(line + n, sizeof line - (size_t)n, ", write %.3f s", m->t_write);
    fprintf(stderr, PROG ": ");
    /* the input name is escaped; the rest is ours (UTF-8 symbols only in a UTF-8 locale) */
    char name[1024];
    q2n_escape(name, sizeof name, o->input);
    fprintf(stderr, "%s%s\n", name, line + strlen(o->input));
}

typedef struct run_state {
    cli_options *o;
    cli_progress prog;
    q2n_output_set outs;
    q2n_model *m;
    int utf8;
} run_state;

/* Remove the outputs' temporaries; signals are held off meanwhile, so that the handler never
 * sees a name that is being freed. */
static void discard_outputs(run_state *s)
{
    sigset_t old;
    cli_signals_block(&old);
    q2n_outputs_abort(&s->outs);
    cli_signals_register(NULL);
    cli_signals_unblock(&old);
}

/* Print an error (after clearing the progress line), clean up, return the exit code. */
static int fail(run_state *s, int code, const char *msg)
{
    cli_progress_clear(&s->prog);
    say("%s", msg);
    discard_outputs(s);
    q2n_model_free(s->m);
    return code;
}

static void warning(run_state *s, const char *msg)
{
    if (s->o->quiet) return;
    cli_progress_clear(&s->prog);
    say("warning: %s", msg);
}

static int run(run_state *s)
{
    cli_options *o = s->o;
    q2n_error err = {Q2N_OK, ""};
    q2n_status st;
    char msg[1200];
    if ((st = q2n_export_date_from_env(&o->xopt, &err))) return fail(s, 2, err.message);
    /* outputs first: a wrong name or an unwritable place shows before any work; the temporaries
     * are registered for the signal handler before a signal can come in */
    sigset_t old;
    cli_signals_block(&old);
    st = q2n_outputs_open(&s->outs, o->noutputs, o->outputs, o->format, o->input, &err);
    if (!st) cli_signals_register(&s->outs);
    cli_signals_unblock(&old);
    if (st) return fail(s, st == Q2N_ERR_ARG ? 2 : 1, err.message);
    o->model.progress = (q2n_progress_sink){cli_progress_report, &s->prog, q2n_now()};
    if ((st = q2n_model_read(o->input, &o->model, &s->m, &err))) return fail(s, input_exit(st), err.message);
    q2n_model *m = s->m;
    if (m->read_info.tags) {
        snprintf(msg, sizeof msg, "%s:%ld: %ld OpenSubdiv tag line%s ignored (%s): sharp features are not supported yet",
                 o->input, m->read_info.tag_line, m->read_info.tags, m->read_info.tags == 1 ? "" : "s",
                 m->read_info.tag_names[0] ? m->read_info.tag_names : "t");
        warning(s, msg);
    }
    q2n_plan plan = {0};
    plan.sample = o->sample;
    plan.tess = o->tess;
    plan.grid = o->grid;
    plan.continuity = o->fit.continuity;
    plan.nout = s->outs.n;
    plan.out = s->outs.out;
    for (int i = 0; i < s->outs.n; i++) {
        plan.fit |= q2n_format_needs_fit(s->outs.out[i].format);
        plan.obj |= s->outs.out[i].format == Q2N_FORMAT_OBJ;
    }
    char warn[16][160];
    int nw = q2n_options_warnings(&o->model, &o->fit, o->set, &plan, warn, 16);
    for (int i = 0; i < nw; i++) warning(s, warn[i]);
    if ((st = q2n_model_check_resources(m, &plan, o->max_memory, &err)))
        return fail(s, st == Q2N_ERR_ARG ? 2 : 1, err.message);
    if ((st = q2n_model_construct(m, &err))) return fail(s, input_exit(st), err.message);
    if (m->note[0] && !o->quiet) { /* what the ACC path did (information, not a warning) */
        cli_progress_clear(&s->prog);
        say("%s", m->note);
    }
    if (m->warning[0]) warning(s, m->warning);
    if (m->uncovered) {
        snprintf(msg, sizeof msg, "%d of %d faces are in extraordinary regions that the regular construction does not "
                 "cover; they are left out of the output", m->uncovered, m->mesh->nf);
        warning(s, msg);
    }
    if ((st = q2n_model_resolve_tol(m, &o->fit, &err))) return fail(s, 2, err.message);
    if (plan.fit && (st = q2n_model_fit(m, &o->fit, &err))) {
        snprintf(msg, sizeof msg, "%s: %s", o->input, err.message);
        return fail(s, st == Q2N_ERR_GEOMETRY || st == Q2N_ERR_NOMEM || st == Q2N_ERR_NUMERIC ? 1 : 2, msg);
    }
    if (plan.fit && (!m->fit.g1_met || !m->fit.g2_met)) {
        snprintf(msg, sizeof msg, "continuity target not met: %s (max G1 %.3g deg, G2 %.3g)",
                 m->fit.note[0] ? m->fit.note : "see the report", m->fit.g1_max_deg, m->fit.g2_max_rel);
        warning(s, msg);
    }
    if (o->sample && (st = q2n_model_write_samples(m, o->grid, stdout, &err))) {
        if (errno == EPIPE) { /* `sample ... | head`: the reader has enough; end quietly, as filters do */
            discard_outputs(s);
            signal(SIGPIPE, SIG_DFL);
            raise(SIGPIPE);
        }
        return fail(s, 1, err.message);
    }
    /* CAD files first, so the report written after them gives their sizes */
    for (int pass = 0; pass < 2; pass++)
        for (int i = 0; i < s->outs.n; i++)
            if ((s->outs.out[i].format == Q2N_FORMAT_JSON) == pass &&
                (st = q2n_model_write_output(m, &s->outs.out[i], o->tess, &o->xopt, &err)))
                return fail(s, 1, err.message);
    cli_signals_block(&old); /* the temporaries' names stay valid for the handler until they are gone */
    st = q2n_outputs_commit(&s->outs, &err);
    cli_signals_register(NULL);
    cli_signals_unblock(&old);
    if (st) return fail(s, 1, err.message);
    if (o->sample && fflush(stdout) != 0) return fail(s, 1, "standard output: write failed");
    cli_progress_clear(&s->prog);
    if (!o->quiet && !o->sample) summary(o, m, plan.fit, s->utf8);
    q2n_model_free(m);
    s->m = NULL;
    return 0;
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
    o.fit.continuity = 0;    /* follow the construction */
    o.fit.tol = 0;           /* the default unless --tol or --tol-abs */
    o.fit.g1_tol_deg = o.fit.g2_tol_rel = 0;
    int rc = parse_args(argc, argv, &o);
    if (rc) return rc < 0 ? 0 : rc;
    /* UTF-8 symbols (°, ×, µ) in the summary only where the terminal's locale is UTF-8 */
    int utf8 = 0;
    if (setlocale(LC_CTYPE, "")) utf8 = strcmp(nl_langinfo(CODESET), "UTF-8") == 0;
    setlocale(LC_CTYPE, "C");
    run_state s;
    memset(&s, 0, sizeof s);
    s.o = &o;
    s.utf8 = utf8;
    cli_progress_init(&s.prog, o.quiet, o.progress, utf8);
    cli_signals_install();
    return run(&s);
}
