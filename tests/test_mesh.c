/* test_mesh.c — OBJ reader, validation messages, half-edge topology, ribbons, writer, fuzzing.
 * References: hand-counted closed forms for procedural grids and tori (E, valences, ribbons,
 * boundary loops), the statistics table of ../shared/meshes/README.md (computed by others),
 * exact %.17g round trips, and q2n_mesh_check on every mesh that parses. */
#include <errno.h>
#include <stdint.h>
#include <sys/stat.h>
#include <time.h>

#include "check.h"
#include "mesh/mesh.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* ------------------------------------------------------------ bad inputs */

typedef struct bad_case {
    const char *text;
    q2n_status code;
    const char *prefix;  /* message must start with this ("t.obj:LINE:") */
    const char *needle;  /* and contain this */
} bad_case;

static void test_bad_inputs(void)
{
    static const bad_case cases[] = {
        {"v 1 2 3\nv 1 x 3\n", Q2N_ERR_PARSE, "t.obj:2: ", "bad number 'x'"},
        {"v 1 2 3\nv 1 2 3e\n", Q2N_ERR_PARSE, "t.obj:2: ", "bad number"},
        {"# c\nv 1 2 nan\n", Q2N_ERR_PARSE, "t.obj:2: ", "non-finite"},
        {"v 1 -inf 2\n", Q2N_ERR_PARSE, "t.obj:1: ", "non-finite"},
        {"v 1e999 0 0\n", Q2N_ERR_PARSE, "t.obj:1: ", "non-finite"},
        {"v 1 2\n", Q2N_ERR_PARSE, "t.obj:1: ", "too few coordinates (2"},
        {"v\n", Q2N_ERR_PARSE, "t.obj:1: ", "too few coordinates (0"},
        {"v 1 2 3 4 5\n", Q2N_ERR_PARSE, "t.obj:1: ", "5 numbers"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n", Q2N_ERR_PARSE, "t.obj:4: ", "face index 0"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n", Q2N_ERR_TOPOLOGY, "t.obj:5: ",
         "face index 4 out of range (3 vertices)"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n", Q2N_ERR_TOPOLOGY, "t.obj:4: ",
         "relative face index -4 out of range"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", Q2N_ERR_TOPOLOGY, "t.obj:4: ", "face with only 2 vertices (a face needs at least 3)"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf\n", Q2N_ERR_TOPOLOGY, "t.obj:4: ", "face with 0 vertices"},
        {"v 0 0 0\nvx 1 0 0\n", Q2N_ERR_PARSE, "t.obj:2: ", "unknown keyword 'vx'"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3x\n", Q2N_ERR_PARSE, "t.obj:4: ", "bad face vertex '3x'"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/ 2 3\n", Q2N_ERR_PARSE, "t.obj:4: ", "bad face vertex"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/2/ 2 3\n", Q2N_ERR_PARSE, "t.obj:4: ", "bad face vertex"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1///2 2 3\n", Q2N_ERR_PARSE, "t.obj:4: ", "bad face vertex"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 --3\n", Q2N_ERR_PARSE, "t.obj:4: ", "bad face vertex"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 2147483648\n", Q2N_ERR_TOPOLOGY, "t.obj:4: ", "2^31"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999999\n", Q2N_ERR_TOPOLOGY,
         "t.obj:4: ", "2^31"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 2147483647\n", Q2N_ERR_TOPOLOGY, "t.obj:4: ",
         "out of range (3 vertices)"},
        {"v 0 0 0\n# nothing else\n", Q2N_ERR_TOPOLOGY, "t.obj: ", "empty mesh (no faces)"},
        {"", Q2N_ERR_TOPOLOGY, "t.obj: ", "empty mesh"},
        {"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\nf 1 2 3 2\n", Q2N_ERR_TOPOLOGY, "t.obj:6: ",
         "face 0 repeats vertex 1"},
        {"v 0 0 0\nv 1 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 4\n", Q2N_ERR_GEOMETRY, "t.obj:5: ",
         "zero-length edge 1-2"},
        /* three triangles on edge 1-2 */
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n",
         Q2N_ERR_TOPOLOGY, "t.obj:8: ", "non-manifold edge 0-1 used by 3 faces: 0 (line 6), 1 (line 7), 2 (line 8)"},
        /* same direction twice */
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nf 1 2 3\nf 1 2 4\n", Q2N_ERR_TOPOLOGY, "t.obj:6: ",
         "inconsistent orientation: faces 0 (line 5), 1 (line 6) both use edge 0->1"},
        /* bow-tie: two triangles sharing only vertex 1 */
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nv -1 0 0\nv 0 -1 0\nf 1 2 3\nf 1 4 5\n", Q2N_ERR_TOPOLOGY,
         "t.obj:7: ", "non-manifold vertex 0 (bow-tie)"},
        /* two closed tetrahedra touching at vertex 1: two closed fans */
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv -1 0 0\nv 0 -1 0\nv 0 0 -1\n"
         "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\nf 1 6 5\nf 1 7 6\nf 1 5 7\nf 5 6 7\n",
         Q2N_ERR_TOPOLOGY, "t.obj:", "non-manifold vertex 0"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nbogus\n", Q2N_ERR_PARSE, "t.obj:5: ", "unknown keyword"},
        {"v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 \\\r\n 4\r\n", Q2N_ERR_TOPOLOGY, "t.obj:4: ",
         "face index 4 out of range"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const bad_case *c = &cases[i];
        q2n_mesh *m = (q2n_mesh *)1;
        q2n_error err = {0};
        q2n_status st = q2n_mesh_parse_obj(c->text, strlen(c->text), "t.obj", &m, &err);
        CHECK(st == c->code, "bad case %zu: status %d, expected %d (%s)", i, st, c->code,
              err.message);
        CHECK(m == NULL, "bad case %zu: *out not NULL on error", i);
        CHECK(err.code == c->code, "bad case %zu: err.code %d", i, err.code);
        CHECK(!strncmp(err.message, c->prefix, strlen(c->prefix)) && strstr(err.message, c->needle),
              "bad case %zu: message '%s' lacks '%s'...'%s'", i, err.message, c->prefix, c->needle);
        CHECK(!strchr(err.message, '\n'), "bad case %zu: message has a newline", i);
        /* the status does not depend on having an error buffer */
        CHECK(q2n_mesh_parse_obj(c->text, strlen(c->text), "t.obj", &m, NULL) == c->code && !m,
              "bad case %zu without error buffer", i);
    }
    /* NUL byte inside a line (the buffer API takes a length) */
    {
        const char text[] = "v 0 0 0\nv 1 0\0 0\n";
        q2n_mesh *m = NULL;
        q2n_error err = {0};
        q2n_status st = q2n_mesh_parse_obj(text, sizeof text - 1, "t.obj", &m, &err);
        CHECK(st == Q2N_ERR_PARSE && strstr(err.message, "t.obj:2: NUL byte"), "NUL: %s",
              err.message);
    }
    /* unreadable files */
    {
        q2n_mesh *m = NULL;
        q2n_error err = {0};
        q2n_status st = q2n_mesh_read_obj("/nonexistent-dir/x.obj", &m, &err);
        CHECK(st == Q2N_ERR_IO && !strcmp(err.message, "/nonexistent-dir/x.obj: No such file or "
                                          "directory"), "missing file: %d %s", st, err.message);
        st = q2n_mesh_read_obj("/tmp", &m, &err);
        CHECK(st == Q2N_ERR_IO && !strncmp(err.message, "/tmp: ", 6) && m == NULL,
              "directory: %d %s", st, err.message);
    }
}

