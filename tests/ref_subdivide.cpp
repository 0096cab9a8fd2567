/* ref_subdivide.cpp — q2n_mesh_subdivide against OpenSubdiv (Far::TopologyRefiner uniform
 * refinement + Far::PrimvarRefinerReal<double>, Sdc::SCHEME_CATMARK,
 * VTX_BOUNDARY_EDGE_AND_CORNER), on shared meshes with boundaries, n-gons and extraordinary
 * vertices, 1 and 2 levels.
 *
 * Correspondence is taken from OpenSubdiv's own parent/child relations, not from index order:
 * our vertex v -> GetVertexChildVertex(v), face point of face f -> GetFaceChildVertex(f'),
 * edge point of edge (a,b) -> GetEdgeChildVertex(FindEdge(a',b')), sub-face at corner i of
 * face f -> GetFaceChildFaces(f')[i].  Positions must agree to 1e-12 x bbox diagonal and every
 * sub-face must have the same vertices in the same cyclic order (same first vertex).  Whether
 * OpenSubdiv's numbering coincides with ours is printed (informative, not asserted).  The last
 * level's limit positions (q2n_mesh_limit_points) must agree with PrimvarRefiner::Limit to the same
 * tolerance, boundaries and corners included. */
#include "osd_ref.h"
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <cmath>
#include <memory>
#include <vector>

extern "C" {
#include "mesh/mesh.h"
}
#include "check.h"

using namespace OpenSubdiv;

