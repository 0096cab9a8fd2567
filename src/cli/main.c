/* main.c — `quad2nurbs` command line (getopt_long, GNU conventions; see usage()).
 *
 * A run: options -> outputs opened (every temporary created: unwritable places fail in
 * milliseconds) -> mesh read -> estimate checked against the limits -> surface built -> fit (when
 * an output needs it) -> outputs written -> all committed at once.  Exit status: 0 success, 2 bad
 * input or usage, 1 any other failure (writing included); a signal removes the temporaries. */
#include <errno.h>
#include <getopt.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <langinfo.h>
#include <locale.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "quad2nurbs.h"
#include "cli.h"
#include "cli/policy.h"

#define MAX_OUTPUTS 8
#define PROG "quad2nurbs"

/* Command-line settings (the library options plus what only the CLI has). */
typedef struct cli_options {
    const char *input;
    const char *outputs[MAX_OUTPUTS];
    int noutputs, sample, grid, quiet, progress;
    q2n_options opt;              /* the library's options; opt.given: Q2N_GIVEN_* of those given */
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
          "MESH: Wavefront .obj, .off (ASCII), .ply or .stl (ASCII or binary).\n"
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
          "      --ev-gluing G     patches of the fair construction: auto (default: their edges\n"
          "                        glued by polynomials wherever the corners allow it; G1 patches\n"
          "                        are then bi-quintic and the fit exactly G1 with one span, G2\n"
          "                        patches ripple less and fit with fewer spans; a region of G2\n"
          "                        patches keeps the smoothsteps where they ripple less and bend\n"
          "                        no more), polynomial (no such choice) or smoothstep (every\n"
          "                        edge as before: least squares in the fit)\n"
          "      --keep-flat       where the mesh is flat around a vertex (its faces' corners in\n"
          "                        one plane), the fair construction keeps the surface in that\n"
          "                        plane exactly (flat panels stay flat; the bends beside them\n"
          "                        get tighter)\n"
          "      --frame F         auto (default): where the mesh's faces are stretched on the\n"
          "                        whole (a model scaled along an axis), also build in the frame\n"
          "                        that makes them isotropic (or only the extraordinary regions,\n"
          "                        against the mesh's own regular patches, or only their vertex\n"
          "                        charts measured there), map back, and keep the\n"
          "                        build that ripples less (no more bending energy, no more\n"
          "                        folds); off: build in the mesh's own frame only\n"
          "      --param P         edge parameter intervals: centripetal (default), chordal,\n"
          "                        uniform, mean (ribbon-averaged baseline of the paper)\n"
          "      --alpha A         exponent of |edge|^A for centripetal/mean (default 0.5)\n"
          "      --pair-triangles  merge pairs of triangles into quads first, across their shared\n"
          "                        edges (convex pairs, best shaped first): the quads of a\n"
          "                        triangulated quad mesh (an STL tessellation) come back; the\n"
          "                        triangles left need --subdivide\n"
          "      --fill-ngons      fill every face of n >= 6 sides, n even, with quads (a ring of n\n"
          "                        and a grid inside it, shaped to the polygon; odd ones in pairs,\n"
          "                        one vertex more each on a strip of quads between them): no\n"
          "                        vertex of valence n (--subdivide would split it into n kites\n"
          "                        around one), and the mesh's own vertices still interpolated\n"
          "      --subdivide N     apply N Catmull-Clark steps first (needed for non-quad faces); the\n"
          "                        surface then passes through the subdivision surface's limit points\n"
          "      --limit-points    the same without --subdivide: every vertex moved to its\n"
          "                        Catmull-Clark limit position first (the mesh's own vertices are\n"
          "                        then not interpolated); --no-limit-points: through the control\n"
          "                        vertices, also after --subdivide\n"
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
          "      --threads N       threads of the construction and the fit (default: the processors\n"
          "                        this process may use; results do not depend on it; at most 64)\n"
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
    OPT_CURV, OPT_MAXMEM, OPT_PROGRESS, OPT_EVMETHOD, OPT_EVGLUING, OPT_MAXSPANS, OPT_GLUING, OPT_LIMIT, OPT_NOLIMIT, OPT_KEEPFLAT, OPT_PAIR, OPT_FILL, OPT_FRAME
};

