/* model.c — the pipeline object (see model.h). */
#include "api/model.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>

#include "api/api_policy.h"
#include "core/outfile.h"
#include "core/vec3.h"
#include "patch/augmented.h"
#include "patch/extraordinary.h"
#include "patch/fairness.h"

void q2n_model_free(q2n_model *m)
{
    if (!m) return;
    q2n_nurbs_model_free(m->nurbs);
    q2n_surface_free(m->surface);
    q2n_mesh_free(m->mesh);
    free(m->edge_iv);
    free(m);
}

/* The augmented surface on m->mesh, or, while m->frame_mesh is set, on that mesh (the same faces in
 * the isotropic frame) and mapped back by m->frame_Ainv; while m->frame_charts is set, on m->mesh
 * with the vertex charts of the extraordinary regions measured on it; while m->frame_regions is set,
 * the regular patches of m->mesh (its intervals) mapped by m->frame_A, the extraordinary regions built
 * on m->frame_regions (the mesh in that frame) against them, and all mapped back. */
static q2n_status build_augmented(q2n_model *m, q2n_error *err)
{
    q2n_augmented_options ao = {m->opt.cls, m->opt.param};
    q2n_extraordinary_options eo = {m->opt.cls, m->opt.param, (q2n_ev_patch_kind)m->opt.ev_patch,
                                    (q2n_ev_method)m->opt.ev_method, m->opt.threads, m->opt.keep_flat,
                                    m->opt.smooth_gluing == Q2N_EV_GLUING_SMOOTHSTEP, NULL, NULL};
    eo.chart_mesh = m->frame_charts;
    eo.smooth_vertices = m->smooth_v;
    const q2n_mesh *bm = m->frame_mesh ? m->frame_mesh : m->mesh;
    q2n_status st = q2n_param_edge_intervals(bm, &m->opt.param, &m->edge_iv, err);
    if (!st) st = q2n_augmented_build(bm, &ao, m->edge_iv, &m->surface, err);
    /* the extraordinary regions in the frame: the mesh's own regular patches (its intervals) seen there */
    if (!st && m->frame_regions) q2n_augmented_map_points(m->surface, m->frame_A);
    /* faces at extraordinary vertices: augmented Coons–Gregory patches (§4) */
    if (!st && q2n_surface_count(m->surface, Q2N_PATCH_UNCOVERED) > 0)
        st = q2n_extraordinary_build_stats(m->frame_regions ? m->frame_regions : bm, &eo, m->edge_iv, m->surface,
                                           &m->ev_stats, err);
    if (!st && (m->frame_mesh || m->frame_regions)) q2n_surface_map_linear(m->surface, m->frame_Ainv);
    int regular = m->opt.cls->k >= 2 ? 2 : 1, ev = q2n_ev_patch_order(&eo);
    m->continuity = (q2n_surface_count(m->surface, Q2N_PATCH_COONS_GREGORY) > 0 && ev < regular) ? ev : regular;
    return st;
}

static void mark_derived(q2n_model *m);

static q2n_status build_acc(q2n_model *m, q2n_error *err)
{
    q2n_acc_options ao = {m->opt.method == Q2N_SURFACE_ACC3 ? Q2N_ACC_3 : Q2N_ACC_G1, m->opt.acc_strategy, 0};
    q2n_acc_info info;
    memset(&info, 0, sizeof info);
    q2n_status st = q2n_acc_build(m->mesh, &ao, &m->surface, &info, err);
    if (st) { q2n_acc_info_free(&info); return st; }
    q2n_acc_describe(&info, &ao, m->note, sizeof m->note);
    if (info.mesh) { /* the patches live on the subdivided mesh: it becomes the model's mesh */
        q2n_mesh_free(m->mesh);
        m->mesh = info.mesh;
        info.mesh = NULL;
        mark_derived(m);
    }
    q2n_acc_info_free(&info);
    /* acc3 is C0 across edges that end at an EV (C2 elsewhere); acc-g1 is G1 everywhere */
    m->continuity = m->opt.method == Q2N_SURFACE_ACC3 ? 0 : 1;
    return Q2N_OK;
}

/* "NAME:LINE: face k" for messages (LINE of the face, or of the input face it was subdivided
 * from), with a note when the mesh is the subdivided one. */
static void face_where(const q2n_model *m, int k, char *buf, size_t n)
{
    const q2n_mesh *me = m->mesh;
    int line = me->face_line ? me->face_line[k] : 0;
    const char *d = me->derived, *pre = d[0] ? " (of the " : "", *post = d[0] ? " mesh)" : ""; /* as q2n_mesh_of */
    if (line > 0) snprintf(buf, n, "%s:%d: face %d%s%s%s", me->name, line, k, pre, d, post);
    else snprintf(buf, n, "%s: face %d%s%s%s", me->name, k, pre, d, post);
}

/* What made the model's mesh, for its messages (q2n_mesh_of): set whenever a step replaces it. */
static void mark_derived(q2n_model *m)
{
    q2n_mesh *me = m->mesh;
    snprintf(me->derived, sizeof me->derived, "%s",
             me->nf != m->taken_faces && m->taken_faces > 0 ? "subdivided"
             : m->paired && m->filled                       ? "paired and filled"
             : m->filled                                    ? "filled"
             : m->paired                                    ? "paired"
                                                            : "");
}

static q2n_status not_finite(const q2n_model *m, int k, double u, double v, const char *what,
                             q2n_error *err)
{
    char where[320];
    face_where(m, k, where, sizeof where);
    return q2n_error_set(err, Q2N_ERR_NUMERIC, "%s: %s is not finite (NaN or Inf) at u %.3g, v %.3g",
                         where, what, u, v);
}

/* The ratio of face f's shortest edge to its longest, and that edge's vertices. */
static double near_triangle(const q2n_mesh *me, int f, int *a, int *b)
{
    int s = me->face_start[f], k = me->face_start[f + 1] - s;
    double lo = INFINITY, hi = 0;
    for (int i = 0; i < k; i++) {
        int v = me->face_vert[s + i], w = me->face_vert[s + (i + 1) % k];
        double len = q2n_v3_dist(q2n_mesh_vpos(me, v), q2n_mesh_vpos(me, w));
        if (len < lo) lo = len, *a = v, *b = w;
        if (len > hi) hi = len;
    }
    return hi > 0 ? lo / hi : 1;
}

/* Every covered patch at the scan grid: finite values (else fail), and folds (counted; the first
 * named in m->warning). */
