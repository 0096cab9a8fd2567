/* ref_acc_osd.cpp — the Catmull–Clark path against OpenSubdiv's limit surface (Bfr::Surface,
 * Sdc::SCHEME_CATMARK, VTX_BOUNDARY_EDGE_AND_CORNER, smooth approximation level 10 so that the
 * reference error near extraordinary vertices is far below the errors measured).
 *
 *  1. Patch corners are Catmull–Clark limit positions: every corner of every patch against
 *     OpenSubdiv at >= 1000 points per mesh (meshes are subdivided first when they have fewer
 *     corners), acc3 and acc-g1, on every mesh of ../shared/meshes (n-gon meshes included: the
 *     build subdivides them).  Also q2n_acc_limit_points.
 *  2. Meshes without extraordinary vertices (tori, open grids with boundaries and corners):
 *     acc3 is the limit surface itself (bicubic B-spline), at 8 x 8 points per face.
 *  3. Convergence (seed 001 §6.3): max distance to the limit under successive subdivision of the
 *     input, acc3 and acc-g1 (cs-s); table of errors and rates; acc-g1 must converge at about
 *     rate 2 and acc3 at about 1.5 (asserted with margins, see below). */
#include "osd_ref.h"
#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <cmath>
#include <ctime>
#include <memory>
#include <string>
#include <vector>

extern "C" {
#include "acc/acc.h"
#include "mesh/mesh.h"
}
#include "check.h"

using namespace OpenSubdiv;