static const struct option LONGOPTS[] = {
    {"output", required_argument, 0, 'o'},         {"tess", required_argument, 0, OPT_TESS},
    {"grid", required_argument, 0, OPT_GRID},       {"class", required_argument, 0, OPT_CLASS},
    {"param", required_argument, 0, OPT_PARAM},     {"alpha", required_argument, 0, OPT_ALPHA},
    {"subdivide", required_argument, 0, OPT_SUBDIV}, {"surface", required_argument, 0, OPT_SURFACE},
    {"keep-flat", no_argument, 0, OPT_KEEPFLAT}, {"frame", required_argument, 0, OPT_FRAME}, {"pair-triangles", no_argument, 0, OPT_PAIR}, {"fill-ngons", no_argument, 0, OPT_FILL}, {"limit-points", no_argument, 0, OPT_LIMIT},   {"no-limit-points", no_argument, 0, OPT_NOLIMIT},
    {"acc-strategy", required_argument, 0, OPT_STRAT}, {"quiet", no_argument, 0, 'q'},
    {"tol", required_argument, 0, OPT_TOL},         {"threads", required_argument, 0, OPT_THREADS},
    {"units", required_argument, 0, OPT_UNITS},     {"ev-patch", required_argument, 0, OPT_EVPATCH},
    {"solver", required_argument, 0, OPT_SOLVER},   {"continuity", required_argument, 0, OPT_CONT},
    {"format", required_argument, 0, OPT_FORMAT},   {"scale", required_argument, 0, OPT_SCALE},
    {"tol-abs", required_argument, 0, OPT_TOLABS},  {"angle-tol", required_argument, 0, OPT_ANGLE},
    {"curvature-tol", required_argument, 0, OPT_CURV}, {"max-memory", required_argument, 0, OPT_MAXMEM},
    {"ev-construction", required_argument, 0, OPT_EVMETHOD},
    {"ev-gluing", required_argument, 0, OPT_EVGLUING},
    {"max-spans", required_argument, 0, OPT_MAXSPANS}, {"gluing", required_argument, 0, OPT_GLUING},
    {"progress", no_argument, 0, OPT_PROGRESS},     {"help", no_argument, 0, 'h'},
    {"version", no_argument, 0, 'V'},               {0, 0, 0, 0}};

/* An enum option: its value into *value, else a message and -1. */
static int parse_choice(q2n_choice what, const char *opt, const char *arg, int *value)
{
    if (q2n_parse_choice(what, arg, value) == Q2N_OK) return 0;
    say("%s: expected %s, got '%s'", opt, q2n_choice_list(what), arg);
    return -1;
}

