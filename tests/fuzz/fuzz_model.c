/* fuzz_model.c — fuzz harness: the whole pipeline, parse -> build -> evaluate -> sample -> fit
 * -> STEP text.
 *
 * The first byte picks the options (surface method, spline class, parametrization, one
 * Catmull–Clark step or none); the rest is the OBJ text.  Every stage must succeed or fail with a
 * clean status; what succeeds must be finite: q2n_model_eval values, the printed samples, the
 * fitted control points, the STEP text.  Meshes are capped (faces, half-edges) so one input stays
 * well under a second; the fit runs on the smallest ones, with a loose tolerance and few spans, and
 * on Coons–Gregory patches only when Q2N_FUZZ_FIT_EV is set (they cost seconds under ASan).
 *   libFuzzer:  make fuzz && build/fuzz/fuzz_model -dict=tests/fuzz/obj.dict CORPUS
 *   replayed:   tests/test_fuzz_corpus.c (make check) over the seeds of make_corpus.sh */
#define _GNU_SOURCE /* open_memstream */
#include "api/model.h"
#include "fuzz_common.h"
#include "patch/extraordinary.h"

#define FZ_MODEL_MAX_HE 256   /* half-edges of the input (64 quads) */
#define FZ_MODEL_MAX_FIT 4    /* faces of the built mesh the fit runs on */

static int fz_eval_all(const q2n_model *m)
{
    static const double uv[4] = {0.0, 0.3, 0.77, 1.0};
    double e[9];
    q2n_error err = {Q2N_OK, ""};
    for (int k = 0; k < m->mesh->nf; k++) {
        if (q2n_surface_kind(m->surface, k) == Q2N_PATCH_UNCOVERED) continue;
        for (int i = 0; i < 16; i++) {
            q2n_status st = q2n_model_eval(m, k, uv[i & 3], uv[i >> 2], e, &err);
            if (st) FZ_REQUIRE(st == Q2N_ERR_NUMERIC && fz_clean_error(st, &err), err.message);
            else FZ_REQUIRE(fz_all_finite(e, 9), "evaluation finite");
        }
    }
    return 1;
}

static int fz_samples(const q2n_model *m)
{
    char *buf = NULL;
    size_t len = 0;
    q2n_error err = {Q2N_OK, ""};
    FILE *f = open_memstream(&buf, &len);
    if (!f) return 1;
    q2n_status st = q2n_model_write_samples(m, 3, f, &err);
    fclose(f);
    int ok = st ? fz_clean_error(st, &err) : fz_text_finite(buf, len);
    free(buf);
    FZ_REQUIRE(ok, st ? err.message : "samples finite");
    return 1;
}

static int fz_fit_export(q2n_model *m)
{
    q2n_fit_options o;
    q2n_error err = {Q2N_OK, ""};
    q2n_fit_options_default(&o);
    o.continuity = 0;
    o.tol = 1e-3;
    o.solver = Q2N_FIT_SOLVER_DIRECT;
    /* the invariants are about every code path, not about meeting targets: a few spans and rounds
     * (a 12-face subdivided tetrahedron with G1 patches refines to 48 x 48 spans otherwise, 8 s) */
    o.max_spans = 6;
    o.max_rounds = 2;
    q2n_status st = q2n_model_fit(m, &o, &err);
    if (st) FZ_REQUIRE(fz_clean_status(st, &err), err.message);
    if (!m->nurbs) return 1;
    for (int k = 0; k < m->nurbs->n; k++) {
        const q2n_bspline_surface *p = &m->nurbs->patches[k];
        FZ_REQUIRE(fz_all_finite(p->cp, 3 * (size_t)p->ncp_u * p->ncp_v), "fitted control points finite");
    }
    const q2n_fit_report *r = &m->fit;
    double fig[] = {r->max_dev_rel, r->rms_dev_rel, r->vertex_dev_max_rel, r->g0_max_rel, r->g1_max_deg,
                    r->g2_max_rel, r->g1_construction_deg, r->g2_construction_rel};
    FZ_REQUIRE(fz_all_finite(fig, sizeof fig / sizeof *fig), "report figures finite");
    char *text = NULL;
    size_t len = 0;
    st = q2n_export_step_text(m->nurbs, NULL, &text, &len, &err);
    if (st) FZ_REQUIRE(fz_clean_status(st, &err), err.message);
    else FZ_REQUIRE(text && fz_text_finite(text, len), "STEP text finite");
    free(text);
    return 1;
}

int q2n_fuzz_model(const uint8_t *data, size_t size)
{
    static const char *const classes[4] = {"D5C2P2S4", "D3C1P2S4", "D2C1P2S4", "D5C2P4S6"};
    if (size < 1) return 0;
    unsigned sel = data[0];
    q2n_mesh *mesh = NULL;
    q2n_error err = {Q2N_OK, ""};
    q2n_status st = q2n_mesh_parse_obj((const char *)data + 1, size - 1, FZ_NAME, &mesh, &err);
    if (st) {
        FZ_REQUIRE(fz_clean_error(st, &err) && !mesh, err.message);
        return 0;
    }
    if (mesh->nh > FZ_MODEL_MAX_HE) {
        q2n_mesh_free(mesh);
        return 0;
    }
    q2n_model_options mo;
    memset(&mo, 0, sizeof mo);
    mo.method = (q2n_surface_method)(sel % 3);
    mo.subdivide = (sel >> 2) & 1;
    mo.param.method = (q2n_param_method)((sel >> 3) & 3);
    mo.param.alpha = NAN;
    mo.cls = q2n_spline_class_find(classes[(sel >> 5) & 3]);
    mo.ev_patch = (sel >> 7) & 1 ? Q2N_EV_PATCH_G1 : Q2N_EV_PATCH_DEFAULT;
    q2n_model *m = NULL;
    st = q2n_model_build_mesh(mesh, &mo, &m, &err);
    if (st) {
        FZ_REQUIRE(fz_clean_error(st, &err) && !m, err.message);
        return 0;
    }
    /* fitting Coons–Gregory patches costs ~9 s CPU per input under ASan (their evaluation):
     * only when Q2N_FUZZ_FIT_EV is set (long runs); Bézier and regular patches always */
    static int fit_ev = -1;
    if (fit_ev < 0) fit_ev = getenv("Q2N_FUZZ_FIT_EV") != NULL;
    int ev = q2n_surface_count(m->surface, Q2N_PATCH_COONS_GREGORY) > 0;
    if (fz_eval_all(m) && fz_samples(m) && m->mesh->nf <= FZ_MODEL_MAX_FIT && !m->uncovered &&
        (!ev || fit_ev))
        fz_fit_export(m);
    q2n_model_free(m);
    return 0;
}

#ifdef Q2N_LIBFUZZER
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) { return q2n_fuzz_model(data, size); }
#endif