namespace {

/* Limit surface of one mesh: one prepared Bfr surface per face. */
struct Limit {
    std::unique_ptr<Far::TopologyRefiner> refiner;
    std::vector<Bfr::Surface<double>> surf;
    std::vector<std::vector<double>> pts;
    bool ok = false;
};

std::unique_ptr<Limit> make_limit(const q2n_mesh *m, int approx_level)
{
    std::unique_ptr<Limit> L(new Limit);
    L->refiner.reset(osd_refiner_create(m));
    if (!L->refiner) return L;
    Bfr::RefinerSurfaceFactory<>::Options opt;
    opt.SetApproxLevelSmooth(approx_level);
    Bfr::RefinerSurfaceFactory<> factory(*L->refiner, opt);
    L->surf.resize(m->nf);
    L->pts.resize(m->nf);
    for (int f = 0; f < m->nf; f++) {
        if (!factory.InitVertexSurface<double>(f, &L->surf[f])) return L;
        L->pts[f].resize(3 * (size_t)L->surf[f].GetNumPatchPoints());
        L->surf[f].PreparePatchPoints(m->pos, Bfr::Surface<double>::PointDescriptor(3), L->pts[f].data(),
                                      Bfr::Surface<double>::PointDescriptor(3));
    }
    L->ok = true;
    return L;
}

extern "C" q2n_status limit_eval(void *ctx, int face, double u, double v, double p[3], double n[3])
{
    Limit *L = static_cast<Limit *>(ctx);
    double uv[2] = { u, v }, du[3], dv[3];
    L->surf[face].Evaluate(uv, L->pts[face].data(), Bfr::Surface<double>::PointDescriptor(3), p, du, dv);
    n[0] = du[1] * dv[2] - du[2] * dv[1];
    n[1] = du[2] * dv[0] - du[0] * dv[2];
    n[2] = du[0] * dv[1] - du[1] * dv[0];
    return Q2N_OK;
}

q2n_mesh *read_mesh(const char *file)
{
    const char *path = chk_shared_mesh(file);
    if (!path) return NULL;
    q2n_mesh *m = NULL;
    q2n_error err;
    if (q2n_mesh_read_obj(path, &m, &err) != Q2N_OK) {
        CHECK(0, "%s: %s", file, err.message);
        return NULL;
    }
    return m;
}

q2n_mesh *subdivided(const q2n_mesh *m, int steps)
{
    q2n_mesh *s = NULL;
    q2n_error err;
    if (q2n_mesh_subdivide(m, steps, &s, &err) != Q2N_OK) {
        CHECK(0, "subdivide %s: %s", m->name, err.message);
        return NULL;
    }
    return s;
}

const char *ALL[] = {
    "osd_catmark_cube.obj", "osd_catmark_torus.obj", "osd_catmark_righthanded.obj",
    "osd_catmark_flap.obj", "osd_catmark_tent.obj", "osd_catmark_square_hedit0.obj",
    "osd_catmark_gregory_test0.obj", "osd_catmark_gregory_test1.obj", "osd_catmark_gregory_test6.obj",
    "osd_catmark_fvar_bound3.obj", "osd_catmark_xord_boundary.obj", "osd_catmark_helmet.obj",
    "osd_catmark_pawn.obj", "osd_catmark_rook.obj", "gismo_ev_valence3.obj",
    "gismo_ev_valence3_carpet.obj", "gismo_ev_valence5_carpet.obj", "gismo_ev_valence6_carpet.obj",
    "gismo_ev_valence7_carpet.obj", "gismo_ev_valence8_carpet.obj", "gismo_cube_with_boundary.obj",
    "gismo_octtorus.obj", "gismo_octtorus_hole.obj", "gismo_polycube.obj",
    "crane_spot_control_mesh.obj",
};

/* 1. corners */
void test_corners()
{
    printf("%-32s %-6s %6s %6s %12s\n", "mesh (corners vs OpenSubdiv)", "method", "steps", "points", "max/diag");
    for (const char *file : ALL) {
        q2n_mesh *m0 = read_mesh(file);
        if (!m0) continue;
        /* enough corners: 4 * faces >= 1000 (faces x4 per step) */
        int pre = 0;
        for (int nf = m0->nf; 4 * nf < 1000; nf *= 4) pre++;
        q2n_mesh *m = pre ? subdivided(m0, pre) : m0;
        if (!m) { q2n_mesh_free(m0); continue; }
        double diag = q2n_mesh_bbox_diag(m);
        for (int me = 0; me < 2; me++) {
            q2n_acc_options o = { (q2n_acc_method)me, Q2N_ACC_CS_S, 0 };
            q2n_surface *s = NULL;
            q2n_acc_info info;
            q2n_error err;
            if (q2n_acc_build(m, &o, &s, &info, &err) != Q2N_OK) {
                CHECK(0, "%s: %s", file, err.message);
                continue;
            }
            const q2n_mesh *bm = q2n_acc_info_mesh(&info, m);
            std::unique_ptr<Limit> L = make_limit(bm, 10);
            CHECK(L->ok, "%s: OpenSubdiv limit surface", file);
            double maxe = 0;
            int npts = 0;
            std::vector<double> lim(3 * (size_t)bm->nv);
            CHECK(q2n_acc_limit_points(bm, lim.data(), NULL, &err) == Q2N_OK, "limit points: %s", err.message);
            for (int f = 0; L->ok && f < bm->nf; f++)
                for (int c = 0; c < 4; c++) {
                    double u = (c == 1 || c == 2), v = (c >= 2), e[3], p[3], n[3];
                    q2n_surface_eval(s, f, u, v, 0, e);
                    limit_eval(L.get(), f, u, v, p, n);
                    for (int t = 0; t < 3; t++) maxe = std::fmax(maxe, std::fabs(e[t] - p[t]));
                    npts++;
                    if (me == 0) { /* q2n_acc_limit_points at the face's corner vertex */
                        const double *q = &lim[3 * (size_t)bm->face_vert[bm->face_start[f] + c]];
                        for (int t = 0; t < 3; t++) maxe = std::fmax(maxe, std::fabs(q[t] - p[t]));
                    }
                }
            CHECK(npts >= 1000, "%s: only %d corner points", file, npts);
            CHECK(maxe <= 1e-12 * diag, "%s %s: corner vs limit %.3g (diag %.3g)", file,
                  q2n_acc_method_name(o.method), maxe, diag);
            printf("%-32s %-6s %6d %6d %12.2e\n", file, q2n_acc_method_name(o.method),
                   pre + info.subdiv_steps, npts, maxe / diag);
            q2n_surface_free(s);
            q2n_acc_info_free(&info);
        }
        if (m != m0) q2n_mesh_free(m);
        q2n_mesh_free(m0);
    }
}

/* 2. no EVs: acc3 = limit */
void test_regular()
{
    const char *files[] = { "osd_catmark_torus.obj", "gismo_octtorus.obj", "osd_catmark_flap.obj",
                            "osd_catmark_tent.obj", "osd_catmark_square_hedit0.obj" };
    for (const char *file : files) {
        q2n_mesh *m = read_mesh(file);
        if (!m) continue;
        double diag = q2n_mesh_bbox_diag(m);
        q2n_surface *s = NULL;
        q2n_acc_info info;
        q2n_error err;
        q2n_acc_options o = { Q2N_ACC_3, Q2N_ACC_CS_S, 0 };
        if (q2n_acc_build(m, &o, &s, &info, &err) != Q2N_OK) {
            CHECK(0, "%s: %s", file, err.message);
            q2n_mesh_free(m);
            continue;
        }
        CHECK(info.n_ev_interior == 0 && info.n_ev_boundary == 0, "%s has EVs", file);
        std::unique_ptr<Limit> L = make_limit(m, 10);
        q2n_acc_distance d;
        q2n_status st = q2n_acc_limit_distance(s, m, 8, limit_eval, L.get(), 0, &d, &err);
        CHECK(st == Q2N_OK && d.geom_max <= 1e-12 * diag && d.normal_max <= 1e-10,
              "%s: acc3 vs limit without EVs: %.3g (diag %.3g), normal %.3g", file, d.geom_max, diag,
              d.normal_max);
        printf("no EVs, %-28s acc3 vs limit: max %.2e x diag, unit normal %.2e (%d points)\n", file,
               d.geom_max / diag, d.normal_max, d.n_samples);
        q2n_surface_free(s);
        q2n_acc_info_free(&info);
        q2n_mesh_free(m);
    }
}

struct Pt {
    double p[3];
    void Clear() { p[0] = p[1] = p[2] = 0; }
    void AddWithWeight(Pt const &s, double w) { for (int t = 0; t < 3; t++) p[t] += w * s.p[t]; }
};

/* Far::PrimvarRefiner::Limit tangents (Sdc limit masks) at the base vertices. */
void far_limit_tangents(const Far::TopologyRefiner &r, const q2n_mesh *m, std::vector<double> &t1,
                        std::vector<double> &t2)
{
    std::vector<Pt> src(m->nv), P(m->nv), A(m->nv), B(m->nv);
    for (int v = 0; v < m->nv; v++) for (int t = 0; t < 3; t++) src[v].p[t] = m->pos[3 * v + t];
    Far::PrimvarRefinerReal<double>(r).Limit(src, P, A, B);
    t1.resize(3 * (size_t)m->nv);
    t2.resize(3 * (size_t)m->nv);
    for (int v = 0; v < m->nv; v++)
        for (int t = 0; t < 3; t++) { t1[3 * v + t] = A[v].p[t]; t2[3 * v + t] = B[v].p[t]; }
}

/* 2b. exact limit samples (q2n_acc_limit_samples_make): subdivided-mesh vertices mapped to
 * (face, u, v) of the base mesh, limit points and normals, against OpenSubdiv. */
void test_samples()
{
    const char *files[] = { "osd_catmark_cube.obj", "gismo_ev_valence5_carpet.obj", "gismo_polycube.obj",
                            "osd_catmark_xord_boundary.obj", "osd_catmark_tent.obj", "gismo_octtorus_hole.obj",
                            "osd_catmark_helmet.obj" };
    for (const char *file : files) {
        q2n_mesh *m = read_mesh(file);
        if (!m) continue;
        double diag = q2n_mesh_bbox_diag(m);
        std::unique_ptr<Limit> L = make_limit(m, 10);
        q2n_acc_limit_samples ls;
        q2n_error err;
        if (q2n_acc_limit_samples_make(m, 2, &ls, &err) != Q2N_OK) {
            CHECK(0, "%s: %s", file, err.message);
            q2n_mesh_free(m);
            continue;
        }
        double dp = 0, dn = 0;
        int nn = 0;
        std::vector<double> T1, T2;
        far_limit_tangents(*L->refiner, m, T1, T2);
        for (int i = 0; i < ls.n; i++) {
            double p[3], n[3];
            limit_eval(L.get(), ls.face[i], ls.uv[2 * i], ls.uv[2 * i + 1], p, n);
            double ln = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            for (int t = 0; t < 3; t++) dp = std::fmax(dp, std::fabs(p[t] - ls.p[3 * i + t]));
            /* Bfr's normal exactly at an EV is itself approximate (its refined patches end there):
             * at interior EVs compare with Far's limit tangent masks instead (Sdc, exact); at
             * boundary EVs Far uses Biermann's masks for modified rules (docs/acc.md), skip. */
            bool ev = i < m->nv && (m->vert_boundary[i] ? m->valence[i] >= 4 : m->valence[i] != 4);
            if (ev && m->vert_boundary[i]) continue;
            if (ev) {
                const double *a = &T1[3 * (size_t)i], *b = &T2[3 * (size_t)i];
                n[0] = a[1] * b[2] - a[2] * b[1];
                n[1] = a[2] * b[0] - a[0] * b[2];
                n[2] = a[0] * b[1] - a[1] * b[0];
                ln = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            }
            for (int t = 0; t < 3; t++) dn = std::fmax(dn, std::fabs(n[t] / ln - ls.nrm[3 * i + t]));
            nn++;
        }
        CHECK(dp <= 1e-12 * diag && dn <= 1e-9, "%s: limit samples vs OpenSubdiv: point %.3g (diag %.3g), "
              "normal %.3g", file, dp, diag, dn);
        printf("limit samples %-30s %5d points: max |p - osd| %.2e x diag, normals %.2e (%d)\n", file, ls.n,
               dp / diag, dn, nn);
        q2n_acc_limit_samples_free(&ls);
        q2n_mesh_free(m);
    }
}

/* 3. convergence */
struct Row { double g[2], gp[2], nrm[2]; };

void test_convergence()
{
    const char *files[] = { "gismo_ev_valence5_carpet.obj", "osd_catmark_cube.obj",
                            "osd_catmark_xord_boundary.obj", "gismo_polycube.obj" };
    const int levels = 3; /* meshes subdivided 1, 2, 3 times */
    printf("\nconvergence to the Catmull-Clark limit (max over 6x6 samples per face, / bbox diag;\n"
           "param = same (u,v), proj = closest point on the patch; rate = log2 ratio)\n");
    printf("%-30s %3s %6s | %10s %5s %10s %5s %9s | %10s %5s %10s %5s %9s\n", "mesh", "lvl", "faces",
           "acc3 param", "rate", "acc3 proj", "rate", "normal", "g1 param", "rate", "g1 proj", "rate", "normal");
    for (const char *file : files) {
        q2n_mesh *m0 = read_mesh(file);
        if (!m0) continue;
        double diag = q2n_mesh_bbox_diag(m0);
        std::vector<Row> rows;
        for (int l = 1; l <= levels; l++) {
            q2n_mesh *m = subdivided(m0, l);
            if (!m) break;
            std::unique_ptr<Limit> L = make_limit(m, 10);
            Row row = {};
            for (int me = 0; me < 2; me++) {
                q2n_acc_options o = { (q2n_acc_method)me, Q2N_ACC_CS_S, -1 };
                q2n_surface *s = NULL;
                q2n_acc_info info;
                q2n_error err;
                if (q2n_acc_build(m, &o, &s, &info, &err) != Q2N_OK) {
                    CHECK(0, "%s level %d: %s", file, l, err.message);
                    continue;
                }
                q2n_acc_distance d, dp;
                q2n_acc_limit_distance(s, m, 6, limit_eval, L.get(), 0, &d, &err);
                q2n_acc_limit_distance(s, m, 6, limit_eval, L.get(), 1, &dp, &err);
                row.g[me] = d.geom_max / diag;
                row.gp[me] = dp.geom_max / diag;
                row.nrm[me] = dp.normal_max;
                q2n_surface_free(s);
                q2n_acc_info_free(&info);
            }
            double r[4] = { NAN, NAN, NAN, NAN };
            if (!rows.empty()) {
                const Row &p = rows.back();
                r[0] = std::log2(p.g[0] / row.g[0]);
                r[1] = std::log2(p.gp[0] / row.gp[0]);
                r[2] = std::log2(p.g[1] / row.g[1]);
                r[3] = std::log2(p.gp[1] / row.gp[1]);
            }
            printf("%-30s %3d %6d | %10.3e %5.2f %10.3e %5.2f %9.2e | %10.3e %5.2f %10.3e %5.2f %9.2e\n",
                   file, l, m->nf, row.g[0], r[0], row.gp[0], r[1], row.nrm[0], row.g[1], r[2], row.gp[1],
                   r[3], row.nrm[1]);
            rows.push_back(row);
            q2n_mesh_free(m);
        }
        if (rows.size() == (size_t)levels) {
            const Row &a = rows[levels - 2], &b = rows[levels - 1];
            double r3 = std::log2(a.gp[0] / b.gp[0]), rg = std::log2(a.gp[1] / b.gp[1]);
            /* seed 001 §6.3 reports rate 2 for G1 and 1.5 for ACC3 (closest-point distance,
             * interior EVs).  Measured here with 3 levels: G1 1.85-2.4 at interior EVs, 1.7 at
             * boundary EVs; ACC3 1.6-2.6.  Asserted with margins: */
            CHECK(rg >= 1.6, "%s: acc-g1 convergence rate %.2f (< 1.6)", file, rg);
            CHECK(r3 >= 1.4, "%s: acc3 convergence rate %.2f (< 1.4)", file, r3);
            CHECK(b.gp[1] < a.gp[1] && b.gp[0] < a.gp[0], "%s: errors must decrease", file);
            if (std::string(file).find("boundary") == std::string::npos)
                CHECK(b.gp[1] < b.gp[0] && b.nrm[1] < b.nrm[0],
                      "%s: acc-g1 should be closer to the limit than acc3 (%.3g vs %.3g)", file, b.gp[1], b.gp[0]);
        }
        q2n_mesh_free(m0);
    }
}

} // namespace

int main()
{
    clock_t t0 = clock();
    test_corners();
    test_regular();
    test_samples();
    test_convergence();
    printf("ref_acc_osd: %.1f s CPU\n", (double)(clock() - t0) / CLOCKS_PER_SEC);
    CHECK_DONE("ref_acc_osd");
}