/* One option; 0, 2 (usage error, message printed) or -1 (done: --help, --version). */
static int parse_option(int c, const char *arg, cli_options *o)
{
    q2n_options *q = &o->opt;
    int v = 0;
    switch (c) {
    case 'o':
        if (o->noutputs == MAX_OUTPUTS) { say("at most %d outputs", MAX_OUTPUTS); return 2; }
        o->outputs[o->noutputs++] = arg;
        return 0;
    case OPT_FORMAT:
        if (parse_choice(Q2N_CHOICE_FORMAT, "--format", arg, &v)) return 2;
        q->format = (q2n_format)v;
        return 0;
    case OPT_TESS: q->given |= Q2N_GIVEN_TESS; return parse_int(arg, "--tess", 2, 10000, &q->tess) ? 2 : 0;
    case OPT_GRID: q->given |= Q2N_GIVEN_GRID; return parse_int(arg, "--grid", 1, 10000, &o->grid) ? 2 : 0;
    case OPT_SUBDIV: return parse_int(arg, "--subdivide", 0, 6, &q->subdivide) ? 2 : 0;
    case OPT_LIMIT: q->limit_points = 1; return 0;
    case OPT_PAIR: q->pair_triangles = 1; return 0;
    case OPT_FILL: q->fill_ngons = 1; return 0;
    case OPT_KEEPFLAT: q->keep_flat = 1; return 0;
    case OPT_FRAME:
        if (strcmp(arg, "auto") && strcmp(arg, "off")) {
            fprintf(stderr, "quad2nurbs: --frame: unknown '%s' (expected auto or off)\n", arg);
            return 2;
        }
        q->frame = strcmp(arg, "auto") ? -1 : 0;
        return 0;
    case OPT_NOLIMIT: q->limit_points = -1; return 0;
    case OPT_THREADS: q->given |= Q2N_GIVEN_THREADS; return parse_int(arg, "--threads", 1, 4096, &q->threads) ? 2 : 0;
    case OPT_MAXSPANS: return parse_int(arg, "--max-spans", 1, 1024, &q->max_spans) ? 2 : 0;
    case OPT_GLUING:
        if (parse_choice(Q2N_CHOICE_GLUING, "--gluing", arg, &v)) return 2;
        q->gluing = (q2n_gluing)v;
        return 0;
    case OPT_EVGLUING:
        if (strcmp(arg, "auto") && strcmp(arg, "polynomial") && strcmp(arg, "smoothstep")) {
            fprintf(stderr, "quad2nurbs: --ev-gluing: unknown '%s' (expected auto, polynomial or smoothstep)\n", arg);
            return 2;
        }
        q->ev_smooth_gluing = !strcmp(arg, "smoothstep")   ? Q2N_EV_GLUING_SMOOTHSTEP
                              : !strcmp(arg, "polynomial") ? Q2N_EV_GLUING_POLYNOMIAL
                                                           : Q2N_EV_GLUING_AUTO;
        return 0;
    case OPT_EVMETHOD:
        if (parse_choice(Q2N_CHOICE_EV_CONSTRUCTION, "--ev-construction", arg, &v)) return 2;
        q->ev_construction = (q2n_ev_method)v;
        return 0;
    case OPT_CLASS:
        q->given |= Q2N_GIVEN_CLASS;
        if (parse_choice(Q2N_CHOICE_CLASS, "--class", arg, &v)) return 2;
        q->spline_class = (q2n_class)v;
        return 0;
    case OPT_PARAM:
        q->given |= Q2N_GIVEN_PARAM;
        if (parse_choice(Q2N_CHOICE_PARAM, "--param", arg, &v)) return 2;
        q->param = (q2n_param_method)v;
        return 0;
    case OPT_ALPHA:
        q->given |= Q2N_GIVEN_ALPHA;
        return parse_real(arg, "--alpha", 0, 1, 2, " (use --param uniform for alpha 0)", &q->alpha) ? 2 : 0;
    case OPT_TOL: q->given |= Q2N_GIVEN_TOL; return parse_real(arg, "--tol", Q2N_TOL_MIN, 0, Q2N_TOL_MAX, "", &q->tol) ? 2 : 0;
    case OPT_TOLABS:
        q->given |= Q2N_GIVEN_TOL;
        return parse_real(arg, "--tol-abs", 0, 1, 1e300, " (model units)", &q->tol_abs) ? 2 : 0;
    case OPT_ANGLE:
        q->given |= Q2N_GIVEN_ANGLE_TOL;
        return parse_real(arg, "--angle-tol", 0, 1, 90, " (degrees)", &q->angle_tol_deg) ? 2 : 0;
    case OPT_CURV:
        q->given |= Q2N_GIVEN_CURVATURE_TOL;
        return parse_real(arg, "--curvature-tol", 0, 1, 10, " (relative)", &q->curvature_tol) ? 2 : 0;
    case OPT_SCALE: return parse_real(arg, "--scale", Q2N_SCALE_MIN, 0, Q2N_SCALE_MAX, "", &q->scale) ? 2 : 0;
    case OPT_MAXMEM: return parse_size(arg, &q->max_memory) ? 2 : 0;
    case OPT_EVPATCH:
        q->given |= Q2N_GIVEN_EV_PATCH;
        if (parse_choice(Q2N_CHOICE_EV_PATCH, "--ev-patch", arg, &v)) return 2;
        q->ev_patch = (q2n_ev_patch_kind)v;
        return 0;
    case OPT_SOLVER:
        q->given |= Q2N_GIVEN_SOLVER;
        if (parse_choice(Q2N_CHOICE_SOLVER, "--solver", arg, &v)) return 2;
        q->solver = (q2n_solver)v;
        return 0;
    case OPT_CONT:
        q->given |= Q2N_GIVEN_CONTINUITY;
        if (parse_choice(Q2N_CHOICE_CONTINUITY, "--continuity", arg, &v)) return 2;
        q->continuity = (q2n_continuity)v;
        return 0;
    case OPT_UNITS:
        q->given |= Q2N_GIVEN_UNITS;
        if (parse_choice(Q2N_CHOICE_UNITS, "--units", arg, &v)) return 2;
        q->units = (q2n_units)v;
        return 0;
    case OPT_SURFACE:
        if (parse_choice(Q2N_CHOICE_SURFACE, "--surface", arg, &v)) return 2;
        q->surface = (q2n_surface_method)v;
        return 0;
    case OPT_STRAT:
        q->given |= Q2N_GIVEN_ACC_STRATEGY;
        if (parse_choice(Q2N_CHOICE_ACC_STRATEGY, "--acc-strategy", arg, &v)) return 2;
        q->acc_strategy = (q2n_acc_strategy)v;
        return 0;
    case OPT_PROGRESS: o->progress = 1; return 0;
    case 'q': o->quiet = 1; return 0;
    case 'h': usage(stdout); return -1;
    case 'V': printf(PROG " %s\n", q2n_version()); return -1;
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
    if (o->opt.tol > 0 && o->opt.tol_abs > 0) {
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
static void fmt_length(double v, q2n_units u, double mm, int utf8, char *out, size_t n)
{
    if (u == Q2N_UNITS_IN || u == Q2N_UNITS_FT) {
        snprintf(out, n, "%.2g %s", v, q2n_choice_name(Q2N_CHOICE_UNITS, (int)u));
        return;
    }
    double m = v * mm / 1000.0;
    static const struct { double f; const char *s, *a; } P[] = {
        {1, "m", "m"}, {1e-3, "mm", "mm"}, {1e-6, "\xc2\xb5m", "um"}, {1e-9, "nm", "nm"}};
    int i = 0;
    while (i < 3 && fabs(m) < P[i].f) i++;
    snprintf(out, n, "%.3g %s", m / P[i].f, utf8 ? P[i].s : P[i].a);
}

static void summary(const cli_options *o, const q2n_report *r, int fit, int utf8)
{
    char line[1024];
    int n = snprintf(line, sizeof line, "%s: %d faces", o->input, r->faces);
    if (r->paired_quads || r->triangles_left)
        n += snprintf(line + n, sizeof line - (size_t)n, " (%d pairs of triangles merged into quads, %d triangles left)",
                      r->paired_quads, r->triangles_left);
    if (r->filled_faces)
        n += snprintf(line + n, sizeof line - (size_t)n, " (%d faces of 5 or more sides filled with %d quads)",
                      r->filled_faces, r->fill_quads);
    n += snprintf(line + n, sizeof line - (size_t)n, ", %d patches, read %.3f s, build %.3f s", r->patches, r->t_read,
                  r->t_build);
    if (fit) {
        char abs[48];
        fmt_length(r->max_dev, r->units, r->unit_mm, utf8, abs, sizeof abs);
        const char *deg = utf8 ? "\xc2\xb0" : " deg";
        n += snprintf(line + n, sizeof line - (size_t)n,
                      ", fit %.3f s (max dev %.2g %s diag = %s, G1 %.2g%s (target %.2g%s)", r->t_fit, r->max_dev_rel,
                      utf8 ? "\xc3\x97" : "x", abs, r->g1_max_deg, deg, r->g1_tol_deg, deg);
        if (r->continuity == 2)
            n += snprintf(line + n, sizeof line - (size_t)n, ", G2 %.2g %% (target %.2g %%)", 100 * r->g2_max_rel,
                          100 * r->g2_tol_rel);
        n += snprintf(line + n, sizeof line - (size_t)n, ", control points per face %d/%d/%d min/median/max",
                      r->cp_min, r->cp_median, r->cp_max);
        if (r->step_bytes)
            n += snprintf(line + n, sizeof line - (size_t)n, ", STEP %.1f KB/face", r->step_bytes / 1024.0 / r->faces);
        if (r->iges_bytes)
            n += snprintf(line + n, sizeof line - (size_t)n, ", IGES %.1f KB/face", r->iges_bytes / 1024.0 / r->faces);
        n += snprintf(line + n, sizeof line - (size_t)n, ")");
    }
    snprintf(line + n, sizeof line - (size_t)n, ", write %.3f s", r->t_write);
    fprintf(stderr, PROG ": ");
    /* the input name is escaped; the rest is ours (UTF-8 symbols only in a UTF-8 locale) */
    char name[1024];
    q2n_escape(name, sizeof name, o->input);
    fprintf(stderr, "%s%s\n", name, line + strlen(o->input));
}

typedef struct run_state {
    cli_options *o;
    cli_progress prog;
    q2n_outputs *outs;
    q2n_model *m;
    int utf8;
    int warned;             /* the model's warnings printed so far */
} run_state;

/* Remove the outputs' temporaries; signals are held off meanwhile, so that the handler never
 * sees a name that is being freed. */
static void discard_outputs(run_state *s)
{
    sigset_t old;
    cli_signals_block(&old);
    q2n_outputs_abort(s->outs);
    s->outs = NULL;
    cli_signals_register(NULL);
    cli_signals_unblock(&old);
}

/* Print an error (after clearing the progress line), clean up, return the exit code. */
static int fail(run_state *s, int code, const char *msg)
{
    cli_progress_clear(&s->prog);
    say("%s", msg);
    discard_outputs(s);
    q2n_close(s->m);
    return code;
}

/* The model's warnings not printed yet. */
static void warnings(run_state *s)
{
    const char *w;
    for (; (w = q2n_warning(s->m, s->warned)); s->warned++) {
        if (s->o->quiet) continue;
        cli_progress_clear(&s->prog);
        say("warning: %s", w);
    }
}

static int run(run_state *s)
{
    cli_options *o = s->o;
    char err[1024], msg[1200];
    q2n_status st;
    /* outputs first: a wrong name or an unwritable place shows before any work; the temporaries
     * are registered for the signal handler before a signal can come in */
    sigset_t old;
    cli_signals_block(&old);
    st = q2n_outputs_open(o->outputs, o->noutputs, o->opt.format, o->input, &s->outs, err, sizeof err);
    if (!st) cli_signals_register(s->outs);
    cli_signals_unblock(&old);
    if (st) return fail(s, st == Q2N_ERR_ARG ? 2 : 1, err);
    o->opt.progress = cli_progress_report;
    o->opt.progress_user = &s->prog;
    if ((st = q2n_read(o->input, &o->opt, &s->m, err, sizeof err))) return fail(s, input_exit(st), err);
    q2n_model *m = s->m;
    warnings(s);
    int fit = 0;
    for (int i = 0; i < q2n_outputs_count(s->outs); i++) {
        q2n_format f = q2n_outputs_format(s->outs, i);
        fit |= f == Q2N_FORMAT_STEP || f == Q2N_FORMAT_IGES || f == Q2N_FORMAT_JSON;
    }
    st = q2n_check_plan(m, s->outs, o->sample ? o->grid : 0, err, sizeof err);
    warnings(s);
    if (st) return fail(s, st == Q2N_ERR_ARG ? 2 : 1, err);
    if ((st = q2n_build(m, err, sizeof err))) return fail(s, input_exit(st), err);
    q2n_report r;
    q2n_get_report(m, &r);
    if (r.construction_note[0] && !o->quiet) { /* what the ACC path did (information, not a warning) */
        cli_progress_clear(&s->prog);
        say("%s", r.construction_note);
    }
    warnings(s);
    if (fit && (st = q2n_fit(m, err, sizeof err))) {
        size_t li = strlen(o->input); /* a message that names the file itself is not prefixed again */
        const char *at = strstr(err, o->input);
        if (at && at[li] == ':') snprintf(msg, sizeof msg, "%s", err);
        else snprintf(msg, sizeof msg, "%s: %s", o->input, err);
        return fail(s, st == Q2N_ERR_GEOMETRY || st == Q2N_ERR_NOMEM || st == Q2N_ERR_NUMERIC ? 1 : 2, msg);
    }
    warnings(s);
    if (o->sample && (st = q2n_write_samples(m, o->grid, stdout, err, sizeof err))) {
        if (errno == EPIPE) { /* `sample ... | head`: the reader has enough; end quietly, as filters do */
            discard_outputs(s);
            signal(SIGPIPE, SIG_DFL);
            raise(SIGPIPE);
        }
        return fail(s, 1, err);
    }
    if ((st = q2n_outputs_write(m, s->outs, err, sizeof err))) return fail(s, 1, err);
    cli_signals_block(&old); /* the temporaries' names stay valid for the handler until they are gone */
    st = q2n_outputs_commit(s->outs, err, sizeof err);
    s->outs = NULL;
    cli_signals_register(NULL);
    cli_signals_unblock(&old);
    if (st) return fail(s, 1, err);
    if (o->sample && fflush(stdout) != 0) return fail(s, 1, "standard output: write failed");
    cli_progress_clear(&s->prog);
    q2n_get_report(m, &r);
    if (!o->quiet && !o->sample) summary(o, &r, fit, s->utf8);
    q2n_close(m);
    s->m = NULL;
    return 0;
}

int main(int argc, char **argv)
{
#ifdef __GLIBC__
    /* freed work arrays stay in the heap for the next face (cli/policy.h) */
    mallopt(M_MMAP_THRESHOLD, CLI_MMAP_THRESHOLD);
    mallopt(M_TRIM_THRESHOLD, CLI_TRIM_THRESHOLD);
#endif
    cli_options o;
    memset(&o, 0, sizeof o);
    o.grid = 5;               /* zeroed library options are its defaults */
    int rc = parse_args(argc, argv, &o);
    if (rc) return rc < 0 ? 0 : rc;
    /* the machine's processors unless --threads says otherwise (the results do not depend on it) */
    if (!(o.opt.given & Q2N_GIVEN_THREADS)) o.opt.threads = q2n_default_threads();
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