/* ------------------------------------------------- degenerate geometry (issue 16) */

/* Parse text; 0 when accepted, else the status (message in err). */
static q2n_status parse(const char *text, q2n_error *err)
{
    q2n_mesh *m = NULL;
    q2n_status st = q2n_mesh_parse_obj(text, strlen(text), "t.obj", &m, err);
    q2n_mesh_free(m);
    return st;
}

/* A quad whose edge v1-v2 has length e relative to its diagonal (1.41) or, with thin set, a
 * parallelogram of width e relative to its diagonal (3), at scale s: text in buf. */
static const char *quad_text(char *buf, size_t n, double e, int thin, double s)
{
    if (thin) /* (0,0) (2,0) (3,3e) (1,3e): area 6e, longest edge 2, diagonal ~3 */
        snprintf(buf, n, "v 0 0 0\nv %.17g 0 0\nv %.17g %.17g 0\nv %.17g %.17g 0\nf 1 2 3 4\n", 2 * s,
                 3 * s, 3 * e * s, s, 3 * e * s);
    else
        snprintf(buf, n, "v 0 0 0\nv %.17g 0 0\nv %.17g %.17g 0\nv 0 %.17g 0\nf 1 2 3 4\n", s, s,
                 e * s, s);
    return buf;
}

static void test_degenerate_geometry(void)
{
    static const bad_case cases[] = {
        /* issue 16: accepted before (exact-equality check only), NaN samples with exit 0 */
        {"v 0 0 0\nv 1 0 0\nv 1 1e-50 0\nv 0 1 0\nf 1 2 3 4\n", Q2N_ERR_GEOMETRY, "t.obj:5: ",
         "face 0 has a degenerate edge 1-2: length 1e-50, 7.1e-51 of the bounding-box diagonal"},
        {"v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nf 1 2 3 4\n", Q2N_ERR_GEOMETRY, "t.obj:5: ",
         "face 0 has (near) zero area"},
        {"v 0 0 0\nv 1 0 0\nv 0 0 0\nv 0 1 0\nf 1 2 3 4\n", Q2N_ERR_GEOMETRY, "t.obj:5: ",
         "face 0 has opposite corners 0 and 2 at the same position"},
        {"v 0 0 0\nv 1 1 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 4\n", Q2N_ERR_GEOMETRY, "t.obj:5: ",
         "(near) zero area"}, /* symmetric bow-tie: the two lobes cancel */
        {"v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n", Q2N_ERR_GEOMETRY, "t.obj:4: ", "zero area"},
        /* the second face of a valid first one: its line */
        {"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 4 0 1e-20\nf 1 2 3 4\nf 2 5 6\n",
         Q2N_ERR_GEOMETRY, "t.obj:8: ", "face 1 has (near) zero area"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        q2n_error err = {0};
        q2n_status st = parse(cases[i].text, &err);
        CHECK(st == cases[i].code && !strncmp(err.message, cases[i].prefix, strlen(cases[i].prefix)) &&
              strstr(err.message, cases[i].needle), "degenerate case %zu: %d '%s' lacks '%s'", i, st,
              err.message, cases[i].needle);
    }
    /* the threshold sits where mesh_policy.h says (1e-12 of the diagonal), at every scale */
    static const double scales[] = {1.0, 1e-300, 1e300, 3e-320, 1.7e308};
    for (int c = 0; c < 5; c++) {
        char buf[512];
        q2n_error err = {0};
        double s = scales[c] == 1.7e308 ? 5e307 : scales[c]; /* 3 s must stay in range */
        int big = c == 3; /* 3e-320 is subnormal: its 1e-11 fraction is not representable */
        if (!big) {
            CHECK(parse(quad_text(buf, sizeof buf, 1.41e-13, 0, s), &err) == Q2N_ERR_GEOMETRY &&
                  strstr(err.message, "degenerate edge"), "edge 1e-13 at scale %g: %s", s, err.message);
            CHECK(parse(quad_text(buf, sizeof buf, 1.41e-11, 0, s), &err) == Q2N_OK, "edge 1e-11 at scale "
                  "%g: %s", s, err.message);
            CHECK(parse(quad_text(buf, sizeof buf, 1e-13, 1, s), &err) == Q2N_ERR_GEOMETRY &&
                  strstr(err.message, "zero area"), "width 1e-13 at scale %g: %s", s, err.message);
            CHECK(parse(quad_text(buf, sizeof buf, 1e-11, 1, s), &err) == Q2N_OK, "width 1e-11 at scale "
                  "%g: %s", s, err.message);
        }
        CHECK(parse(quad_text(buf, sizeof buf, 0.5, 0, s), &err) == Q2N_OK, "plain quad at scale %g: %s",
              s, err.message);
    }
    /* the arrays constructor names the mesh and the face */
    {
        const double pos[] = {0, 0, 0, 1, 0, 0, 1, 1e-14, 0, 0, 1, 0};
        const int fs[] = {0, 4}, fv[] = {0, 1, 2, 3};
        q2n_mesh *m = NULL;
        q2n_error err = {0};
        CHECK(q2n_mesh_from_arrays(4, pos, 1, fs, fv, "arr", &m, &err) == Q2N_ERR_GEOMETRY && !m &&
              !strncmp(err.message, "arr: face 0 has a degenerate edge 1-2", 37), "arrays: %s", err.message);
    }
    /* accepted: a straight corner (vertex on its neighbours' segment, as in
     * osd_catmark_gregory_test1), a dart, an asymmetric bow-tie (a valid Catmull–Clark control
     * face); q2n_mesh_check_crossing then rejects only the bow-tie, naming its line */
    static const struct { const char *text; int crossing; } ok[] = {
        {"v 0 0 0\nv 2 0 0\nv 2 2 0\nv 1 1 0\nf 1 2 3 4\n", 0},
        {"v 0 0 0\nv 2 0 0\nv 0.6 0.6 0\nv 0 2 0\nf 1 2 3 4\n", 0},
        {"v 0 0 0\nv 2 2 0\nv 2 0 0\nv 0 1 0\n# bow-tie\nf 1 2 3 4\n", 1},
        {"v 0 0 0\nv 1 0 0.9\nv 1 1 0\nv 0 1 0.9\nf 1 2 3 4\n", 0}, /* saddle: warped, not crossing */
    };
    for (int i = 0; i < 4; i++) {
        q2n_mesh *m = NULL;
        q2n_error err = {0};
        CHECK(q2n_mesh_parse_obj(ok[i].text, strlen(ok[i].text), "t.obj", &m, &err) == Q2N_OK,
              "accepted shape %d: %s", i, err.message);
        if (!m) continue;
        q2n_status st = q2n_mesh_check_crossing(m, &err);
        CHECK(ok[i].crossing ? st == Q2N_ERR_GEOMETRY && !strncmp(err.message, "t.obj:6: face 0 is "
              "self-crossing (a bow-tie)", 40) : st == Q2N_OK, "shape %d crossing: %d %s", i, st,
              st ? err.message : "");
        q2n_mesh_free(m);
    }
}

/* q2n_mesh_normalize: diagonal 1, centre at the origin, power-of-two scales bit for bit,
 * unreferenced vertices untouched, and the map back reproduces the input to rounding. */
static void test_normalize(void)
{
    const char *text = "v 1e6 2e6 -3\nv 1000004 2e6 -3\nv 1000004 2000003 -2\nv 1e6 2000003 -3\n"
                       "v 7 7 7\nf 1 2 3 4\n";
    q2n_mesh *m = NULL, *h = NULL;
    q2n_error err = {0};
    if (q2n_mesh_parse_obj(text, strlen(text), "n.obj", &m, &err)) { CHECK(0, "%s", err.message); return; }
    double in[15], c[3], mant, c2[3], mant2;
    int exp, exp2;
    memcpy(in, m->pos, sizeof in);
    q2n_mesh_normalize(m, c, &mant, &exp);
    CHECK_NEAR(q2n_mesh_bbox_diag(m), 1.0, 2e-16, "normalised diagonal");
    CHECK(c[0] == 1000002 && c[1] == 2000001.5 && c[2] == -2.5, "centre %g %g %g", c[0], c[1], c[2]);
    CHECK_NEAR(ldexp(mant, exp), sqrt(16 + 9 + 1), 1e-14, "diagonal as mant * 2^exp");
    CHECK(m->pos[12] == 7 && m->pos[13] == 7 && m->pos[14] == 7, "unreferenced vertex untouched");
    double worst = 0;
    for (int i = 0; i < 12; i++) {
        double back = c[i % 3] + ldexp(m->pos[i] * mant, exp);
        if (fabs(back - in[i]) > worst) worst = fabs(back - in[i]);
    }
    CHECK(worst <= 4.7e-10, "map back differs by %g (rounding of 2e6 is 2.3e-10)", worst);
    /* the same mesh halved 600 times normalises to the same bits */
    char half[512];
    snprintf(half, sizeof half, "v %a %a %a\nv %a %a %a\nv %a %a %a\nv %a %a %a\nf 1 2 3 4\n",
             ldexp(in[0], -600), ldexp(in[1], -600), ldexp(in[2], -600), ldexp(in[3], -600),
             ldexp(in[4], -600), ldexp(in[5], -600), ldexp(in[6], -600), ldexp(in[7], -600),
             ldexp(in[8], -600), ldexp(in[9], -600), ldexp(in[10], -600), ldexp(in[11], -600));
    if (q2n_mesh_parse_obj(half, strlen(half), "h.obj", &h, &err) == Q2N_OK) {
        q2n_mesh_normalize(h, c2, &mant2, &exp2);
        CHECK(memcmp(h->pos, m->pos, 12 * sizeof(double)) == 0 && mant2 == mant && exp2 == exp - 600,
              "power-of-two scale: normalised coordinates differ");
    } else CHECK(0, "halved mesh: %s", err.message);
    q2n_mesh_free(h);
    q2n_mesh_free(m);
    /* coordinates near the ends of the double range: frame without overflow */
    const char *big = "v -1.7e308 -1.7e308 0\nv 1.7e308 -1.7e308 0\nv 1.7e308 1.7e308 0\nf 1 2 3\n";
    if (q2n_mesh_parse_obj(big, strlen(big), "b.obj", &m, &err) == Q2N_OK) {
        q2n_mesh_frame(m, c, &mant, &exp);
        CHECK(c[0] == 0 && c[1] == 0 && exp == 1024 && fabs(mant - 2 * sqrt(2) * ldexp(1.7e308, -1024)) < 1e-15,
              "huge frame (diagonal 4.8e308 = mant * 2^1024): c %g %g, "
              "mant %g exp %d", c[0], c[1], mant, exp);
        q2n_mesh_normalize(m, c, &mant, &exp);
        CHECK_NEAR(q2n_mesh_bbox_diag(m), 1.0, 2e-16, "huge mesh normalised");
        q2n_mesh_free(m);
    } else CHECK(0, "huge coordinates rejected: %s", err.message);
}

/* -------------------------------------------------------------- valid forms */

static void test_valid_forms(void)
{
    const char text[] =
        "# header comment\r\n"
        "mtllib x.mtl\r\n"
        "o thing\n"
        "v 0 0 0 1.0\n"
        "v 1.5 0 0   # trailing comment\n"
        "v 1.5 2e0 0\n"
        "\n"
        "   \t\n"
        "v 0 2 -0.25 0.5 0.5 0.5\n"             /* x y z r g b */
        "v 9 9 9\n"                              /* unreferenced */
        "vt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\nvp 0.5\ng grp\ns off\nusemtl m\n"
        "f 1/1/1 2/2/1 3/3/1 4/1/1\n"
        "l 1 2\n"
        "v 3 0 0\n"
        "f 2//1 -1//1 \\\n"                      /* continuation, negative index */
        "  3//1\n"
        "f +3/2 -1/1 7/3\n"                      /* a/b, '+' sign, forward reference */
        "v 3 2 0\n";
    q2n_mesh *m = NULL;
    q2n_error err = {0};
    q2n_status st = q2n_mesh_parse_obj(text, sizeof text - 1, "ok.obj", &m, &err);
    CHECK(st == Q2N_OK, "valid forms: %s", err.message);
    if (st) return;
    CHECK(m->nv == 7 && m->nf == 3 && m->nh == 10, "valid forms: V %d F %d H %d", m->nv, m->nf,
          m->nh);
    static const int fv[] = {0, 1, 2, 3, 1, 5, 2, 2, 5, 6};
    static const int fs[] = {0, 4, 7, 10};
    for (int i = 0; i < 10; i++) CHECK(m->face_vert[i] == fv[i], "face_vert[%d] = %d", i, m->face_vert[i]);
    for (int i = 0; i < 4; i++) CHECK(m->face_start[i] == fs[i], "face_start[%d]", i);
    CHECK(m->face_line[0] == 19 && m->face_line[1] == 22 && m->face_line[2] == 24,
          "face lines %d %d %d", m->face_line[0], m->face_line[1], m->face_line[2]);
    CHECK(m->pos[3 * 3 + 2] == -0.25 && m->pos[3 * 2 + 1] == 2.0 && m->pos[3 * 1 + 0] == 1.5,
          "positions");
    CHECK(m->vert_he[4] == -1 && m->valence[4] == 0 && m->vert_nfaces[4] == 0,
          "unreferenced vertex kept with no fan");
    CHECK(m->all_quads == 0, "mixed faces: all_quads 0");
    CHECK(q2n_mesh_check(m, &err) == Q2N_OK, "check: %s", err.message);
    /* the unreferenced vertex (9,9,9) does not count in the bounding box: x 0..3, y 0..2, z -0.25..0 */
    CHECK_NEAR(q2n_mesh_bbox_diag(m), sqrt(9.0 + 4.0 + 0.0625), 1e-15, "bbox diag");
    q2n_mesh_free(m);
    q2n_mesh_free(NULL);
    /* a UTF-8 byte order mark before the first record */
    const char bom[] = "\xEF\xBB\xBFv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    CHECK(q2n_mesh_parse_obj(bom, sizeof bom - 1, "bom.obj", &m, &err) == Q2N_OK && m->nv == 3,
          "BOM: %s", err.message);
    q2n_mesh_free(m);
}

