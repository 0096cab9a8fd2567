/* ref_export_occt.cpp — second importer for the export stage: OpenCASCADE's own STEPControl_Reader
 * and IGESControl_Reader (C++, no FreeCAD, no Python) read the files the writers produce, and the
 * imported shapes are checked:
 *   - face / shell / solid counts, free edges (edges with one adjacent face) = mesh boundary edges;
 *   - every imported face's B-spline surface has the model's poles and weights (to 1e-14 x scale):
 *     the numbers survive the trip through a foreign parser, in face order;
 *   - G0 gap and G1 normal jump along every shared edge at t = (i + 0.5)/N of the edge's p-curves,
 *     plus LocalAnalysis_SurfaceContinuity's own G1 verdict on the smooth models (tori, cylinder). */
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

extern "C" {
#include "iges/export.h"
#include "test_export_models.h"
}
#include "check.h"

/* OCCT 7.6 headers use std::iterator, deprecated in C++17: not our warning to fix */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
#include <BRep_Tool.hxx>
#include <Geom2d_Curve.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Geom_Surface.hxx>
#include <GeomAbs_Shape.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Reader.hxx>
#include <LocalAnalysis_SurfaceContinuity.hxx>
#include <STEPControl_Reader.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#include <gp_Pnt.hxx>
#include <gp_Pnt2d.hxx>
#include <gp_Vec.hxx>

#if defined(__SANITIZE_ADDRESS__)
/* Under make CONFIG=asan: OpenCASCADE's readers keep allocations in static singletons that it never
 * frees (TKernel's memory manager, XSBase's editors); those are the reference library's, not ours. */
extern "C" const char *__lsan_default_suppressions() { return "leak:libTKernel.so\nleak:libTKXSBase.so\n"; }
#endif
#pragma GCC diagnostic pop

static bool read_shape(const char *path, TopoDS_Shape &out)
{
    size_t n = strlen(path);
    bool step = n > 5 && strcmp(path + n - 5, ".step") == 0;
    if (step) {
        STEPControl_Reader r;
        if (r.ReadFile(path) != IFSelect_RetDone) return false;
        r.TransferRoots();
        out = r.OneShape();
    } else {
        IGESControl_Reader r;
        if (r.ReadFile(path) != IFSelect_RetDone) return false;
        r.TransferRoots();
        out = r.OneShape();
    }
    return !out.IsNull();
}

struct Continuity {
    double g0 = 0, g1_deg = 0;
    int samples = 0, not_g1 = 0; /* LocalAnalysis verdicts */
};

static gp_Vec oriented_normal(const Handle(Geom_Surface) &s, const gp_Pnt2d &uv, const TopoDS_Face &f, gp_Pnt &p)
{
    gp_Vec du, dv;
    s->D1(uv.X(), uv.Y(), p, du, dv);
    gp_Vec n = du.Crossed(dv);
    n.Normalize();
    return f.Orientation() == TopAbs_REVERSED ? n.Reversed() : n;
}

static Continuity audit_edges(const TopoDS_Shape &shape, int N, int *free_edges)
{
    TopTools_IndexedDataMapOfShapeListOfShape emap;
    TopExp::MapShapesAndAncestors(shape, TopAbs_EDGE, TopAbs_FACE, emap);
    Continuity c;
    *free_edges = 0;
    for (int i = 1; i <= emap.Extent(); i++) {
        const TopTools_ListOfShape &fl = emap.FindFromIndex(i);
        if (fl.Extent() == 1) { (*free_edges)++; continue; }
        if (fl.Extent() != 2) continue;
        TopoDS_Edge e = TopoDS::Edge(emap.FindKey(i));
        TopoDS_Face f[2] = {TopoDS::Face(fl.First()), TopoDS::Face(fl.Last())};
        Handle(Geom_Surface) s[2];
        Handle(Geom2d_Curve) pc[2];
        double a[2], b[2];
        for (int k = 0; k < 2; k++) {
            s[k] = BRep_Tool::Surface(f[k]);
            pc[k] = BRep_Tool::CurveOnSurface(e, f[k], a[k], b[k]);
        }
        if (pc[0].IsNull() || pc[1].IsNull()) { c.g0 = INFINITY; continue; }
        for (int j = 0; j < N; j++) {
            double t = (j + 0.5) / N;
            gp_Pnt2d uv[2];
            gp_Pnt p[2];
            gp_Vec n[2];
            for (int k = 0; k < 2; k++) {
                uv[k] = pc[k]->Value(a[k] + t * (b[k] - a[k]));
                n[k] = oriented_normal(s[k], uv[k], f[k], p[k]);
            }
            c.g0 = fmax(c.g0, p[0].Distance(p[1]));
            c.g1_deg = fmax(c.g1_deg, atan2(n[0].Crossed(n[1]).Magnitude(), n[0].Dot(n[1])) * 180.0 / M_PI);
            LocalAnalysis_SurfaceContinuity la(s[0], uv[0].X(), uv[0].Y(), s[1], uv[1].X(), uv[1].Y(), GeomAbs_G1);
            c.samples++;
            if (!la.IsDone() || !la.IsG1()) c.not_g1++;
        }
    }
    return c;
}