namespace {

struct Vtx {
    double p[3];
    void Clear() { p[0] = p[1] = p[2] = 0.0; }
    void AddWithWeight(Vtx const &s, double w)
    {
        p[0] += w * s.p[0];
        p[1] += w * s.p[1];
        p[2] += w * s.p[2];
    }
};

std::unique_ptr<Far::TopologyRefiner> make_refiner(const q2n_mesh *m, int levels)
{
    std::unique_ptr<Far::TopologyRefiner> r(osd_refiner_create(m));
    if (r) {
        Far::TopologyRefiner::UniformOptions uo(levels);
        uo.fullTopologyInLastLevel = true;
        r->RefineUniform(uo);
    }
    return r;
}

/* One level: our mesh `a` (level k, vertex map amap into OSD level k) and its subdivision `b`.
 * Fills bmap (ours at level k+1 -> OSD level k+1); returns false on a structural mismatch. */
bool compare_level(const char *name, int k, const q2n_mesh *a, const std::vector<int> &amap,
                   const q2n_mesh *b, const Far::TopologyRefiner &r, const std::vector<Vtx> &osd,
                   std::vector<int> &bmap, double tol, int *identity)
{
    Far::TopologyLevel const &L = r.GetLevel(k);
    Far::TopologyLevel const &C = r.GetLevel(k + 1);
    CHECK(C.GetNumVertices() == b->nv && C.GetNumFaces() == b->nf, "%s level %d: OSD V %d F %d, "
          "ours %d %d", name, k + 1, C.GetNumVertices(), C.GetNumFaces(), b->nv, b->nf);
    if (C.GetNumVertices() != b->nv || C.GetNumFaces() != b->nf) return false;
    /* OSD face index of each of our level-k faces: faces are given in our order at level 0,
     * and at level k > 0 our face h (sub-face at corner i of parent face f) was mapped by the
     * previous call; here a's faces are matched through a's own vertex map. */
    bmap.assign(b->nv, -1);
    for (int v = 0; v < a->nv; v++) bmap[v] = L.GetVertexChildVertex(amap[v]);
    std::vector<int> fmap(a->nf, -1), fshift(a->nf, 0); /* OSD face, and its corner of our v0 */
    for (int f = 0; f < a->nf; f++) {
        /* find the OSD face with the same first two vertices (via the edge's faces) */
        int v0 = amap[a->face_vert[a->face_start[f]]], v1 = amap[a->face_vert[a->face_start[f] + 1]];
        int e = L.FindEdge(v0, v1);
        if (e < 0) return false;
        Far::ConstIndexArray ef = L.GetEdgeFaces(e);
        for (int i = 0; i < ef.size(); i++) {
            Far::ConstIndexArray fv = L.GetFaceVertices(ef[i]);
            for (int j = 0; j < fv.size(); j++)
                if (fv[j] == v0 && fv[(j + 1) % fv.size()] == v1 && fv.size() == q2n_face_size(a, f))
                    fmap[f] = ef[i], fshift[f] = j;
        }
        if (fmap[f] < 0) return false;
        bmap[a->nv + f] = L.GetFaceChildVertex(fmap[f]);
    }
    for (int e = 0; e < a->ne; e++) {
        int h = a->edge_he[e];
        int oe = L.FindEdge(amap[q2n_he_origin(a, h)], amap[q2n_he_dest(a, h)]);
        if (oe < 0) return false;
        bmap[a->nv + a->nf + e] = L.GetEdgeChildVertex(oe);
    }
    int nid = 0;
    double maxd = 0.0;
    for (int v = 0; v < b->nv; v++) {
        const double *p = q2n_mesh_vpos(b, v), *q = osd[bmap[v]].p;
        double d = std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                             (p[2] - q[2]) * (p[2] - q[2]));
        if (d > maxd) maxd = d;
        nid += bmap[v] == v;
    }
    CHECK(maxd <= tol, "%s level %d: max |ours - OSD| = %.3g > %.3g", name, k + 1, maxd, tol);
    /* sub-faces: ours at corner i of face f is face face_start[f]+i; OSD's child faces follow
     * OSD's corner order of its face, and a child quad of a quad starts at its parent's corner
     * (OSD keeps the parent's parametric orientation), ours starts at the old vertex */
    int badf = 0, fid = 0, nrot = 0;
    for (int f = 0; f < a->nf; f++) {
        Far::ConstIndexArray cf = L.GetFaceChildFaces(fmap[f]);
        if (cf.size() != q2n_face_size(a, f)) { badf++; continue; }
        for (int i = 0; i < cf.size(); i++) {
            int g = a->face_start[f] + i, oc = (i + fshift[f]) % cf.size(); /* OSD's corner */
            Far::ConstIndexArray fv = C.GetFaceVertices(cf[oc]);
            if (fv.size() != 4) { badf++; continue; }
            int rot = -1; /* OSD starts child face i of a quad at its corner i */
            for (int s = 0; s < 4 && rot < 0; s++) {
                int same = 1;
                for (int j = 0; j < 4; j++) same &= bmap[b->face_vert[4 * g + j]] == fv[(j + s) % 4];
                if (same) rot = s;
            }
            if (rot < 0) badf++;
            else if (rot != (q2n_face_size(a, f) == 4 ? oc : 0)) nrot++;
            fid += cf[oc] == g;
        }
    }
    CHECK(badf == 0, "%s level %d: %d sub-faces differ from OSD's child faces", name, k + 1, badf);
    CHECK(nrot == 0, "%s level %d: %d sub-faces start at an unexpected corner", name, k + 1, nrot);
    printf("%s level %d: V %d F %d, max |ours - OSD| = %.2e (%.2e x diag); OSD numbering equals "
           "ours for %d/%d vertices, %d/%d faces\n", name, k + 1, b->nv, b->nf, maxd,
           maxd / (tol * 1e12), nid, b->nv, fid, b->nf);
    if (identity) *identity = (nid == b->nv && fid == b->nf);
    return true;
}

