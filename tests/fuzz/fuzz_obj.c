/* fuzz_obj.c — fuzz harness: the OBJ reader and the mesh stage.
 *
 * Parse the input; a failure must be a clean status.  An accepted mesh must pass
 * q2n_mesh_check, have finite coordinates and a frame; one Catmull–Clark step, the ribbons,
 * section continuation, normalisation and the bow-tie check must then each succeed or fail
 * cleanly, and whatever they produce must be valid again.
 *   libFuzzer:  make fuzz && build/fuzz/fuzz_obj -dict=tests/fuzz/obj.dict CORPUS
 *   replayed:   tests/test_fuzz_corpus.c (make check) over the seeds of make_corpus.sh */
#include "fuzz_common.h"
#include "mesh/mesh.h"
#include "mesh/mesh_policy.h"

/* Caps that keep one input fast (a fuzzer wants thousands per second). */
#define FZ_OBJ_MAX_SUBDIVIDE_HE 4096

static int fz_mesh_valid(const q2n_mesh *m)
{
    q2n_error err;
    if (q2n_mesh_check(m, &err) != Q2N_OK) return 0;
    for (int h = 0; h < m->nh; h++)
        if (!fz_all_finite(q2n_mesh_vpos(m, m->face_vert[h]), 3)) return 0;
    return 1;
}

int q2n_fuzz_obj(const uint8_t *data, size_t size)
{
    q2n_mesh *m = (q2n_mesh *)&m, *s = NULL;
    q2n_error err = {Q2N_OK, ""};
    { /* the same bytes as STL (binary when the size fits a facet count, else ASCII) */
        q2n_mesh *sm = NULL;
        q2n_error se = {Q2N_OK, ""};
        q2n_status ss = q2n_mesh_parse_stl((const char *)data, size, FZ_NAME, &sm, &se);
        if (ss) FZ_REQUIRE(fz_clean_error(ss, &se) && !sm, se.message);
        else FZ_REQUIRE(sm && fz_mesh_valid(sm), "STL mesh is valid");
        q2n_mesh_free(sm);
    }
    q2n_status st = q2n_mesh_parse_obj((const char *)data, size, FZ_NAME, &m, &err);
    if (st) {
        FZ_REQUIRE(fz_clean_error(st, &err), err.message);
        FZ_REQUIRE(m == NULL, "no mesh on failure");
        return 0;
    }
    FZ_REQUIRE(m != NULL && fz_mesh_valid(m), "accepted mesh is valid");
    double c[3], mant;
    int e;
    q2n_mesh_frame(m, c, &mant, &e);
    FZ_REQUIRE(fz_all_finite(c, 3) && mant >= 1.0 && mant < 3.47, "frame");

    if (m->nh <= FZ_OBJ_MAX_SUBDIVIDE_HE) {
        st = q2n_mesh_subdivide(m, 1, &s, &err);
        if (st) FZ_REQUIRE(fz_clean_error(st, &err) && !s, err.message);
        else FZ_REQUIRE(s && s->all_quads && fz_mesh_valid(s) && s->nf == m->nh, "subdivided mesh");
        q2n_mesh_free(s);
    }
    { /* --pair-triangles: a valid mesh, each pair two triangles fewer and one quad more */
        int np = -1, left = -1, tri = 0, quads = 0, pquads = 0;
        st = q2n_mesh_pair_triangles(m, &s, &np, &left, &err);
        if (st) FZ_REQUIRE(fz_clean_error(st, &err) && !s, err.message);
        else {
            for (int f = 0; f < m->nf; f++) tri += q2n_face_size(m, f) == 3, quads += q2n_face_size(m, f) == 4;
            for (int f = 0; f < s->nf; f++) pquads += q2n_face_size(s, f) == 4;
            FZ_REQUIRE(fz_mesh_valid(s) && np >= 0 && s->nf == m->nf - np && left == tri - 2 * np &&
                           pquads == quads + np && s->nv == m->nv, "paired mesh");
        }
        q2n_mesh_free(s);
        s = NULL;
    }
    { /* --fill-ngons: a valid mesh, every fillable polygon filled (odd ones paired by strips); without
         odd pairs each even n-gon (n >= 6) replaced by n + a (n/2 - a) quads, a in 1 .. floor(n/4),
         or, split along chords from reflex corners (fill.c fill_poly), by pieces: at least (n - 2)/2
         quads (a quad mesh of an n-gon without inner vertices), at most what fill.c makes room for
         (faces of at most 64 sides: a bigger one's fill grows with n^2) */
        int big = 0, nfill = 0, nq = 0, even = 0, lo = 0, hi = 0;
        for (int f = 0; f < m->nf; f++) {
            int n = q2n_face_size(m, f), ns = n + 2 * (1 << Q2N_FILL_SPLIT_DEPTH);
            big |= n > 64;
            if (n >= 6 && n % 2 == 0) even++, lo += (n - 2) / 2, hi += n + n / 4 * (n / 2 - n / 4) + ns + ns * ns / 16;
        }
        if (!big && m->nh <= FZ_OBJ_MAX_SUBDIVIDE_HE) {
            int count = q2n_mesh_fill_count(m, 0);
            FZ_REQUIRE(count >= even, "fill count");
            st = q2n_mesh_fill_ngons(m, &s, &nfill, &nq, &err);
            if (st) FZ_REQUIRE(fz_clean_error(st, &err) && !s, err.message);
            else FZ_REQUIRE(fz_mesh_valid(s) && nfill == count && (count > even || (nq >= lo && nq <= hi &&
                                s->nf == m->nf - even + nq)), "filled mesh");
            q2n_mesh_free(s);
            s = NULL;
        }
    }
    int *rib = NULL, nrib = 0;
    FZ_REQUIRE(q2n_mesh_ribbons(m, &rib, &nrib, &err) == Q2N_OK && nrib >= 1 && nrib <= m->ne, "ribbons");
    for (int i = 0; i < m->ne; i++) FZ_REQUIRE(rib[i] >= 0 && rib[i] < nrib, "ribbon index");
    free(rib);
    for (int h = 0; h < m->nh; h++) {
        int g = q2n_mesh_continue(m, h);
        FZ_REQUIRE(g == -1 || (g >= 0 && g < m->nh && q2n_he_origin(m, g) == q2n_he_dest(m, h)), "continue");
    }
    q2n_mesh_normalize(m, c, &mant, &e);
    double d = q2n_mesh_bbox_diag(m);
    FZ_REQUIRE(fabs(d - 1.0) < 1e-12 && fz_mesh_valid(m), "normalised mesh has diagonal 1");
    st = q2n_mesh_check_crossing(m, &err);
    FZ_REQUIRE(st == Q2N_OK || (st == Q2N_ERR_GEOMETRY && fz_clean_error(st, &err)), err.message);
    q2n_mesh_free(m);
    return 0;
}

#ifdef Q2N_LIBFUZZER
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) { return q2n_fuzz_obj(data, size); }
#endif