/* Arrays constructor: same validation, messages name the mesh and the element. */
static void test_from_arrays_errors(void)
{
    const double pos[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, NAN, 1, 0};
    const int fs[] = {0, 3, 6}, fv_ok[] = {0, 1, 2, 0, 2, 1}, fv_range[] = {0, 1, 2, 0, 2, 4};
    const int fs_bad[] = {1, 4};
    q2n_mesh *m = (q2n_mesh *)1;
    q2n_error err = {0};
    CHECK(q2n_mesh_from_arrays(4, pos, 1, fs, fv_ok, "arr", &m, &err) == Q2N_ERR_PARSE && !m &&
          !strcmp(err.message, "arr: vertex 3 has a non-finite coordinate"), "NaN: %s", err.message);
    CHECK(q2n_mesh_from_arrays(3, pos, 2, fs, fv_range, "arr", &m, &err) == Q2N_ERR_TOPOLOGY &&
          !strcmp(err.message, "arr: face 1 vertex index 4 out of range (3 vertices)"),
          "range: %s", err.message);
    CHECK(q2n_mesh_from_arrays(3, pos, 1, fs_bad, fv_ok, "arr", &m, &err) == Q2N_ERR_ARG,
          "face_start[0] != 0: %s", err.message);
    CHECK(q2n_mesh_from_arrays(3, pos, 0, fs, fv_ok, "arr", &m, &err) == Q2N_ERR_TOPOLOGY &&
          strstr(err.message, "no faces"), "no faces: %s", err.message);
    /* two triangles 0,1,2 and 0,2,1 glue into a closed two-sided pillow: valid, no boundary */
    CHECK(q2n_mesh_from_arrays(3, pos, 2, fs, fv_ok, "arr", &m, &err) == Q2N_OK && m &&
          m->n_boundary_loops == 0 && m->ne == 3, "pillow: %s", err.message);
    q2n_mesh_free(m);
}