/* Poles and weights of each imported face (explorer order) against the model's patches. */
static double pole_error(const TopoDS_Shape &shape, const q2n_nurbs_model *m, int *mismatch)
{
    TopTools_IndexedMapOfShape fm;
    TopExp::MapShapes(shape, TopAbs_FACE, fm);
    double err = 0.0;
    *mismatch = fm.Extent() != m->n;
    for (int k = 1; k <= fm.Extent() && k <= m->n; k++) {
        Handle(Geom_BSplineSurface) bs = Handle(Geom_BSplineSurface)::DownCast(BRep_Tool::Surface(TopoDS::Face(fm(k))));
        const q2n_bspline_surface *s = &m->patches[k - 1];
        if (bs.IsNull() || bs->NbUPoles() != s->ncp_u || bs->NbVPoles() != s->ncp_v) { (*mismatch)++; continue; }
        for (int j = 0; j < s->ncp_v; j++)
            for (int i = 0; i < s->ncp_u; i++) {
                gp_Pnt p = bs->Pole(i + 1, j + 1);
                const double *q = s->cp + 3 * (j * s->ncp_u + i);
                err = fmax(err, fmax(fabs(p.X() - q[0]), fmax(fabs(p.Y() - q[1]), fabs(p.Z() - q[2]))));
                double w = s->weights ? s->weights[j * s->ncp_u + i] : 1.0;
                err = fmax(err, fabs(bs->Weight(i + 1, j + 1) - w));
            }
    }
    return err;
}

static int count(const TopoDS_Shape &s, TopAbs_ShapeEnum t)
{
    TopTools_IndexedMapOfShape m;
    TopExp::MapShapes(s, t, m);
    return m.Extent();
}

static void check_model(const char *name, const q2n_nurbs_model *m, bool closed, bool smooth)
{
    const q2n_mesh *me = m->mesh;
    double diag = em_mesh_diag(me);
    const char *ext[2] = {".step", ".igs"};
    for (int k = 0; k < 2; k++) {
        char path[1200];
        snprintf(path, sizeof path, "%s/%s%s", chk_scratch_dir(), name, ext[k]);
        q2n_error err;
        if (q2n_export_file(m, NULL, path, &err) != Q2N_OK) { CHECK(0, "%s: %s", path, err.message); continue; }
        TopoDS_Shape sh;
        if (!read_shape(path, sh)) { CHECK(0, "%s: OCCT could not read it", path); continue; }
        int nf = count(sh, TopAbs_FACE), nsh = count(sh, TopAbs_SHELL), nso = count(sh, TopAbs_SOLID), fe;
        CHECK(nf == me->nf, "%s: %d faces for %d mesh faces", path, nf, me->nf);
        CHECK(nsh == 1 && nso == (closed ? 1 : 0), "%s: %d shells, %d solids", path, nsh, nso);
        int mismatch;
        double perr = pole_error(sh, m, &mismatch);
        CHECK(mismatch == 0 && perr <= 1e-14 * diag, "%s: imported poles/weights differ by %.3g (%d mismatches)", path,
              perr, mismatch);
        Continuity c = audit_edges(sh, 16, &fe);
        CHECK(fe == em_mesh_boundary_edges(me), "%s: %d free edges, mesh boundary %d", path, fe, em_mesh_boundary_edges(me));
        CHECK(c.g0 <= 1e-9 * diag, "%s: G0 gap %.3g (diag %.3g)", path, c.g0, diag);
        if (smooth) {
            CHECK(c.g1_deg <= 0.01, "%s: G1 %.3g deg", path, c.g1_deg);
            CHECK(c.samples > 0 && c.not_g1 == 0, "%s: LocalAnalysis G1 fails at %d of %d samples", path, c.not_g1, c.samples);
        } else {
            CHECK(c.g1_deg > 1.0 && c.not_g1 > 0, "%s: kinks seen (%.3g deg, %d non-G1 samples)", path, c.g1_deg, c.not_g1);
        }
        printf("%s: %d faces, G0 %.3g, G1 %.3g deg, pole error %.3g\n", path, nf, c.g0, c.g1_deg, perr);
    }
}

int main()
{
    q2n_mesh *g = em_mesh_grid(4, 3);
    q2n_nurbs_model gm = em_model_bilinear(g);
    check_model("grid", &gm, false, false);
    q2n_mesh *tm, *cm;
    q2n_nurbs_model tr = em_model_torus_rational(3.0, 1.0, &tm);
    check_model("torus_rat", &tr, true, true);
    q2n_nurbs_model cy = em_model_cylinder_rational(2.0, 3.0, 2, &cm);
    check_model("cylinder", &cy, false, true);
    const char *tp = chk_shared_mesh("osd_catmark_torus.obj");
    q2n_mesh *om = tp ? em_mesh_read_obj(tp) : NULL;
    q2n_nurbs_model bm;
    if (tp && (!om || !em_model_bicubic(om, &bm))) CHECK(0, "C2 torus model from %s", tp);
    else if (tp) {
        check_model("torus_c2", &bm, true, true);
        em_model_release(&bm);
    }
    em_mesh_free(om);
    em_model_release(&gm); em_mesh_free(g);
    em_model_release(&tr); em_mesh_free(tm);
    em_model_release(&cy); em_mesh_free(cm);
    CHECK_DONE("ref_export_occt");
}
