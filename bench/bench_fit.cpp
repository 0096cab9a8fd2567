// bench_fit.cpp — benchmark (not a test): the whole pipeline and the fit alone on the largest
// test meshes, with 1 and 2 threads, next to OpenCASCADE's GeomAPI_PointsToBSplineSurface fitting
// the same patches (a degree-5 surface through a 20 x 20 sample grid of each patch, to the same
// absolute tolerance) in the same run.  The peer does far less — no shared boundaries, no G1/G2
// conditions, no verification at unused points — so the ratio is an upper bound on our overhead.
// Times are thread CPU time for single-threaded runs and wall time for the 2-thread run.
#include <cstdio>
#include <ctime>
#include <vector>

#include <GeomAPI_PointsToBSplineSurface.hxx>
#include <Geom_BSplineSurface.hxx>
#include <TColgp_Array2OfPnt.hxx>

extern "C" {
#include "api/model.h"
#include "check.h"
}

static double wall()
{
    timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static double occt_fit(const q2n_model *m, double tol_abs, int *ok)
{
    const int N = 20;
    std::vector<double> t(N), buf(9 * N * N);
    for (int i = 0; i < N; i++) t[i] = double(i) / (N - 1);
    double total = 0;
    *ok = 0;
    for (int k = 0; k < m->mesh->nf; k++) {
        q2n_surface_eval_grid(m->surface, k, N, t.data(), N, t.data(), buf.data());
        TColgp_Array2OfPnt pts(1, N, 1, N);
        for (int j = 0; j < N; j++)
            for (int i = 0; i < N; i++) {
                const double *e = &buf[9 * (j * N + i)];
                pts.SetValue(i + 1, j + 1, gp_Pnt(e[0], e[1], e[2]));
            }
        double t0 = wall();
        GeomAPI_PointsToBSplineSurface fit(pts, 5, 5, GeomAbs_C2, tol_abs);
        total += wall() - t0;
        *ok += fit.IsDone() ? 1 : 0;
    }
    return total;
}

static void run(const char *file, int subdivide)
{
    const char *path = chk_shared_mesh(file);
    if (!path) return; /* chk_shared_mesh said so */
    q2n_model_options mo = {};
    mo.subdivide = subdivide;
    mo.param.alpha = -1;
    q2n_error err;
    for (int threads = 1; threads <= 2; threads++) {
        q2n_model *m = nullptr;
        double t0 = wall();
        if (q2n_model_build(path, &mo, &m, &err)) {
            std::printf("%s: %s\n", file, err.message);
            return;
        }
        q2n_fit_options fo;
        q2n_fit_options_default(&fo);
        fo.continuity = 0;
        fo.threads = threads;
        q2n_status st = q2n_model_fit(m, &fo, &err);
        double total = wall() - t0;
        std::printf("%-34s %4d faces  threads %d | build %.3f s  fit %.3f s  pipeline %.3f s | max dev %.2e  G1 %.2e deg  G2 %.2e  spans %d..%d%s\n",
                    file, m->mesh->nf, threads, m->t_build, m->t_fit, total, m->fit.max_dev_rel, m->fit.g1_max_deg,
                    m->fit.g2_max_rel, m->fit.spans_min, m->fit.spans_max, st ? "  (targets not met)" : "");
        if (threads == 1) {
            int ok;
            double tol_abs = fo.tol * q2n_mesh_bbox_diag(m->mesh);
            double occt = occt_fit(m, tol_abs, &ok);
            std::printf("%-34s OCCT GeomAPI_PointsToBSplineSurface (deg 5, 20x20 samples, %d/%d done): %.3f s"
                        " | ratio ours/OCCT %.2f\n",
                        "", ok, m->mesh->nf, occt, m->t_fit / occt);
        }
        q2n_model_free(m);
    }
}

int main()
{
    std::printf("bench_fit: augmented surface (D5C2P2S4, G2 mode) fitted to tol 1e-5 x bbox diagonal\n");
    run("osd_catmark_pawn.obj", 0);
    run("crane_spot_control_mesh.obj", 1);
    return 0;
}