/* ------------------------------------------------------- procedural meshes */

/* (nx x ny) quads; torus = 1 wraps both directions (vertices nx*ny), else a flat grid. */
static q2n_mesh *grid(int nx, int ny, int torus)
{
    int vx = torus ? nx : nx + 1, vy = torus ? ny : ny + 1, nv = vx * vy, nf = nx * ny;
    double *pos = malloc(3 * (size_t)nv * sizeof *pos);
    int *fs = malloc(((size_t)nf + 1) * sizeof *fs), *fv = malloc(4 * (size_t)nf * sizeof *fv);
    for (int j = 0; j < vy; j++)
        for (int i = 0; i < vx; i++) {
            double *p = pos + 3 * (j * vx + i);
            if (torus) {
                double a = 2 * M_PI * i / nx, b = 2 * M_PI * j / ny;
                p[0] = (3 + cos(b)) * cos(a); p[1] = (3 + cos(b)) * sin(a); p[2] = sin(b);
            } else {
                p[0] = i; p[1] = j; p[2] = 0.1 * i * j;
            }
        }
    for (int j = 0, f = 0; j < ny; j++)
        for (int i = 0; i < nx; i++, f++) {
            int i1 = (i + 1) % vx, j1 = (j + 1) % vy;
            fs[f] = 4 * f;
            fv[4 * f + 0] = j * vx + i; fv[4 * f + 1] = j * vx + i1;
            fv[4 * f + 2] = j1 * vx + i1; fv[4 * f + 3] = j1 * vx + i;
        }
    fs[nf] = 4 * nf;
    q2n_mesh *m = NULL;
    q2n_error err = {0};
    q2n_status st = q2n_mesh_from_arrays(nv, pos, nf, fs, fv, "grid", &m, &err);
    CHECK(st == Q2N_OK, "grid %dx%d torus %d: %s", nx, ny, torus, err.message);
    free(pos); free(fs); free(fv);
    return m;
}