static q2n_status scan_patches(q2n_model *m, q2n_error *err)
{
    char where[320] = "";
    double fu = 0, fv = 0;
    m->folded = 0;
    m->folded_face = -1;
    for (int k = 0; k < m->mesh->nf; k++) {
        if (q2n_surface_kind(m->surface, k) == Q2N_PATCH_UNCOVERED) continue;
        double area[3], u = 0, v = 0;
        int folded;
        q2n_mesh_face_area(m->mesh, k, area);
        q2n_status st = q2n_surface_scan(m->surface, k, Q2N_MODEL_SCAN_GRID, area, &folded, &u, &v);
        if (st == Q2N_ERR_NUMERIC) return not_finite(m, k, u, v, "the surface", err);
        if (st) {
            face_where(m, k, where, sizeof where);
            return q2n_error_set(err, st, "%s: the surface cannot be evaluated", where);
        }
        if (folded && m->folded++ == 0) face_where(m, k, where, sizeof where), fu = u, fv = v, m->folded_face = k;
    }
    if (m->folded) {
        int len, a = -1, b = -1;
        double ratio = near_triangle(m->mesh, m->folded_face, &a, &b);
        if (ratio < Q2N_MODEL_NEAR_TRIANGLE)
            len = snprintf(m->warning, sizeof m->warning, "%s: the surface folds over (at u %.3g, v %.3g its normal "
                           "points against the face's): the face is nearly a triangle, its edge %d-%d %.2g times its "
                           "longest (collapse that edge, or --limit-points)", where, fu, fv, a, b, ratio);
        else
            len = snprintf(m->warning, sizeof m->warning, "%s: the surface folds over (at u %.3g, "
                           "v %.3g its normal points against the face's: a non-convex or strongly "
                           "warped face?)", where, fu, fv);
        if (m->folded > 1 && len > 0 && (size_t)len < sizeof m->warning)
            len += snprintf(m->warning + len, sizeof m->warning - len, "; %d faces fold in all", m->folded);
        /* a G2 extraordinary patch: the curvature a thin or sharp feature needs across a few faces
         * (docs/extraordinary.md, "Found and not fixed"); G1 patches or more faces there do not fold
         * on most cases measured.  (The control vertices instead of the limit points were offered
         * too until stop 35, on the strength of one skewed spike; with the charts of stop 35 that
         * spike folds through its control vertices and not through its limit points.) */
        if (m->continuity == 2 && q2n_surface_kind(m->surface, m->folded_face) == Q2N_PATCH_COONS_GREGORY && len > 0 &&
            (size_t)len < sizeof m->warning)
            snprintf(m->warning + len, sizeof m->warning - len,
                     "; on a thin or sharp feature G1 patches (--ev-patch g1 --continuity g1) or a finer mesh "
                     "(--subdivide %d) may avoid it", m->opt.subdivide + 1);
    }
    return Q2N_OK;
}

/* A built surface and what its build and scan said, set aside while the model builds another
 * (the fallbacks below keep whichever folds on fewer faces). */
typedef struct built {
    q2n_surface *surface;
    double *edge_iv;
    q2n_extraordinary_stats ev_stats;
    int folded, folded_face, continuity;
    char warning[sizeof ((q2n_model *)0)->warning];
} built;

/* Set m's surface aside into *b (set_aside), and (rebuild) build the augmented surface again with
 * m's (changed) options, then scan it; the status of the second build. */
static void set_aside(const q2n_model *m, built *b)
{
    *b = (built){m->surface, m->edge_iv, m->ev_stats, m->folded, m->folded_face, m->continuity, {0}};
    memcpy(b->warning, m->warning, sizeof b->warning);
}

static q2n_status rebuild(q2n_model *m, built *b)
{
    set_aside(m, b);
    m->surface = NULL;
    m->edge_iv = NULL;
    m->warning[0] = 0;
    q2n_error e1;
    q2n_status st = build_augmented(m, &e1);
    if (!st) st = scan_patches(m, &e1);
    return st;
}

/* Keep the second build (drop the first) or go back to the first. */
static void keep_second(built *b)
{
    q2n_surface_free(b->surface);
    free(b->edge_iv);
}

static void keep_first(q2n_model *m, built *b)
{
    q2n_surface_free(m->surface);
    free(m->edge_iv);
    m->surface = b->surface;
    m->edge_iv = b->edge_iv;
    m->ev_stats = b->ev_stats;
    m->folded = b->folded;
    m->folded_face = b->folded_face;
    m->continuity = b->continuity;
    memcpy(m->warning, b->warning, sizeof m->warning);
}

/* Patches glued by polynomials (ev_fair_gluing.c; G2 ones also ev_fair_gluing2.c) whose surface folds over: the extraordinary
 * regions are built again with the smoothsteps and kept if they fold on fewer faces.  The gluing's
 * twist corrections are fixed before the energy solve, which the fold guard cannot undo, and on a
 * thin plate they turned four faces over where the smoothsteps turn none (docs/extraordinary.md,
 * "Polynomial gluing of G1 patches").  An error of the second build keeps the first. */
static void gluing_fallback(q2n_model *m)
{
    if (m->opt.smooth_gluing == Q2N_EV_GLUING_SMOOTHSTEP || m->folded == 0 || m->ev_stats.polynomial_edges == 0) return;
    built b;
    int given = m->opt.smooth_gluing;
    m->opt.smooth_gluing = Q2N_EV_GLUING_SMOOTHSTEP;
    q2n_status st = rebuild(m, &b);
    m->opt.smooth_gluing = given;
    if (!st && m->folded < b.folded) {
        char where[320];
        face_where(m, b.folded_face, where, sizeof where);
        keep_second(&b);
        q2n_model_warn(m, "%s: G%d patches glued by polynomials fold over there (on %d faces in all); glued by smoothsteps "
                       "instead (%d faces fold; least squares across their edges in the fit)", where, m->continuity, b.folded,
                       m->folded);
        return;
    }
    keep_first(m, &b);
}

/* G2 patches at extraordinary vertices fold over on a thin or sharp feature: the curvature a G2
 * surface must carry across a few faces there (docs/extraordinary.md, "Found and not fixed").  With
 * opt.fold_fallback the extraordinary regions are built again with G1 patches, which need no
 * curvature continuity there, and kept if they fold on fewer faces (the construction's continuity
 * becomes G1, and the warnings say so); else the G2 surface stays.  An error of the second build
 * keeps the first. */
static void fold_fallback(q2n_model *m)
{
    if (!m->opt.fold_fallback || m->opt.method != Q2N_SURFACE_AUGMENTED || m->opt.ev_patch != Q2N_EV_PATCH_DEFAULT ||
        m->continuity != 2 || m->folded == 0 || q2n_surface_kind(m->surface, m->folded_face) != Q2N_PATCH_COONS_GREGORY)
        return;
    built b;
    m->opt.ev_patch = Q2N_EV_PATCH_G1;
    q2n_status st = rebuild(m, &b);
    if (!st) gluing_fallback(m);
    if (!st && m->folded < b.folded) {
        char where[320];
        face_where(m, b.folded_face, where, sizeof where);
        keep_second(&b);
        m->g2_folded = b.folded;
        q2n_model_warn(m, "%s: G2 patches at the extraordinary vertices fold over there (on %d faces in all: a thin "
                       "or sharp feature); built with G1 patches at every extraordinary vertex instead (%d faces fold), "
                       "G1 across their edges (--ev-patch g2 keeps the G2 surface)", where, b.folded, m->folded);
        return;
    }
    /* no better, or the second build failed: the first surface as it was */
    keep_first(m, &b);
    m->opt.ev_patch = Q2N_EV_PATCH_DEFAULT;
}

/* The augmented surface with its fallbacks, as q2n_model_construct builds it. */
static q2n_status build_checked(q2n_model *m, q2n_error *err)
{
    q2n_status st = build_augmented(m, err);
    if (!st) st = scan_patches(m, err);
    if (!st) gluing_fallback(m);
    if (!st) fold_fallback(m);
    return st;
}

