/* main.c — `quad2nurbs` command line (getopt_long conventions; see usage()). */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "cli/cli.h"

static void usage(FILE *f)
{
    fputs("usage: quad2nurbs [options] MESH.obj -o OUT [-o OUT ...]\n"
          "       quad2nurbs sample [options] MESH.obj [--grid N]\n"
          "\n"
          "Builds a smooth surface on a quad mesh (patch k on face k, domain [0,1]^2, u along the\n"
          "face's first edge v0->v1, v along v0->v3) and writes it; the output format follows the\n"
          "extension:  .obj  tessellation (--tess N points per patch side).\n"
          "`sample` prints one line per patch k and grid point: k u v x y z xu yu zu xv yv zv.\n"
          "\n"
          "options:\n"
          "  -o, --output FILE     output file (repeatable)\n"
          "      --surface M       augmented (default: augmented interpolatory surface)\n"
          "      --class C         spline class of the augmented surface: D5C2P2S4 (default, C2),\n"
          "                        D3C1P2S4 (Catmull-Rom, C1), D2C1P2S4, D3C2P2S4, D5C2P4S6\n"
          "      --param P         edge parameter intervals: centripetal (default), chordal,\n"
          "                        uniform, mean (ribbon-averaged baseline of the paper)\n"
          "      --alpha A         exponent of |edge|^A for centripetal/mean (default 0.5)\n"
          "      --subdivide N     apply N Catmull-Clark steps first (needed for non-quad faces)\n"
          "      --tess N          tessellation points per patch side (default 9)\n"
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
    enum { OPT_TESS = 256, OPT_GRID, OPT_CLASS, OPT_PARAM, OPT_ALPHA, OPT_SUBDIV, OPT_SURFACE, OPT_STRAT };
    static const struct option longopts[] = {
        {"output", required_argument, 0, 'o'},   {"tess", required_argument, 0, OPT_TESS},
        {"grid", required_argument, 0, OPT_GRID}, {"class", required_argument, 0, OPT_CLASS},
        {"param", required_argument, 0, OPT_PARAM}, {"alpha", required_argument, 0, OPT_ALPHA},
        {"subdivide", required_argument, 0, OPT_SUBDIV}, {"surface", required_argument, 0, OPT_SURFACE},
        {"acc-strategy", required_argument, 0, OPT_STRAT}, {"quiet", no_argument, 0, 'q'},
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
            if (o->noutputs == Q2N_MAX_OUTPUTS) {
                fprintf(stderr, "quad2nurbs: at most %d outputs\n", Q2N_MAX_OUTPUTS);
                return 2;
            }
            o->outputs[o->noutputs++] = optarg;
            break;
        case OPT_TESS: if (parse_int(optarg, "--tess", 2, 10000, &o->tess)) return 2; break;
        case OPT_GRID: if (parse_int(optarg, "--grid", 1, 10000, &o->grid)) return 2; break;
        case OPT_SUBDIV: if (parse_int(optarg, "--subdivide", 0, 6, &o->subdivide)) return 2; break;
        case OPT_CLASS:
            if (!(o->cls = q2n_spline_class_find(optarg))) {
                fprintf(stderr, "quad2nurbs: --class: unknown class '%s' (known:", optarg);
                for (const q2n_spline_class *const *k = q2n_spline_classes(); *k; k++)
                    fprintf(stderr, " %s", (*k)->name);
                fputs(")\n", stderr);
                return 2;
            }
            break;
        case OPT_PARAM:
            if (q2n_param_method_parse(optarg, &o->param.method)) {
                fprintf(stderr, "quad2nurbs: --param: expected centripetal, chordal, uniform or mean, got '%s'\n",
                        optarg);
                return 2;
            }
            break;
        case OPT_ALPHA: {
            char *end;
            double a = strtod(optarg, &end);
            if (*end || end == optarg || !(a >= 0 && a <= 2)) {
                fprintf(stderr, "quad2nurbs: --alpha: expected a number in [0, 2], got '%s'\n", optarg);
                return 2;
            }
            o->param.alpha = a;
            break;
        }
        case OPT_SURFACE:
            if (strcmp(optarg, "augmented") == 0) o->surface = CLI_SURF_AUGMENTED;
            else {
                fprintf(stderr, "quad2nurbs: --surface: expected augmented, got '%s'\n", optarg);
                return 2;
            }
            break;
        case OPT_STRAT: o->acc_strategy = optarg; break;
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
        fprintf(stderr, "quad2nurbs: no output given (-o FILE.obj), or use `quad2nurbs sample`\n");
        return 2;
    }
    for (int i = 0; i < o->noutputs; i++) {
        const char *ext = extension(o->outputs[i]);
        if (strcasecmp(ext, ".obj") != 0) {
            fprintf(stderr, "quad2nurbs: %s: unsupported output format '%s' (supported: .obj)\n", o->outputs[i],
                    ext);
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
    default: return 2;
    }
}

int main(int argc, char **argv)
{
    cli_options o = {0};
    o.grid = 5;
    o.tess = 9;
    o.param.method = Q2N_PARAM_CENTRIPETAL;
    o.param.alpha = NAN;
    int rc = parse_args(argc, argv, &o);
    if (rc) return rc < 0 ? 0 : rc;
    if (!o.cls) o.cls = q2n_spline_class_find("D5C2P2S4");

    cli_result r = {0};
    q2n_error err = {Q2N_OK, ""};
    q2n_status st = cli_run_pipeline(&o, &r, &err);
    if (st) {
        fprintf(stderr, "quad2nurbs: %s\n", err.message);
        cli_result_free(&r);
        return exit_code(st);
    }
    if (r.uncovered && !o.quiet)
        fprintf(stderr,
                "quad2nurbs: warning: %d of %d faces are in extraordinary regions that the regular "
                "construction does not cover; they are left out of the output\n",
                r.uncovered, r.mesh->nf);
    double t0 = cli_now();
    if (o.sample) st = cli_write_samples(&r, o.grid, stdout, &err);
    for (int i = 0; !st && i < o.noutputs; i++) st = cli_write_tessellation(&r, o.tess, o.outputs[i], &err);
    if (st) {
        fprintf(stderr, "quad2nurbs: %s\n", err.message);
        cli_result_free(&r);
        return exit_code(st);
    }
    if (!o.quiet && !o.sample)
        fprintf(stderr, "quad2nurbs: %s: %d faces, %d patches (%s, %s), read %.3f s, build %.3f s, write %.3f s\n",
                o.input, r.mesh->nf, r.mesh->nf - r.uncovered, o.cls->name,
                q2n_param_method_name(o.param.method), r.t_read, r.t_build, cli_now() - t0);
    cli_result_free(&r);
    return 0;
}