static void test_grid_topology(void)
{
    const int nx = 5, ny = 3;
    q2n_mesh *m = grid(nx, ny, 0);
    if (!m) return;
    q2n_error err = {0};
    CHECK(q2n_mesh_check(m, &err) == Q2N_OK, "grid check: %s", err.message);
    CHECK(m->ne == nx * (ny + 1) + ny * (nx + 1), "grid edges %d", m->ne);
    CHECK(m->n_boundary_loops == 1 && m->all_quads == 1, "grid loops %d", m->n_boundary_loops);
    int vx = nx + 1, nbad = 0, nrot = 0;
    for (int j = 0; j <= ny; j++)
        for (int i = 0; i <= nx; i++) {
            int v = j * vx + i, bi = (i == 0 || i == nx), bj = (j == 0 || j == ny);
            int val = 4 - bi - bj;
            if (m->valence[v] != val || m->vert_boundary[v] != (bi || bj) ||
                m->vert_nfaces[v] != (bi && bj ? 1 : bi || bj ? 2 : 4))
                nbad++;
            /* rotating from vert_he visits every incident face exactly once */
            int h = m->vert_he[v], k = 0;
            do { k++; h = q2n_mesh_rotate(m, h); } while (h >= 0 && h != m->vert_he[v] && k < 10);
            if (k != m->vert_nfaces[v]) nrot++;
            if ((bi || bj) && m->he_twin[m->vert_he[v]] != -1) nrot++;
        }
    CHECK(nbad == 0, "grid valences: %d wrong", nbad);
    CHECK(nrot == 0, "grid rotations: %d wrong", nrot);
    /* edge numbering: first appearance in face order -> face 0 gives edges 0..3 */
    for (int i = 0; i < 4; i++) CHECK(m->he_edge[i] == i, "he_edge[%d] = %d", i, m->he_edge[i]);
    CHECK(m->he_edge[4] == 4 && m->he_edge[4 + 3] == 1, "face 1 edges: %d %d", m->he_edge[4],
          m->he_edge[7]);
    /* section polylines: interior row j = 1 from x = 0 to x = nx, then bottom boundary row */
    for (int row = 1; row >= 0; row--) {
        int h = -1;
        for (int g = 0; g < m->nh; g++)
            if (q2n_he_origin(m, g) == row * vx && q2n_he_dest(m, g) == row * vx + 1) h = g;
        int steps = 1, ok = h >= 0;
        while (ok && (h = q2n_mesh_continue(m, h)) >= 0) {
            steps++;
            if (q2n_he_origin(m, h) != row * vx + steps - 1 || q2n_he_dest(m, h) != row * vx + steps)
                ok = 0;
        }
        CHECK(ok && steps == nx, "continue along row %d: %d steps (expected %d)", row, steps, nx);
    }
    /* an interior edge arriving at a boundary vertex ends the polyline */
    for (int g = 0; g < m->nh; g++)
        if (q2n_he_origin(m, g) == vx + 2 && q2n_he_dest(m, g) == 2)
            CHECK(q2n_mesh_continue(m, g) == -1, "continue into boundary vertex must end");
    int *rib = NULL, nr = 0;
    CHECK(q2n_mesh_ribbons(m, &rib, &nr, &err) == Q2N_OK && nr == nx + ny, "grid ribbons %d", nr);
    if (rib) {
        int bad = 0;
        for (int f = 0; f < m->nf; f++)
            for (int i = 0; i < 2; i++)
                if (rib[m->he_edge[4 * f + i]] != rib[m->he_edge[4 * f + i + 2]]) bad++;
        CHECK(bad == 0 && rib[0] == 0, "ribbons of opposite edges differ (%d)", bad);
        int prev_max = -1, order_ok = 1; /* numbering in order of first edge */
        for (int e = 0; e < m->ne; e++) {
            if (rib[e] > prev_max + 1) order_ok = 0;
            if (rib[e] > prev_max) prev_max = rib[e];
        }
        CHECK(order_ok, "ribbon numbering not in edge order");
    }
    free(rib);
    q2n_mesh_free(m);

    m = grid(6, 4, 1);
    if (!m) return;
    CHECK(q2n_mesh_check(m, &err) == Q2N_OK, "torus check: %s", err.message);
    CHECK(m->n_boundary_loops == 0 && m->ne == 2 * 24 && m->nv - m->ne + m->nf == 0,
          "torus: loops %d E %d", m->n_boundary_loops, m->ne);
    int all4 = 1;
    for (int v = 0; v < m->nv; v++) all4 &= m->valence[v] == 4 && !m->vert_boundary[v];
    CHECK(all4, "torus valences");
    /* a closed loop of continuations returns to its start after 6 steps */
    int h0 = 0, h = h0, k = 0;
    do { h = q2n_mesh_continue(m, h); k++; } while (h >= 0 && h != h0 && k < 100);
    CHECK(h == h0 && k == 6, "torus continuation loop: %d steps", k);
    CHECK(q2n_mesh_ribbons(m, &rib, &nr, &err) == Q2N_OK && nr == 6 + 4, "torus ribbons %d", nr);
    free(rib);
    q2n_mesh_free(m);
}