/* The isotropic frame (docs/extraordinary.md): the construction measures lengths and angles, so a
 * mesh stretched along an axis — a model scaled in one direction — gets charts and fits of faces that
 * are not the shapes its vertices describe, and ripples or folds where the same mesh built unstretched
 * and mapped along does not.  Where the mesh's faces are stretched by more than
 * Q2N_MODEL_FRAME_MIN_STRETCH on the whole (q2n_mesh_isotropic_frame), the surface is built again on
 * the mesh mapped into its isotropic frame and mapped back (exact: affine maps keep the
 * interpolation, G1 and G2); where that build is not kept, once more with only the extraordinary
 * regions' vertex charts measured in that frame (until stop 54 only where the first build's regions
 * rippled less: since the G2 patches are glued by polynomials a build in the frame can ripple more on
 * the whole and its charts still help, a shared mesh stretched 3 x kept the charts' build at stop 53 and
 * lost it with the gluing), and, where its extraordinary regions ripple less (the regular patches, built
 * from the mesh alone, are what got worse), once more with those regions built
 * in that frame — against the mesh's own regular patches mapped into it, which a linear map carries
 * exactly (they are linear in their points for given intervals) —, kept where it beats the best build
 * so far (the charts' where that was kept).  A build is kept only
 * where it is the better surface by issue 11's figures, measured on the construction (patch/fairness.h): less
 * diagonal ripple, no more bending energy, no more folded faces, no lower continuity (G2 patches
 * that fold in one frame and not in the other), and, with the same kind of patches, no fewer edges
 * glued exactly by polynomials (G1 patches).  A mesh whose faces are long by design (tubes, rims)
 * also gets an estimate; there the comparison decides.  A build that fails keeps the first. */
typedef struct frame_trial {
    built b;              /* the build to beat (the first, or the best kept since), set aside */
    q2n_fairness f0;      /* its figures */
    int ev_patch, gluing, g2_folded, nw0, nw;
} frame_trial;

/* Build again (m->frame_mesh or m->frame_charts set by the caller) and keep the new build if it is
 * better than the first (above); its figures into *f; 1 when kept. */
static int frame_try(q2n_model *m, frame_trial *T, int ev_patch, int smooth_gluing, q2n_fairness *f)
{
    q2n_error e1;
    m->surface = NULL;
    m->edge_iv = NULL;
    m->warning[0] = 0;
    m->g2_folded = 0;
    m->opt.ev_patch = ev_patch;
    m->opt.smooth_gluing = smooth_gluing;
    q2n_status st = build_checked(m, &e1);
    *f = (q2n_fairness){INFINITY, INFINITY, INFINITY};
    if (!st) *f = q2n_surface_fairness(m->surface, Q2N_MODEL_RIPPLE_SAMPLES, Q2N_MODEL_ENERGY_RULE, m->opt.threads);
    int same_patches = m->opt.ev_patch == T->ev_patch; /* the fallbacks took the same turns */
    const built *b = &T->b;
    if (!st && f->ripple < T->f0.ripple && f->energy <= T->f0.energy && m->folded <= b->folded && m->continuity >= b->continuity &&
        (!same_patches || m->ev_stats.polynomial_edges >= b->ev_stats.polynomial_edges)) {
        keep_second(&T->b);
        /* the first build's warnings (its fallbacks') go with it */
        memmove(m->warnings[T->nw0], m->warnings[T->nw], (size_t)(m->nwarnings - T->nw) * sizeof m->warnings[0]);
        m->nwarnings -= T->nw - T->nw0;
        return 1;
    }
    keep_first(m, &T->b); /* back to the first build, its options and warnings */
    m->nwarnings = T->nw;
    m->opt.ev_patch = T->ev_patch;
    m->opt.smooth_gluing = T->gluing;
    m->g2_folded = T->g2_folded;
    return 0;
}

/* A build frame_try kept becomes the one later tries must beat: its figures and its state (the
 * options its fallbacks took, its warnings). */
static void frame_rebase(const q2n_model *m, frame_trial *T, const q2n_fairness *f)
{
    T->f0 = *f;
    T->ev_patch = m->opt.ev_patch;
    T->gluing = m->opt.smooth_gluing;
    T->g2_folded = m->g2_folded;
    T->nw = m->nwarnings;
}

static void frame_choice(q2n_model *m, int ev_patch, int smooth_gluing, int nw0)
{
    /* not on a mesh without extraordinary regions: its regular patches hardly move with the frame (a
     * torus of rectangles 0.797 -> 0.784 per diagonal), and a second build would double its time */
    if (q2n_surface_count(m->surface, Q2N_PATCH_COONS_GREGORY) == 0) return;
    m->frame_stretch = q2n_mesh_isotropic_frame(m->mesh, m->frame_A, m->frame_Ainv);
    if (!(m->frame_stretch >= Q2N_MODEL_FRAME_MIN_STRETCH)) return;
    q2n_error e1;
    q2n_mesh *fm = NULL;
    if (q2n_mesh_mapped(m->mesh, m->frame_A, &fm, &e1)) return;
    frame_trial T = {.ev_patch = m->opt.ev_patch, .gluing = m->opt.smooth_gluing, .g2_folded = m->g2_folded, .nw0 = nw0,
                     .nw = m->nwarnings};
    set_aside(m, &T.b);
    T.f0 = q2n_surface_fairness(T.b.surface, Q2N_MODEL_RIPPLE_SAMPLES, Q2N_MODEL_ENERGY_RULE, m->opt.threads);
    q2n_fairness f[4] = {T.f0, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}}; /* by frame_used: own, isotropic, charts, regions */
    m->frame_mesh = fm; /* the whole construction in the frame */
    m->frame_used = frame_try(m, &T, ev_patch, smooth_gluing, &f[1]) ? 1 : 0;
    m->frame_mesh = NULL;
    if (!m->frame_used) { /* the charts alone in the frame */
        set_aside(m, &T.b);
        m->frame_charts = fm;
        m->frame_used = frame_try(m, &T, ev_patch, smooth_gluing, &f[2]) ? 2 : 0;
        m->frame_charts = NULL;
        if (m->frame_used) frame_rebase(m, &T, &f[2]);
    }
    /* the extraordinary regions in the frame, against the mesh's own regular patches, kept where they
     * beat the best build so far (the charts' build where that was kept) on all counts: with no regular
     * patch (every face extraordinary) this is the build in the frame again (the same figures to 6
     * digits where the shared meshes reach it), so it is not tried */
    if (m->frame_used != 1 && f[1].ripple_ev < f[0].ripple_ev && q2n_surface_count(m->surface, Q2N_PATCH_AUGMENTED) > 0) {
        set_aside(m, &T.b);
        m->frame_regions = fm;
        if (frame_try(m, &T, ev_patch, smooth_gluing, &f[3])) m->frame_used = 3;
        m->frame_regions = NULL;
    }
    q2n_mesh_free(fm);
    const q2n_fairness *fk = &f[m->frame_used];
    for (int i = 0; i < 4; i++) m->frame_ripple[i] = f[i].ripple, m->frame_energy[i] = f[i].energy;
    static const char *how[4] = {"", "in the mesh's isotropic frame", "with the vertex charts of the mesh's isotropic frame",
                                 "with its extraordinary regions in the mesh's isotropic frame"};
    if (m->frame_used && !m->note[0])
        snprintf(m->note, sizeof m->note, "built %s (its faces stretched %.3g : 1 on the whole)%s: "
                 "diagonal ripple %.4g -> %.4g, bending energy %.4g -> %.4g against its own frame (--frame off builds there)",
                 how[m->frame_used], m->frame_stretch, m->frame_used == 2 ? "" : " and mapped back", f[0].ripple, fk->ripple,
                 f[0].energy, fk->energy);
}