void compare_mesh(const char *file, int levels)
{
    const char *path = chk_shared_mesh(file);
    if (!path) return;
    q2n_mesh *m0 = NULL;
    q2n_error err = {};
    if (q2n_mesh_read_obj(path, &m0, &err) != Q2N_OK) {
        CHECK(0, "%s: %s", file, err.message);
        return;
    }
    double tol = 1e-12 * q2n_mesh_bbox_diag(m0);
    std::unique_ptr<Far::TopologyRefiner> r = make_refiner(m0, levels);
    CHECK(r != nullptr, "%s: OSD refiner", file);
    if (!r) { q2n_mesh_free(m0); return; }
    std::vector<Vtx> osd(r->GetNumVerticesTotal());
    for (int v = 0; v < m0->nv; v++)
        for (int c = 0; c < 3; c++) osd[v].p[c] = m0->pos[3 * v + c];
    Far::PrimvarRefinerReal<double> pr(*r);
    Vtx *src = osd.data();
    for (int l = 1; l <= levels; l++) {
        Vtx *dst = src + r->GetLevel(l - 1).GetNumVertices();
        pr.Interpolate(l, src, dst);
        src = dst;
    }
    std::vector<int> amap(m0->nv), bmap;
    for (int v = 0; v < m0->nv; v++) amap[v] = v;
    const q2n_mesh *a = m0;
    q2n_mesh *owned = NULL;
    size_t off = 0;
    for (int k = 0; k < levels; k++) {
        q2n_mesh *b = NULL;
        q2n_status st = q2n_mesh_subdivide(a, 1, &b, &err);
        CHECK(st == Q2N_OK, "%s level %d: %s", file, k + 1, err.message);
        if (st) break;
        off += r->GetLevel(k).GetNumVertices();
        std::vector<Vtx> lev(osd.begin() + off, osd.begin() + off + r->GetLevel(k + 1).GetNumVertices());
        int identity = 0;
        bool ok = compare_level(file, k, a, amap, b, *r, lev, bmap, tol, &identity);
        CHECK(ok, "%s level %d: no correspondence with OSD's topology", file, k + 1);
        q2n_mesh_free(owned);
        owned = b;
        a = b;
        amap = bmap;
        if (!ok) break;
    }
    /* q2n_mesh_limit_points on the last level against OpenSubdiv's PrimvarRefiner::Limit (the limit
     * masks of Sdc::SCHEME_CATMARK applied to that level), through the same correspondence */
    if (owned && (int)amap.size() == owned->nv) {
        std::vector<Vtx> lim(r->GetLevel(levels).GetNumVertices());
        Vtx *dst = lim.data();
        pr.Limit(src, dst);
        q2n_mesh *L = NULL;
        q2n_status st = q2n_mesh_limit_points(owned, &L, &err);
        CHECK(st == Q2N_OK, "%s: limit points: %s", file, err.message);
        if (!st) {
            double maxd = 0, moved = 0;
            for (int v = 0; v < owned->nv; v++)
                for (int c = 0; c < 3; c++) {
                    maxd = std::fmax(maxd, std::fabs(L->pos[3 * v + c] - lim[amap[v]].p[c]));
                    moved = std::fmax(moved, std::fabs(L->pos[3 * v + c] - owned->pos[3 * v + c]));
                }
            printf("%s level %d limit points: max |ours - OSD Limit| = %.3g (vertices moved by up to %.3g)\n", file, levels,
                   maxd, moved);
            CHECK(maxd <= tol, "%s level %d: limit points differ from OSD's by %.3g > %.3g", file, levels, maxd, tol);
            CHECK(moved > 100 * tol, "%s level %d: limit points did not move the vertices (%.3g)", file, levels, moved);
        }
        q2n_mesh_free(L);
    }
    /* q2n_mesh_subdivide(m0, levels) in one call gives the same result as repeated single steps */
    q2n_mesh *direct = NULL;
    if (owned && q2n_mesh_subdivide(m0, levels, &direct, &err) == Q2N_OK) {
        CHECK(direct->nv == owned->nv &&
              memcmp(direct->pos, owned->pos, 3 * sizeof(double) * owned->nv) == 0,
              "%s: %d steps at once differ from %d single steps", file, levels, levels);
        q2n_mesh_free(direct);
    }
    q2n_mesh_free(owned);
    q2n_mesh_free(m0);
}

} // namespace

int main()
{
    static const struct { const char *file; int levels; } cases[] = {
        {"osd_catmark_cube.obj", 1},          {"osd_catmark_tent.obj", 1},  {"crane_spot_control_mesh.obj", 1},
        {"osd_catmark_rook.obj", 1},          {"osd_catmark_xord_boundary.obj", 1},
        {"osd_catmark_cube.obj", 2},          {"crane_spot_control_mesh.obj", 2},
        {"osd_catmark_helmet.obj", 3},
    };
    for (const auto &c : cases) compare_mesh(c.file, c.levels);
    CHECK_DONE("ref_subdivide");
}