/* q2n_mesh_check must notice each kind of corruption (so that its OK elsewhere means something). */
static void test_check_detects(void)
{
    static const char *what[] = {"twin", "twin of boundary", "he_edge", "edge_he", "vert_he",
                                 "valence", "vert_nfaces", "boundary flag", "loops", "all_quads",
                                 "he_face", "ne"};
    for (int k = 0; k < 12; k++) {
        q2n_mesh *m = grid(3, 2, 0);
        if (!m) return;
        int h = 5, t = m->he_twin[h], bh = m->vert_he[0];
        switch (k) {
        case 0: m->he_twin[h] = m->he_twin[h + 1]; break;
        case 1: m->he_twin[bh] = h; break;
        case 2: m->he_edge[h] = (m->he_edge[h] + 1) % m->ne; break;
        case 3: m->edge_he[m->he_edge[h]] = t > h ? t : (t >= 0 ? h : h + 1); break;
        case 4: m->vert_he[5] = m->vert_he[6]; break;
        case 5: m->valence[5]++; break;
        case 6: m->vert_nfaces[5]--; break;
        case 7: m->vert_boundary[0] = 0; break;
        case 8: m->n_boundary_loops = 2; break;
        case 9: m->all_quads = 0; break;
        case 10: m->he_face[h] = 0; break;
        case 11: m->ne--; break;
        }
        q2n_error err = {0};
        CHECK(q2n_mesh_check(m, &err) != Q2N_OK, "check misses corrupted %s", what[k]);
        q2n_mesh_free(m);
    }
}

/* ---------------------------------------------------------- shared meshes */

typedef struct table_row {
    const char *file;
    int V, F, quads, loops;
    const char *ev;      /* interior EVs "val x count" as in the README, "" if none */
    const char *bev;     /* boundary vertices with valence not in {2,3} */
    int genus;           /* closed meshes: V - E + F = 2 - 2g; -1 for open */
} table_row;

static void ev_string(const q2n_mesh *m, int boundary, char *buf, size_t n)
{
    int cnt[64] = {0};
    for (int v = 0; v < m->nv; v++) {
        int val = m->valence[v];
        if (m->vert_nfaces[v] == 0 || val >= 64) continue;
        if (!boundary && !m->vert_boundary[v] && val != 4) cnt[val]++;
        if (boundary && m->vert_boundary[v] && val != 2 && val != 3) cnt[val]++;
    }
    buf[0] = '\0';
    for (int k = 0; k < 64; k++)
        if (cnt[k]) {
            size_t u = strlen(buf);
            snprintf(buf + u, n - u, "%s%dx%d", u ? ", " : "", k, cnt[k]);
        }
}

static void test_shared_meshes(void)
{
    static const table_row rows[] = { /* ../shared/meshes/README.md */
        {"osd_catmark_cube.obj", 8, 6, 1, 0, "3x8", "", 0},
        {"osd_catmark_torus.obj", 32, 32, 1, 0, "", "", 1},
        {"osd_catmark_righthanded.obj", 436, 434, 1, 0, "3x56, 5x48", "", 0},
        {"osd_catmark_flap.obj", 8, 3, 1, 1, "", "", -1},
        {"osd_catmark_tent.obj", 16, 9, 1, 1, "", "", -1},
        {"osd_catmark_gregory_test1.obj", 10, 7, 1, 1, "3x5", "4x1", -1},
        {"osd_catmark_gregory_test6.obj", 20, 13, 1, 1, "3x2", "4x2", -1},
        {"osd_catmark_fvar_bound3.obj", 13, 6, 1, 1, "6x1", "", -1},
        {"osd_catmark_xord_boundary.obj", 44, 18, 1, 4, "", "4x1, 5x1, 6x1, 7x1", -1},
        {"osd_catmark_helmet.obj", 72, 58, 1, 1, "3x4", "4x4", -1},
        {"osd_catmark_pawn.obj", 601, 588, 1, 1, "3x12, 12x1", "", -1},
        {"osd_catmark_rook.obj", 768, 777, 0, 1, "3x33, 5x44, 6x7, 7x5", "", -1},
        {"gismo_ev_valence8_carpet.obj", 49, 32, 1, 1, "8x1", "", -1},
        {"gismo_cube_with_boundary.obj", 8, 5, 1, 1, "3x4", "", -1},
        {"gismo_octtorus_hole.obj", 32, 29, 1, 1, "", "4x5", -1},
        {"gismo_polycube.obj", 74, 72, 1, 0, "3x13, 5x3, 6x1", "", 0},
        {"crane_spot_control_mesh.obj", 188, 180, 0, 0, "3x52, 5x24, 6x4", "", 0},
    };
    for (size_t i = 0; i < sizeof rows / sizeof rows[0]; i++) {
        const table_row *r = &rows[i];
        const char *path = chk_shared_mesh(r->file);
        if (!path) continue;
        q2n_mesh *m = NULL;
        q2n_error err = {0};
        q2n_status st = q2n_mesh_read_obj(path, &m, &err);
        CHECK(st == Q2N_OK, "%s: %s", r->file, err.message);
        if (st) continue;
        CHECK(q2n_mesh_check(m, &err) == Q2N_OK, "%s check: %s", r->file, err.message);
        CHECK(m->nv == r->V && m->nf == r->F, "%s: V %d F %d (table %d %d)", r->file, m->nv, m->nf,
              r->V, r->F);
        CHECK(m->all_quads == r->quads, "%s: all_quads %d", r->file, m->all_quads);
        CHECK(m->n_boundary_loops == r->loops, "%s: loops %d (table %d)", r->file,
              m->n_boundary_loops, r->loops);
        char ev[256], bev[256];
        ev_string(m, 0, ev, sizeof ev);
        ev_string(m, 1, bev, sizeof bev);
        CHECK(!strcmp(ev, r->ev), "%s: interior EVs '%s' (table '%s')", r->file, ev, r->ev);
        CHECK(!strcmp(bev, r->bev), "%s: boundary valences '%s' (table '%s')", r->file, bev, r->bev);
        if (r->genus >= 0)
            CHECK(m->nv - m->ne + m->nf == 2 - 2 * r->genus, "%s: Euler characteristic %d", r->file,
                  m->nv - m->ne + m->nf);
        q2n_mesh_free(m);
    }
}