/* Does a build of ripple r and energy e beat one of r0, e0: less ripple, and no more energy, both beyond
 * what the figures' quadrature can tell (Q2N_MODEL_GLUING_TIE)? */
static int fairer(double r, double e, double r0, double e0)
{
    return r < r0 * (1 - Q2N_MODEL_GLUING_TIE) && e <= e0 * (1 + Q2N_MODEL_GLUING_TIE);
}

/* The gluing choice (G2 patches, docs/extraordinary.md, "The gluing chosen per region"): the polynomial
 * gluing ripples less than the smoothsteps on most meshes, but not everywhere (a cube: every edge's β
 * changes sign between its ends and the twists it forces are twice its edge vectors).  So the
 * extraordinary regions are built once more with the smoothsteps, in the frame the build kept, and
 * each region — a set of extraordinary faces joined by their corners, whose patches depend on their own
 * vertices' jets and on the regular patches around them only — keeps the gluing that is the fairer
 * there by issue 11's figures on the construction (patch/fairness.h): the smoothsteps where they ripple
 * less and bend no more.  Where some regions but not all change, a third build glues those by
 * smoothsteps (their vertices kept out of the polynomial gluing) and the rest as before.  The build with
 * smoothsteps is kept if it folds on no more faces and is the fairer on the whole as well (the
 * construction's near-fold guard decides on the whole mesh).  A build that fails keeps the first. */
static void gluing_choice(q2n_model *m)
{
    const q2n_mesh *me = m->mesh;
    int nf = me->nf, nv = me->nv;
    if (m->opt.smooth_gluing != Q2N_EV_GLUING_AUTO || m->opt.method != Q2N_SURFACE_AUGMENTED || m->opt.ev_method == Q2N_EV_METHOD_PAPER ||
        m->continuity != 2 || m->ev_stats.polynomial_edges == 0)
        return;
    double (*fa)[2] = malloc(sizeof *fa * (size_t)nf), (*fb)[2] = malloc(sizeof *fb * (size_t)nf);
    double (*cs)[4] = calloc((size_t)nv, sizeof *cs); /* per region (its root vertex): ripple, energy of both */
    int *uf = malloc(sizeof(int) * (size_t)nv);
    char *smooth = calloc((size_t)nv, 1), *evf = calloc((size_t)nf + 1, 1);
    q2n_mesh *fm = NULL;
    q2n_error e1;
    if (!fa || !fb || !cs || !uf || !smooth || !evf || (m->frame_used && q2n_mesh_mapped(me, m->frame_A, &fm, &e1))) goto done;
    q2n_surface_fairness_patches(m->surface, Q2N_MODEL_RIPPLE_SAMPLES, Q2N_MODEL_ENERGY_RULE, m->opt.threads, fa);
    /* the regions: extraordinary faces joined by their corners */
    for (int f = 0; f < nf; f++) evf[f] = q2n_surface_kind(m->surface, f) == Q2N_PATCH_COONS_GREGORY;
    q2n_mesh_corner_regions(me, evf, uf);
    /* the smoothsteps' build, in the frame the build kept */
    built a, b;
    int used = m->frame_used;
    m->frame_mesh = used == 1 ? fm : NULL, m->frame_charts = used == 2 ? fm : NULL, m->frame_regions = used == 3 ? fm : NULL;
    m->opt.smooth_gluing = Q2N_EV_GLUING_SMOOTHSTEP;
    q2n_status st = rebuild(m, &a);
    m->opt.smooth_gluing = Q2N_EV_GLUING_AUTO;
    if (st) { keep_first(m, &a); goto reset; }
    q2n_surface_fairness_patches(m->surface, Q2N_MODEL_RIPPLE_SAMPLES, Q2N_MODEL_ENERGY_RULE, m->opt.threads, fb);
    double tot[2] = {0, 0};
    for (int f = 0; f < nf; f++) { /* evf: every build constructs the same faces */
        if (!evf[f]) continue;
        int r = uf[me->face_vert[me->face_start[f]]];
        cs[r][0] += fa[f][0], cs[r][1] += fa[f][1], cs[r][2] += fb[f][0], cs[r][3] += fb[f][1];
        tot[0] += fa[f][0], tot[1] += fa[f][1];
    }
    int nreg = 0, nsm = 0;
    for (int v = 0; v < nv; v++) {
        if (uf[v] != v || !(cs[v][0] > 0 || cs[v][1] > 0)) continue;
        nreg++;
        if (fairer(cs[v][2], cs[v][3], cs[v][0], cs[v][1])) smooth[v] = 1, nsm++;
    }
    for (int v = 0; v < nv; v++) smooth[v] = smooth[uf[v]];
    m->gluing_regions[0] = nreg;
    double fc[2] = {0, 0}; /* the candidate's extraordinary regions, against the first build's (tot) */
    if (nsm > 0 && nsm < nreg) { /* the mixed build: the chosen regions' vertices out of the polynomial gluing (the
                                    smoothsteps' build dropped first: two surfaces at a time, as the frame choice) */
        set_aside(m, &b);
        keep_second(&b);
        m->surface = NULL, m->edge_iv = NULL;
        m->smooth_v = smooth;
        st = rebuild(m, &b);
        if (!st) q2n_surface_fairness_patches(m->surface, Q2N_MODEL_RIPPLE_SAMPLES, Q2N_MODEL_ENERGY_RULE, m->opt.threads, fb);
    }
    for (int f = 0; !st && nsm > 0 && f < nf; f++)
        if (evf[f]) fc[0] += fb[f][0], fc[1] += fb[f][1];
    /* the regions' jets are solved apart, but the construction's near-fold guard decides on the whole
     * mesh: the mixed build is kept where it is the fairer on the whole too */
    if (nsm > 0 && !st && m->folded <= a.folded && fairer(fc[0], fc[1], tot[0], tot[1])) {
        keep_second(&a);
        m->gluing_regions[1] = nsm;
    } else {
        keep_first(m, &a);
    }
reset:
    m->frame_mesh = NULL, m->frame_charts = m->frame_regions = NULL;
    m->smooth_v = NULL;
done:
    q2n_mesh_free(fm);
    free(fa), free(fb), free(cs), free(uf), free(smooth), free(evf);
}

/* Where the mesh is flat, does the surface stay flat?  A warning with the remedy when it leaves the
 * plane by more than Q2N_MODEL_FLAT_WARN (docs/extraordinary.md, "Flat fans"). */
static void flat_warning(q2n_model *m)
{
    int nflat = 0, face = -1;
    double dev = 0;
    if (q2n_flat_faces_dev(m->mesh, m->surface, Q2N_MODEL_FLAT_GRID, &nflat, &dev, &face) || !(dev > Q2N_MODEL_FLAT_WARN))
        return;
    char where[320];
    face_where(m, face, where, sizeof where);
    const char *why = m->opt.ev_method == Q2N_EV_METHOD_PAPER ? "--keep-flat (with the fair construction) keeps flat regions flat"
                      : m->opt.keep_flat ? "the regular patches reach two rings of the mesh, across the bends, and bulge it "
                                           "(--class D5C2P2S4 keeps them flat)"
                                         : "--keep-flat keeps flat regions flat";
    q2n_model_warn(m, "%s: the mesh is flat there (and on %d faces in all), the surface leaves the plane by %.2g of the "
                   "diagonal; %s", where, nflat, dev, why);
}

