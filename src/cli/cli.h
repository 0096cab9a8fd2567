/* cli.h — the quad2nurbs command line: option parsing (main.c), the pipeline that builds the
 * surface (pipeline.c) and the writers of the CLI's own text outputs (outputs.c).
 * Only this layer prints and chooses exit codes: 0 success, 2 bad input or usage, 1 other failure. */
#ifndef Q2N_CLI_CLI_H
#define Q2N_CLI_CLI_H

#include <stdio.h>

#include "mesh/mesh.h"
#include "param/param.h"
#include "patch/surface.h"
#include "spline/spline.h"

#define Q2N_VERSION_STRING "0.1.0"
#define Q2N_MAX_OUTPUTS 8

typedef enum { CLI_SURF_AUGMENTED = 0, CLI_SURF_ACC3, CLI_SURF_ACCG1 } cli_surface_kind;

typedef struct cli_options {
    const char *input;
    const char *outputs[Q2N_MAX_OUTPUTS];
    int noutputs;
    int sample;             /* `quad2nurbs sample` */
    int grid;               /* sample points per patch side */
    int tess;               /* tessellation points per patch side */
    int subdivide;          /* Catmull–Clark steps first */
    int quiet;
    cli_surface_kind surface;
    const char *acc_strategy;
    const q2n_spline_class *cls;
    q2n_param_options param;
} cli_options;

/* Everything the pipeline produced; freed with cli_result_free. */
typedef struct cli_result {
    q2n_mesh *mesh;         /* the mesh the patches are built on (after --subdivide) */
    q2n_surface *surface;
    int uncovered;          /* faces no construction covers */
    double t_read, t_build; /* seconds */
} cli_result;

int cli_run_pipeline(const cli_options *o, cli_result *r, q2n_error *err);
void cli_result_free(cli_result *r);

/* Writers: OBJ tessellation of the covered patches, and the `sample` listing. */
q2n_status cli_write_tessellation(const cli_result *r, int n, const char *path, q2n_error *err);
q2n_status cli_write_samples(const cli_result *r, int n, FILE *out, q2n_error *err);

double cli_now(void);

#endif
