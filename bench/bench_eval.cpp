// bench_eval.cpp — benchmark (not a test): surface evaluation speed, position + first
// derivatives, single-threaded, of the augmented surface vs OpenSubdiv's Catmull–Clark limit
// evaluation (Bfr::Surface::Evaluate) on the same mesh and the same per-face grid, measured in
// the same run.  Prints points per second of both and the ratio (absolute times on shared
// machines are noisy; the ratio is the figure of merit).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <algorithm>
#include <vector>

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include "osd_ref.h"

extern "C" {
#include "check.h"
#include "meshgen.h"
#include "patch/augmented.h"
}

using namespace OpenSubdiv;

// Thread CPU time: the machine is shared, so wall time would charge us for other processes.
static double now()
{
    timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static volatile double sink;

// Our evaluation: build once, then evaluate every patch on an N x N grid (grid fast path) or
// point by point; repeated until at least min_s seconds have passed.
static double bench_ours(const q2n_surface *S, int nf, int N, int per_point, double min_s)
{
    std::vector<double> t(N), out(9 * N * N);
    for (int i = 0; i < N; i++) t[i] = (i + 0.5) / N;
    long pts = 0;
    double t0 = now(), el;
    do {
        for (int f = 0; f < nf; f++) {
            if (per_point) {
                for (int j = 0; j < N; j++)
                    for (int i = 0; i < N; i++) q2n_surface_eval(S, f, t[i], t[j], 1, &out[9 * (j * N + i)]);
            } else {
                q2n_surface_eval_grid(S, f, N, t.data(), N, t.data(), out.data());
            }
            sink += out[0];
        }
        pts += (long)nf * N * N;
    } while ((el = now() - t0) < min_s);
    return pts / el;
}

static double bench_osd(const q2n_mesh *m, int N, double min_s, double *setup_s)
{
    double t0 = now();
    Far::TopologyRefiner *ref = osd_refiner_create(m, Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
    Bfr::RefinerSurfaceFactory<> factory(*ref);
    std::vector<Bfr::Surface<double>> surf(m->nf);
    std::vector<std::vector<double>> pp(m->nf);
    for (int f = 0; f < m->nf; f++) {
        factory.InitVertexSurface(f, &surf[f]);
        pp[f].resize(3 * surf[f].GetNumPatchPoints());
        surf[f].PreparePatchPoints(m->pos, 3, pp[f].data(), 3);
    }
    *setup_s = now() - t0;
    std::vector<double> t(N);
    for (int i = 0; i < N; i++) t[i] = (i + 0.5) / N;
    long pts = 0;
    double P[3], Du[3], Dv[3], el;
    t0 = now();
    do {
        for (int f = 0; f < m->nf; f++) {
            if (!surf[f].IsValid()) continue;
            for (int j = 0; j < N; j++)
                for (int i = 0; i < N; i++) {
                    double uv[2] = {t[i], t[j]};
                    surf[f].Evaluate(uv, pp[f].data(), 3, P, Du, Dv);
                    sink += P[0] + Du[1] + Dv[2];
                }
        }
        pts += (long)m->nf * N * N;
    } while ((el = now() - t0) < min_s);
    delete ref;
    return pts / el;
}

static void run(const char *label, const q2n_mesh *m, int N)
{
    q2n_augmented_options opt = {q2n_spline_class_find("D5C2P2S4"), {Q2N_PARAM_CENTRIPETAL, -1}};
    q2n_surface *S = nullptr;
    q2n_error err;
    double t0 = now();
    if (q2n_augmented_build(m, &opt, nullptr, &S, &err)) {
        std::printf("%s: build failed: %s\n", label, err.message);
        return;
    }
    double build = now() - t0, setup_osd = 0;
    double grid = 0, point = 0, osd = 0;
    for (int round = 0; round < 3; round++) { // interleaved rounds, best of each
        grid = std::max(grid, bench_ours(S, m->nf, N, 0, 0.3));
        point = std::max(point, bench_ours(S, m->nf, N, 1, 0.2));
        osd = std::max(osd, bench_osd(m, N, 0.3, &setup_osd));
    }
    std::printf("%-24s %5d faces, %dx%d grid/face | quad2nurbs grid %6.2f M pts/s, per-point %6.2f M pts/s | "
                "OpenSubdiv Bfr %6.2f M pts/s | ratio grid/OSD %.2f, per-point/OSD %.2f | setup: ours %.1f ms, OSD %.1f ms\n",
                label, m->nf, N, N, grid * 1e-6, point * 1e-6, osd * 1e-6, grid / osd, point / osd, build * 1e3,
                setup_osd * 1e3);
    q2n_surface_free(S);
}

int main()
{
    std::printf("bench_eval: surface evaluation, position + first derivatives, 1 thread, D5C2P2S4 centripetal\n");
    const char *p = chk_shared_mesh("osd_catmark_torus.obj");
    q2n_error err;
    q2n_mesh *m = nullptr;
    if (p && q2n_mesh_read_obj(p, &m, &err) == Q2N_OK) {
        run("osd_catmark_torus.obj", m, 32);
        q2n_mesh_free(m);
    } else if (p) {
        std::printf("%s: %s\n", p, err.message);
    }
    q2n_mesh *t = mg_torus(96, 48, 3.0, 1.0, 0.1, 1, 5); // the largest regular mesh: 4608 faces
    if (t) {
        run("procedural torus 96x48", t, 16);
        q2n_mesh_free(t);
    }
    return 0;
}