/* Triangles about to be split by Catmull–Clark that would pair into convex quads: say so, with the
 * option (a tessellation's quads come back, instead of three needle-prone quads per triangle;
 * docs/mesh.md, "Pairing triangles"). */
static void pair_hint(q2n_model *m, char *hint, size_t n)
{
    int tri = 0, np = q2n_mesh_pair_count(m->mesh, &tri);
    if (np > 0)
        snprintf(hint, n, "%d of its %d triangles pair into convex quads across shared edges; --pair-triangles "
                 "merges them before the Catmull-Clark step (a triangulated quad mesh gets its quads back, and "
                 "fewer, better-shaped faces)", 2 * np, tri);
}

/* Polygons of many sides about to be split by Catmull–Clark into thin kites around a vertex of high
 * valence: say that --fill-ngons fills them without one (docs/mesh.md, "Filling n-gons"; only from
 * Q2N_MODEL_FILL_HINT_SIDES sides on, where it pays). */
static void fill_hint(q2n_model *m, char *hint, size_t n)
{
    int k = q2n_mesh_fill_count(m->mesh, Q2N_MODEL_FILL_HINT_SIDES);
    if (k > 0)
        snprintf(hint, n, "%d of its faces have %d or more sides; --fill-ngons fills them with quads before the "
                 "Catmull-Clark step, which splits each into thin kites around one vertex of high valence", k,
                 Q2N_MODEL_FILL_HINT_SIDES);
}

/* A new model with its options (defaults filled in) and no mesh yet. */
static q2n_status model_new(const q2n_model_options *opt, q2n_model **out, q2n_error *err)
{
    q2n_model *m = calloc(1, sizeof *m);
    if (!m) return q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory");
    if (opt) m->opt = *opt;
    if (!m->opt.cls) m->opt.cls = q2n_spline_class_find(Q2N_SPLINE_CLASS_DEFAULT);
    if (m->opt.scale == 0.0) m->opt.scale = 1.0;
    m->scale_mant = 1.0;
    if (!(m->opt.scale > 0.0 && isfinite(m->opt.scale))) {
        double sc = m->opt.scale;
        free(m);
        return q2n_error_set(err, Q2N_ERR_ARG, "scale %g is not a positive number", sc);
    }
    *out = m;
    return Q2N_OK;
}

/* Take the mesh over and move it into its frame (scale-free numerics: everything is built at
 * diagonal 1 and mapped back on the way out, times --scale); refuse a diagonal whose output
 * would leave the double range; pair triangles into quads when asked (--pair-triangles: the quads a
 * tessellator cut in two, back, before subdivision and before the resource estimate). */
static q2n_status model_take_mesh(q2n_model *m, q2n_mesh *mesh, q2n_error *err)
{
    m->mesh = mesh;
    m->input_faces = mesh->nf;
    q2n_mesh_normalize(m->mesh, m->origin, &m->scale_mant, &m->scale_exp);
    double mant = m->scale_mant * m->opt.scale;
    int e = m->scale_exp;
    if (ldexp(mant, e - Q2N_MODEL_MAX_DIAG_LOG2) >= 1.0)
        return q2n_error_set(err, Q2N_ERR_UNSUPPORTED, "%s: the bounding box is too large (diagonal "
                             "%.3g%s, limit 2^%d = %.3g): derivatives and differences of the surface "
                             "would overflow a double; scale the mesh down", m->mesh->name, ldexp(mant, e),
                             m->opt.scale != 1.0 ? " after --scale" : "", Q2N_MODEL_MAX_DIAG_LOG2,
                             ldexp(1.0, Q2N_MODEL_MAX_DIAG_LOG2));
    for (int c = 0; c < 3; c++)
        if (!isfinite(m->origin[c] * m->opt.scale))
            return q2n_error_set(err, Q2N_ERR_ARG, "%s: the mesh's centre %g times scale %g overflows", m->mesh->name,
                                 m->origin[c], m->opt.scale);
    if (m->opt.pair_triangles) { /* here, so that the resource estimate sees the paired mesh */
        q2n_mesh *pm = NULL;
        q2n_status st = q2n_mesh_pair_triangles(m->mesh, &pm, &m->paired, &m->tri_left, err);
        if (st) return st;
        q2n_mesh_free(m->mesh);
        m->mesh = pm;
    }
    if (m->opt.fill_ngons) { /* after pairing (triangles are not filled), before the estimate */
        q2n_mesh *fm = NULL;
        q2n_status st = q2n_mesh_fill_ngons(m->mesh, &fm, &m->filled, &m->fill_quads, err);
        if (st) return st;
        q2n_mesh_free(m->mesh);
        m->mesh = fm;
    }
    m->taken_faces = m->mesh->nf;
    mark_derived(m);
    return Q2N_OK;
}