/* ------------------------------------------------------------------ writer */

static void test_writer(void)
{
    /* awkward doubles survive the %.17g round trip bit for bit */
    /* (the extremes sit on the unreferenced vertex 4: a face through 1e300 and 0.3 would be
     * degenerate relative to its bounding box) */
    const double pos[] = {0.1, 1.0 / 3.0, -2.5e-300, 5.0, 1e-17, 0.3, 0.6, 0.9, -1.0 / 9.0,
                          42.0, 42.0, 42.0, 1e300, -0.7, 2.0 / 7.0};
    const int fs[] = {0, 4}, fv[] = {0, 1, 2, 3};
    q2n_mesh *m = NULL, *r = NULL;
    q2n_error err = {0};
    CHECK(q2n_mesh_from_arrays(5, pos, 1, fs, fv, "w", &m, &err) == Q2N_OK, "writer mesh: %s",
          err.message);
    char dir[256], path[400];
    snprintf(dir, sizeof dir, "%s/writer_XXXXXX", chk_scratch_dir());
    if (!m || !mkdtemp(dir)) { CHECK(0, "writer: no folder %s", dir); q2n_mesh_free(m); return; }
    snprintf(path, sizeof path, "%s/out.obj", dir);
    CHECK(q2n_mesh_write_obj(m, path, &err) == Q2N_OK, "write: %s", err.message);
    CHECK(q2n_mesh_read_obj(path, &r, &err) == Q2N_OK, "read back: %s", err.message);
    if (r) {
        CHECK(r->nv == 5 && r->nf == 1 && memcmp(r->pos, pos, sizeof pos) == 0,
              "round trip positions differ");
        CHECK(memcmp(r->face_vert, fv, sizeof fv) == 0, "round trip faces differ");
    }
    struct stat sb;
    CHECK(stat(path, &sb) == 0 && (sb.st_mode & 0777) == 0644, "written file mode %o",
          (unsigned)(sb.st_mode & 0777));
    /* only out.obj is left in the directory (no temp files) */
    char cmd[400];
    snprintf(cmd, sizeof cmd, "test $(ls -A %s | wc -l) -eq 1", dir);
    CHECK(system(cmd) == 0, "temp file left behind in %s", dir);
    snprintf(path, sizeof path, "%s/no/such/dir.obj", dir);
    CHECK(q2n_mesh_write_obj(m, path, &err) == Q2N_ERR_IO && strstr(err.message, "No such file"),
          "write into missing dir: %s", err.message);
    snprintf(path, sizeof path, "%s/out.obj", dir);
    unlink(path);
    rmdir(dir);
    q2n_mesh_free(m);
    q2n_mesh_free(r);
}

/* Long lines (no fixed limit): a 1 MB comment and a 20000-gon written on continued lines,
 * read through the streaming file reader. */
static void test_long_lines(void)
{
    const int n = 20000;
    size_t cap = (size_t)n * 64 + (2u << 20);
    char *text = malloc(cap);
    size_t len = 0;
    text[len++] = '#';
    memset(text + len, 'x', 1u << 20);
    len += 1u << 20;
    text[len++] = '\n';
    for (int i = 0; i < n; i++)
        len += (size_t)snprintf(text + len, cap - len, "v %.17g %.17g 0\n", cos(2 * M_PI * i / n),
                                sin(2 * M_PI * i / n));
    len += (size_t)snprintf(text + len, cap - len, "f");
    for (int i = 0; i < n; i++)
        len += (size_t)snprintf(text + len, cap - len, " %d%s", i + 1, i % 1000 == 999 ? " \\\r\n" : "");
    text[len++] = '\n';
    const char *path = chk_scratch("long_lines.obj");
    FILE *tf = fopen(path, "wb");
    if (!tf) { CHECK(0, "cannot write %s", path); free(text); return; }
    CHECK(fwrite(text, 1, len, tf) == len, "write %s", path);
    fclose(tf);
    q2n_mesh *m = NULL;
    q2n_error err = {0};
    CHECK(q2n_mesh_read_obj(path, &m, &err) == Q2N_OK, "long lines: %s", err.message);
    if (m) {
        CHECK(m->nf == 1 && q2n_face_size(m, 0) == n && m->face_line[0] == n + 2,
              "long face: size %d line %d", q2n_face_size(m, 0), m->face_line[0]);
        CHECK(m->n_boundary_loops == 1 && m->valence[0] == 2, "n-gon boundary");
    }
    q2n_mesh_free(m);
    unlink(path);
    free(text);
}

