/* pipeline.c — read the mesh, optionally subdivide, build the chosen surface construction. */
#include <stdlib.h>
#include <time.h>

#include "cli/cli.h"
#include "patch/augmented.h"

double cli_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

void cli_result_free(cli_result *r)
{
    q2n_surface_free(r->surface);
    q2n_mesh_free(r->mesh);
    r->surface = NULL;
    r->mesh = NULL;
}

int cli_run_pipeline(const cli_options *o, cli_result *r, q2n_error *err)
{
    double t0 = cli_now();
    q2n_status st = q2n_mesh_read_obj(o->input, &r->mesh, err);
    if (st) return st;
    if (o->subdivide > 0) {
        q2n_mesh *sub = NULL;
        if ((st = q2n_mesh_subdivide(r->mesh, o->subdivide, &sub, err))) return st;
        q2n_mesh_free(r->mesh);
        r->mesh = sub;
    }
    if (!r->mesh->all_quads) {
        int f = 0;
        while (f < r->mesh->nf && q2n_face_size(r->mesh, f) == 4) f++;
        return q2n_error_set(err, Q2N_ERR_UNSUPPORTED,
                             "%s:%d: face %d has %d vertices; only quad meshes are supported "
                             "(use --subdivide 1 to apply one Catmull-Clark step first)",
                             o->input, r->mesh->face_line[f], f, q2n_face_size(r->mesh, f));
    }
    r->t_read = cli_now() - t0;
    t0 = cli_now();
    switch (o->surface) {
    case CLI_SURF_AUGMENTED: {
        q2n_augmented_options ao = {o->cls, o->param};
        st = q2n_augmented_build(r->mesh, &ao, NULL, &r->surface, err);
        break;
    }
    default:
        st = q2n_error_set(err, Q2N_ERR_UNSUPPORTED, "surface method not available in this build");
    }
    if (st) return st;
    r->uncovered = q2n_surface_count(r->surface, Q2N_PATCH_UNCOVERED);
    r->t_build = cli_now() - t0;
    return Q2N_OK;
}