void q2n_model_warn(q2n_model *m, const char *fmt, ...)
{
    if (m->nwarnings >= Q2N_MODEL_MAX_WARNINGS) return;
    char raw[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(raw, sizeof raw, fmt, ap);
    va_end(ap);
    q2n_escape(m->warnings[m->nwarnings++], sizeof m->warnings[0], raw);
}

double q2n_model_length_scale(const q2n_model *m)
{
    return ldexp(m->scale_mant * m->opt.scale, m->scale_exp);
}

q2n_status q2n_model_read(const char *mesh_path, const q2n_model_options *opt, q2n_model **out, q2n_error *err)
{
    q2n_model *m = NULL;
    q2n_status st = model_new(opt, &m, err);
    if (st) return st;
    double t0 = q2n_now();
    q2n_progress_emit(&m->opt.progress, "read", mesh_path, 0, 0);
    q2n_mesh *mesh = NULL;
    st = q2n_mesh_read(mesh_path, &mesh, &m->read_info, err);
    if (!st) st = model_take_mesh(m, mesh, err);
    else q2n_mesh_free(mesh);
    m->t_read = q2n_now() - t0;
    if (st) { q2n_model_free(m); return st; }
    const q2n_mesh_read_info *ri = &m->read_info;
    if (ri->tags)
        q2n_model_warn(m, "%s:%ld: %ld OpenSubdiv tag line%s ignored (%s): sharp features are not supported yet",
                       mesh_path, ri->tag_line, ri->tags, ri->tags == 1 ? "" : "s", ri->tag_names[0] ? ri->tag_names : "t");
    *out = m;
    return Q2N_OK;
}

/* The augmented construction's extraordinary patches handle vertices of valence up to
 * Q2N_EV_MAX_VALENCE, and interior vertices of at least 3 faces (two faces sharing two edges at an
 * interior vertex have no tangent plane there to interpolate): others are refused here, with the line
 * of a face at the vertex. */
static q2n_status check_valence(const q2n_model *m, q2n_error *err)
{
    const q2n_mesh *me = m->mesh;
    for (int v = 0; v < me->nv; v++) {
        int low = !me->vert_boundary[v] && me->valence[v] < 3 && me->valence[v] > 0;
        if (me->valence[v] <= Q2N_EV_MAX_VALENCE && !low) continue;
        char where[300], of[48];
        q2n_mesh_vertex_where(me, v, where, sizeof where);
        q2n_mesh_of(me, 0, of, sizeof of);
        if (low)
            return q2n_error_set(err, Q2N_ERR_TOPOLOGY,
                                 "%s: vertex %d (of this face%s) is an interior vertex of only %d faces: they share two "
                                 "edges there and leave no tangent plane to interpolate (merge them into one face)",
                                 where, v, of, me->valence[v]);
        return q2n_error_set(err, Q2N_ERR_UNSUPPORTED,
                             "%s: vertex %d (of this face%s) has valence %d; the augmented construction handles at "
                             "most %d (--surface acc3 or acc-g1 have no limit)", where, v, of, me->valence[v],
                             Q2N_EV_MAX_VALENCE);
    }
    return Q2N_OK;
}

q2n_status q2n_model_construct(q2n_model *m, q2n_error *err)
{
    double t0 = q2n_now();
    q2n_status st = Q2N_OK;
    /* remedies for faces Catmull–Clark is about to split (--pair-triangles and --fill-ngons act as
     * the mesh is taken over): warnings, or part of the error message when the run fails */
    char pair_note[320] = "", fill_note[320] = "";
    const char *hint[2] = {pair_note, fill_note};
    if (!m->opt.pair_triangles && !m->mesh->all_quads &&
        (m->opt.subdivide > 0 || m->opt.method != Q2N_SURFACE_AUGMENTED)) /* the ACC path subdivides non-quads itself */
        pair_hint(m, pair_note, sizeof pair_note);
    if (!m->opt.fill_ngons && !m->mesh->all_quads && m->opt.subdivide > 0 && m->opt.method == Q2N_SURFACE_AUGMENTED)
        fill_hint(m, fill_note, sizeof fill_note);
    if (m->opt.subdivide > 0) {
        q2n_progress_emit(&m->opt.progress, "subdivide", NULL, 0, m->opt.subdivide);
        q2n_mesh *sub = NULL;
        st = q2n_mesh_subdivide(m->mesh, m->opt.subdivide, &sub, err);
        if (!st) { q2n_mesh_free(m->mesh); m->mesh = sub; mark_derived(m); }
    }
    if (!st && !m->mesh->all_quads && m->opt.method == Q2N_SURFACE_AUGMENTED) {
        int f = 0;
        while (f < m->mesh->nf && q2n_face_size(m->mesh, f) == 4) f++;
        char where[320];
        face_where(m, f, where, sizeof where);
        int n = q2n_face_size(m->mesh, f);
        st = q2n_error_set(err, Q2N_ERR_UNSUPPORTED,
                           "%s has %d vertices; only quad meshes are supported "
                           "(use --subdivide 1 to apply one Catmull-Clark step first%s)",
                           where, n,
                           n == 3 && !m->opt.pair_triangles ? ", or --pair-triangles to merge triangles into quads"
                           : n >= 5 && !m->opt.fill_ngons   ? ", or --fill-ngons to fill polygons of 5 or more sides with quads"
                           : n >= 5 && n % 2                ? "; --fill-ngons pairs an odd polygon with another along a "
                                                              "strip of quads, and found none free for this one"
                                                            : "");
    }
    /* limit points (after --subdivide unless --no-limit-points; --limit-points also without): the
     * vertices onto the subdivision surface.  The control vertices of a coarse mesh lie off it,
     * alternately inside and outside, and an interpolant of them ripples where it does not
     * (docs/mesh.md, "Limit points").  The ACC surfaces approximate it from the control mesh itself. */
    int limit = m->opt.limit_points > 0 || (m->opt.limit_points == 0 && m->opt.subdivide > 0);
    if (!st && limit && m->opt.method == Q2N_SURFACE_AUGMENTED) {
        q2n_mesh *lim = NULL;
        st = q2n_mesh_limit_points(m->mesh, &lim, err);
        if (!st) {
            double d = 0, diag = q2n_mesh_bbox_diag(m->mesh);
            for (int v = 0; v < lim->nv; v++)
                d = fmax(d, q2n_v3_dist(q2n_mesh_vpos(lim, v), q2n_mesh_vpos(m->mesh, v)));
            m->moved_rel = diag > 0 ? d / diag : 0;
            q2n_mesh_free(m->mesh);
            m->mesh = lim;
            mark_derived(m);
        }
    }
    /* an interpolating patch follows its quad's sides: a bow-tie's would cross (Catmull–Clark
     * control faces may be bow-ties: the ACC path and --subdivide take them) */
    if (!st && m->opt.method == Q2N_SURFACE_AUGMENTED) st = q2n_mesh_check_crossing(m->mesh, err);
    if (!st && m->opt.method == Q2N_SURFACE_AUGMENTED) st = check_valence(m, err);
    m->t_read += q2n_now() - t0;
    t0 = q2n_now();
    if (!st) q2n_progress_emit(&m->opt.progress, "build", NULL, 0, m->mesh->nf);
    int ev_patch = m->opt.ev_patch, smooth_gluing = m->opt.smooth_gluing, nw = m->nwarnings;
    int aug = m->opt.method == Q2N_SURFACE_AUGMENTED;
    if (!st) st = aug ? build_checked(m, err) : build_acc(m, err);
    if (!st && !aug) st = scan_patches(m, err);
    if (!st && aug && m->opt.frame >= 0) frame_choice(m, ev_patch, smooth_gluing, nw);
    if (!st && aug) gluing_choice(m);
    for (int k = 0; k < 2; k++) { /* a failure is often the split faces' (needles, bow-ties) */
        const char *h = hint[k];
        size_t l = st ? strlen(err->message) : 0;
        if (!h[0]) continue;
        if (!st) q2n_model_warn(m, "%s: %s", m->mesh->name, h);
        else if (l + 4 < sizeof err->message) snprintf(err->message + l, sizeof err->message - l, "; %s", h);
    }
    if (st) return st;
    m->uncovered = q2n_surface_count(m->surface, Q2N_PATCH_UNCOVERED);
    m->t_build = q2n_now() - t0;
    if (m->warning[0]) q2n_model_warn(m, "%s", m->warning);
    if (m->opt.method == Q2N_SURFACE_AUGMENTED && !m->uncovered) flat_warning(m);
    if (m->uncovered)
        q2n_model_warn(m, "%d of %d faces are in extraordinary regions that the regular construction does not cover; "
                       "they are left out of the output", m->uncovered, m->mesh->nf);
    q2n_progress_emit(&m->opt.progress, "build", NULL, m->mesh->nf, m->mesh->nf);
    return Q2N_OK;
}

q2n_status q2n_model_build(const char *mesh_path, const q2n_model_options *opt, q2n_model **out,
                           q2n_error *err)
{
    q2n_model *m = NULL;
    q2n_status st = q2n_model_read(mesh_path, opt, &m, err);
    if (!st && (st = q2n_model_construct(m, err))) q2n_model_free(m);
    if (!st) *out = m;
    return st;
}

q2n_status q2n_model_take_mesh(q2n_mesh *mesh, const q2n_model_options *opt, q2n_model **out, q2n_error *err)
{
    q2n_model *m = NULL;
    q2n_status st = model_new(opt, &m, err);
    if (st) { q2n_mesh_free(mesh); return st; }
    if ((st = model_take_mesh(m, mesh, err))) {
        q2n_model_free(m);
        return st;
    }
    *out = m;
    return Q2N_OK;
}

q2n_status q2n_model_build_mesh(q2n_mesh *mesh, const q2n_model_options *opt, q2n_model **out,
                                q2n_error *err)
{
    q2n_model *m = NULL;
    q2n_status st = q2n_model_take_mesh(mesh, opt, &m, err);
    if (!st && (st = q2n_model_construct(m, err))) q2n_model_free(m);
    if (!st) *out = m;
    return st;
}

/* Output coordinates of an internal point x: scale * (origin + 2^exp * (mant * x)); of a
 * derivative d: scale * 2^exp * (mant * d). */
static double out_point(const q2n_model *m, int c, double x)
{
    return m->opt.scale * (m->origin[c] + ldexp(x * m->scale_mant, m->scale_exp));
}
static double out_vector(const q2n_model *m, double d)
{
    return ldexp(d * m->scale_mant * m->opt.scale, m->scale_exp);
}

void q2n_model_map_points(const q2n_model *m, double *e, size_t n)
{
    for (size_t p = 0; p < n; p++, e += 9)
        for (int c = 0; c < 3; c++) {
            e[c] = out_point(m, c, e[c]);
            e[3 + c] = out_vector(m, e[3 + c]);
            e[6 + c] = out_vector(m, e[6 + c]);
        }
}

/* The fitted model in output coordinates (control points of the patches and of the shared edge
 * curves, the tolerance; knots do not change under an affine map); fails naming the face when a
 * value leaves the double range. */
static q2n_status map_nurbs(q2n_model *m, q2n_error *err)
{
    q2n_nurbs_model *md = m->nurbs;
    md->tol_abs = out_vector(m, md->tol_abs);
    for (int k = 0; k < md->n; k++) {
        q2n_bspline_surface *p = &md->patches[k];
        size_t n = (size_t)p->ncp_u * p->ncp_v;
        for (size_t i = 0; i < n; i++)
            for (int c = 0; c < 3; c++) {
                double *x = &p->cp[3 * i + c];
                *x = out_point(m, c, *x);
                if (!isfinite(*x))
                    return not_finite(m, k, (double)(i % (size_t)p->ncp_u) / (p->ncp_u - 1),
                                      (double)(i / (size_t)p->ncp_u) / (p->ncp_v - 1),
                                      "a fitted control point (near the position shown)", err);
            }
    }
    for (int e = 0; md->edges && e < m->mesh->ne; e++) {
        q2n_bspline_curve *cv = &md->edges[e];
        for (size_t i = 0; i < 3 * (size_t)cv->ncp; i++) cv->cp[i] = out_point(m, (int)(i % 3), cv->cp[i]);
    }
    return Q2N_OK;
}

/* The first edge of the mesh (face order) shorter than tol (internal frame), as "FILE:LINE: face F
 * has an edge V-W of length L (R of the bounding-box diagonal)" in buf; 0 when there is none.  A fit
 * that misses its tolerance says so first: such an edge makes a nearly degenerate face, whose
 * patch spikes at that corner (a torus with one edge 1e-5 of the others: "the construction is not
 * smooth there"), and the remedy is the mesh's.  Not refused before the fit: at a loose tolerance
 * a dense mesh has such edges, the fit meets it, and OCCT imports the file as it is (docs/mesh.md,
 * "Errors"). */
static int short_edge(const q2n_model *m, double tol, char *buf, size_t n)
{
    const q2n_mesh *me = m->mesh;
    double diag = q2n_mesh_bbox_diag(me), scale = q2n_model_length_scale(m);
    for (int f = 0; f < me->nf; f++) {
        int s = me->face_start[f], k = me->face_start[f + 1] - s;
        for (int i = 0; i < k; i++) {
            int v = me->face_vert[s + i], w = me->face_vert[s + (i + 1) % k];
            double len = q2n_v3_dist(q2n_mesh_vpos(me, v), q2n_mesh_vpos(me, w)); /* diagonal ~1 here */
            if (!(len < tol)) continue;
            char where[320];
            face_where(m, f, where, sizeof where);
            snprintf(buf, n, "%s has an edge %d-%d of length %.3g (%.2g of the bounding-box diagonal)", where, v, w,
                     len * scale, len / diag);
            return 1;
        }
    }
    return 0;
}

q2n_status q2n_model_fit(q2n_model *m, const q2n_fit_options *fopt, q2n_error *err)
{
    q2n_fit_options o;
    if (fopt) o = *fopt;
    else q2n_fit_options_default(&o);
    if (o.tol_abs > 0) o.tol_abs /= q2n_model_length_scale(m); /* output units -> the internal frame */
    if (o.continuity == 0) o.continuity = m->continuity >= 2 ? 2 : 1;
    if (m->uncovered)
        return q2n_error_set(err, Q2N_ERR_UNSUPPORTED,
                             "fit: %d faces are not covered by a patch; cannot fit an incomplete surface",
                             m->uncovered);
    if (!o.progress && m->opt.progress.fn) o.progress = &m->opt.progress;
    double t0 = q2n_now();
    q2n_nurbs_model_free(m->nurbs);
    m->nurbs = NULL;
    q2n_status st = q2n_fit_surface(m->surface, m->mesh, &o, &m->nurbs, &m->fit, err);
    m->fit.folded_faces = m->folded; /* the construction's scan, for the report */
    m->fit.vertices_moved_rel = m->moved_rel;
    m->fit.flat_vertices = m->ev_stats.flat_vertices;
    m->fit.polynomial_edges = m->ev_stats.polynomial_edges;
    m->fit.gluing_regions = m->gluing_regions[0], m->fit.smoothstep_regions = m->gluing_regions[1];
    m->fit.g2_folded_faces = m->g2_folded;
    m->fit.paired_quads = m->paired;
    m->fit.triangles_left = m->tri_left;
    m->fit.filled_faces = m->filled;
    m->fit.fill_quads = m->fill_quads;
    m->fit.frame_stretch = m->frame_stretch;
    m->fit.frame_used = m->frame_used;
    memcpy(m->fit.frame_ripple, m->frame_ripple, sizeof m->frame_ripple);
    memcpy(m->fit.frame_energy, m->frame_energy, sizeof m->frame_energy);
    m->fit.folded_face = m->folded_face;
    if (!st && m->g2_folded && !m->fit.note[0]) /* the report says so as well as the warning (-q hides that) */
        snprintf(m->fit.note, sizeof m->fit.note,
                 "G2 patches folded over on %d faces (a thin or sharp feature): built with G1 patches at the "
                 "extraordinary vertices, G1 across their edges, G2 not imposed (--ev-patch g2 keeps G2)",
                 m->g2_folded);
    if (m->nurbs) { /* into output coordinates; relative figures stay */
        q2n_error e2;
        q2n_status st2 = map_nurbs(m, &e2);
        if (st2) {
            q2n_nurbs_model_free(m->nurbs);
            m->nurbs = NULL;
            if (err) *err = e2;
            st = st2;
        }
    }
    m->fit.diag = out_vector(m, m->fit.diag);
    m->fit.tol_abs = out_vector(m, m->fit.tol_abs);
    m->t_fit = q2n_now() - t0;
    if (!st && (!m->fit.g1_met || !m->fit.g2_met)) {
        char g2[32] = ""; /* a G1 fit imposes no curvature target */
        if (m->fit.continuity == 2) snprintf(g2, sizeof g2, ", G2 %.3g", m->fit.g2_max_rel);
        q2n_model_warn(m, "continuity target not met: %s (max G1 %.3g deg%s)", m->fit.note[0] ? m->fit.note : "see the report",
                       m->fit.g1_max_deg, g2);
    }
    char se[400];
    double tol_in = st == Q2N_ERR_GEOMETRY ? (o.tol_abs > 0 ? o.tol_abs : o.tol * q2n_mesh_bbox_diag(m->mesh)) : 0;
    if (st == Q2N_ERR_GEOMETRY && err && m->opt.method == Q2N_SURFACE_AUGMENTED && short_edge(m, tol_in, se, sizeof se)) {
        char msg[sizeof err->message];
        snprintf(msg, sizeof msg, "%s", err->message);
        q2n_error_set(err, st, "fit: %s, shorter than the fit tolerance %.3g: its face is nearly degenerate (collapse "
                      "the edge; --subdivide 1 smooths the mesh first); then %s", se, tol_in * q2n_model_length_scale(m),
                      strncmp(msg, "fit: ", 5) ? msg : msg + 5);
    }
    if (st && err && strncmp(err->message, "fit: ", 5) != 0) { /* every fit message says where it comes from */
        char msg[sizeof err->message];
        snprintf(msg, sizeof msg, "%s", err->message);
        q2n_error_set(err, st, "fit: %s", msg);
    }
    return st;
}

static double *grid_params(int n)
{
    double *t = malloc((size_t)n * sizeof *t);
    if (t)
        for (int i = 0; i < n; i++) t[i] = n == 1 ? 0.5 : (double)i / (n - 1);
    return t;
}

/* Patch k on the n x n grid t x t, in output coordinates, every value finite (else
 * Q2N_ERR_NUMERIC naming the face, its line and the point); unit normals into nrm (3 a point)
 * unless NULL, from the internal derivatives (the direction does not change under the map, and
 * Su x Sv of a part of size 1e200 would overflow). */
static q2n_status eval_patch_grid(const q2n_model *m, int k, int n, const double *t, double *buf,
                                  double *nrm, q2n_error *err)
{
    q2n_status st = q2n_surface_eval_grid(m->surface, k, n, t, n, t, buf);
    for (int p = 0; !st && nrm && p < n * n; p++) {
        double *c = nrm + 3 * p, len;
        q2n_v3_cross(c, buf + 9 * p + 3, buf + 9 * p + 6);
        if ((len = q2n_v3_norm(c)) > 0) q2n_v3_scale(c, 1 / len, c);
    }
    if (!st) q2n_model_map_points(m, buf, (size_t)n * n);
    int bad = st && st != Q2N_ERR_NUMERIC ? -1 : q2n_surface_first_nonfinite(buf, n * n);
    if (bad >= 0) return not_finite(m, k, t[bad % n], t[bad / n], "the surface", err);
    if (st) {
        char where[320];
        face_where(m, k, where, sizeof where);
        return q2n_error_set(err, st, "%s: the surface cannot be evaluated", where);
    }
    return Q2N_OK;
}

q2n_status q2n_model_eval(const q2n_model *m, int k, double u, double v, double out[9], q2n_error *err)
{
    if (k < 0 || k >= m->mesh->nf || q2n_surface_kind(m->surface, k) == Q2N_PATCH_UNCOVERED)
        return q2n_error_set(err, Q2N_ERR_ARG, "patch %d does not exist or is not covered", k);
    q2n_status st = q2n_surface_eval(m->surface, k, u, v, 1, out);
    if (!st) q2n_model_map_points(m, out, 1);
    if (st == Q2N_ERR_NUMERIC || (!st && q2n_surface_first_nonfinite(out, 1) >= 0))
        return not_finite(m, k, u, v, "the surface", err);
    if (st) return q2n_error_set(err, st, "patch %d: evaluation failed at u %g, v %g", k, u, v);
    return Q2N_OK;
}

q2n_status q2n_model_write_tessellation(const q2n_model *m, int n, const char *path, q2n_error *err)
{
    q2n_outfile of;
    q2n_status st = q2n_outfile_open(&of, path, err);
    if (st) return st;
    if ((st = q2n_model_write_tessellation_file(m, n, of.f, err))) {
        q2n_outfile_abort(&of);
        return st;
    }
    return q2n_outfile_commit(&of, err);
}

q2n_status q2n_model_write_tessellation_file(const q2n_model *m, int n, FILE *f, q2n_error *err)
{
    q2n_status st = Q2N_OK;
    double *t = grid_params(n), *buf = malloc(9 * (size_t)n * n * sizeof *buf);
    double *nrm = malloc(3 * (size_t)n * n * sizeof *nrm);
    if (!t || !buf || !nrm) {
        free(t); free(buf); free(nrm);
        return q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (tessellation)");
    }
    char name[sizeof m->mesh->name * 4];
    q2n_escape(name, sizeof name, m->mesh->name); /* a file name is not allowed to end the comment line */
    fprintf(f, "# quad2nurbs tessellation of %s: %d x %d points per patch\n", name, n, n);
    long base = 1;
    for (int k = 0; k < m->mesh->nf; k++) {
        if (k % 256 == 0) q2n_progress_emit(&m->opt.progress, "write", "tessellation", k, m->mesh->nf);
        if (q2n_surface_kind(m->surface, k) == Q2N_PATCH_UNCOVERED) continue;
        if ((st = eval_patch_grid(m, k, n, t, buf, nrm, err))) break;
        fprintf(f, "g patch_%d\n", k);
        for (int p = 0; p < n * n; p++) {
            const double *e = buf + 9 * p, *nv = nrm + 3 * p;
            fprintf(f, "v %.17g %.17g %.17g\nvn %.9g %.9g %.9g\n", e[0], e[1], e[2], nv[0], nv[1], nv[2]);
        }
        for (int j = 0; j + 1 < n; j++)
            for (int i = 0; i + 1 < n; i++) {
                long a = base + j * n + i, b = a + 1, c = a + n + 1, d = a + n;
                fprintf(f, "f %ld//%ld %ld//%ld %ld//%ld %ld//%ld\n", a, a, b, b, c, c, d, d);
            }
        base += (long)n * n;
    }
    free(t);
    free(buf);
    free(nrm);
    return st;
}

q2n_status q2n_model_write_samples(const q2n_model *m, int n, FILE *out, q2n_error *err)
{
    double *t = grid_params(n), *buf = malloc(9 * (size_t)n * n * sizeof *buf);
    q2n_status st = Q2N_OK;
    if (!t || !buf) {
        free(t); free(buf);
        return q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (samples)");
    }
    for (int k = 0; k < m->mesh->nf && !st; k++) {
        if (q2n_surface_kind(m->surface, k) == Q2N_PATCH_UNCOVERED) continue;
        if ((st = eval_patch_grid(m, k, n, t, buf, NULL, err))) break;
        for (int j = 0; j < n; j++)
            for (int i = 0; i < n; i++) {
                const double *e = buf + 9 * ((size_t)j * n + i);
                fprintf(out, "%d %.17g %.17g", k, t[i], t[j]);
                for (int c = 0; c < 9; c++) fprintf(out, " %.17g", e[c]);
                fputc('\n', out);
            }
    }
    free(t);
    free(buf);
    if (!st && ferror(out)) st = q2n_error_set(err, Q2N_ERR_IO, "error writing samples");
    return st;
}