/* ----------------------------------------------------------------- fuzzing */

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static uint32_t rnd(void)
{
    rng_state ^= rng_state << 13; rng_state ^= rng_state >> 7; rng_state ^= rng_state << 17;
    return (uint32_t)(rng_state >> 11);
}

/* Random mutations of small valid meshes: the parser must never crash, and whatever it accepts
 * must pass q2n_mesh_check and subdivide cleanly.  Bounded: 4 s or 200000 inputs. */
static void test_fuzz(void)
{
    static const char *seeds[] = {
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\nf 1 2 3 4\nf 2 5 6 3\n",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
        "v 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nv 0 1 0\r\nvt 0 0\r\nf 1/1 2/1 3/1 \\\r\n4/1\r\n",
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf -4//1 -3//1 -2//1 -1//1\n# end\n",
    };
    static const char *dict[] = {"v ", "f ", "/", "//", "-", "\\\n", "\n", "#", "0", "1", "7",
                                 "-1", "1e308", "1e999", "nan", " ", "\r\n", "2147483648", "vt",
                                 "+", ".", "e", "\t", "f 1 2 3\n", "v 0 0 0\n"};
    clock_t t0 = clock();
    int n = 0, accepted = 0, rejected = 0, bad_check = 0, bad_msg = 0;
    char buf[1024];
    while (n < 200000 && (double)(clock() - t0) / CLOCKS_PER_SEC < 4.0) {
        const char *s = seeds[rnd() % 4];
        size_t len = strlen(s);
        memcpy(buf, s, len);
        int nm = 1 + rnd() % 6;
        for (int k = 0; k < nm; k++) {
            size_t at = len ? rnd() % (len + 1) : 0;
            switch (rnd() % 4) {
            case 0: if (len) buf[rnd() % len] = (char)(rnd() & 0xff); break;  /* flip a byte */
            case 1: {                                                         /* delete a range */
                size_t d = rnd() % 8;
                if (at + d > len) d = len - at;
                memmove(buf + at, buf + at + d, len - at - d);
                len -= d;
                break;
            }
            default: {                                                        /* insert a token */
                const char *t = dict[rnd() % (sizeof dict / sizeof dict[0])];
                size_t tl = strlen(t);
                if (len + tl >= sizeof buf) break;
                memmove(buf + at + tl, buf + at, len - at);
                memcpy(buf + at, t, tl);
                len += tl;
            }
            }
        }
        q2n_mesh *m = NULL, *sd = NULL;
        q2n_error err = {0};
        q2n_status st = q2n_mesh_parse_obj(buf, len, "fz.obj", &m, &err);
        n++;
        if (st == Q2N_OK) {
            accepted++;
            if (q2n_mesh_check(m, &err) != Q2N_OK) bad_check++;
            if (q2n_mesh_subdivide(m, 1, &sd, &err) == Q2N_OK && q2n_mesh_check(sd, &err) != Q2N_OK)
                bad_check++;
        } else {
            rejected++;
            if (strncmp(err.message, "fz.obj", 6) || strchr(err.message, '\n') || !m == 0) bad_msg++;
        }
        q2n_mesh_free(sd);
        q2n_mesh_free(m);
    }
    CHECK(n >= 1000, "fuzz: only %d inputs in the time budget", n);
    CHECK(accepted > 0 && rejected > 0, "fuzz: accepted %d rejected %d (both paths needed)",
          accepted, rejected);
    CHECK(bad_check == 0, "fuzz: %d accepted meshes failed q2n_mesh_check", bad_check);
    CHECK(bad_msg == 0, "fuzz: %d rejections without a 'fz.obj...' one-line message", bad_msg);
    printf("fuzz: %d inputs, %d accepted, %d rejected\n", n, accepted, rejected);

    /* random face lists over few vertices: every validation branch of the arrays constructor;
     * whatever is accepted must be a consistent manifold (q2n_mesh_check) */
    double pos[3 * 8];
    for (int v = 0; v < 8; v++) pos[3 * v] = v, pos[3 * v + 1] = v * v, pos[3 * v + 2] = v % 3;
    int acc2 = 0, bad2 = 0, kinds[8] = {0};
    for (int it = 0; it < 100000; it++) {
        int nf = 1 + rnd() % 6, fs[7], fv[6 * 5], k = 0;
        for (int f = 0; f < nf; f++) {
            fs[f] = k;
            int sz = 3 + rnd() % 3;
            for (int i = 0; i < sz; i++) fv[k++] = rnd() % 8;
        }
        fs[nf] = k;
        q2n_mesh *m = NULL;
        q2n_error err = {0};
        q2n_status st = q2n_mesh_from_arrays(8, pos, nf, fs, fv, "rnd", &m, &err);
        kinds[st & 7]++;
        if (st == Q2N_OK) {
            acc2++;
            if (q2n_mesh_check(m, &err) != Q2N_OK) bad2++;
        }
        q2n_mesh_free(m);
    }
    printf("random faces: 100000 meshes, %d accepted\n", acc2);
    CHECK(bad2 == 0 && acc2 > 100 && kinds[Q2N_ERR_TOPOLOGY] > 100,
          "random faces: %d accepted, %d failed the check", acc2, bad2);
}

int main(void)
{
    test_bad_inputs();
    test_valid_forms();
    test_from_arrays_errors();
    test_degenerate_geometry();
    test_normalize();
    test_grid_topology();
    test_check_detects();
    test_shared_meshes();
    test_writer();
    test_long_lines();
    test_fuzz();
    CHECK_DONE("test_mesh");
}
