/* test_readers.c — the OFF and PLY readers against the OBJ reader (an independent path through the
 * same mesh): the same mesh written as OBJ, ASCII OFF, ASCII PLY and binary PLY (both byte orders,
 * double and float coordinates) reads back to identical vertex and face arrays, so the surface is
 * the same to the bit; `quad2nurbs sample` prints the same bytes and the STEP file is the same for
 * every format.  Bad files give one "file:line" message (binary PLY: element and byte) and the
 * right status; the format is found by extension or by the first line; OBJ `t` tag lines
 * (OpenSubdiv's crease/corner tags) are counted, named and ignored.  STL (binary, also with a header
 * starting "solid", and ASCII) of a triangulated torus welds back to the OBJ's vertices and samples
 * the same bytes through --pair-triangles; malformed STL gives one message naming line or byte. */
#include <stdint.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include "check.h"
#include "meshgen.h"

static char dir[64];

/* ------------------------------------------------------------------ writers of the test files */

static void write_obj(const q2n_mesh *m, const char *path, int tags)
{
    FILE *f = fopen(path, "w");
    if (!f) return;
    for (int v = 0; v < m->nv; v++) fprintf(f, "v %.17g %.17g %.17g\n", m->pos[3 * v], m->pos[3 * v + 1], m->pos[3 * v + 2]);
    if (tags) fputs("t crease 2/1/0 1 2 4.0\nt corner 1/1/0 3 2.5\nt crease 2/1/0 2 3 1.0\n", f);
    for (int k = 0; k < m->nf; k++) {
        fputc('f', f);
        for (int i = m->face_start[k]; i < m->face_start[k + 1]; i++) fprintf(f, " %d", m->face_vert[i] + 1);
        fputc('\n', f);
    }
    if (tags) fputs("t interpolateboundary 1/0/0 1\n", f);
    fclose(f);
}

static void write_off(const q2n_mesh *m, const char *path)
{
    FILE *f = fopen(path, "w");
    if (!f) return;
    fprintf(f, "OFF\n# written by test_readers\n%d %d 0\n", m->nv, m->nf);
    for (int v = 0; v < m->nv; v++) fprintf(f, "%.17g %.17g %.17g\n", m->pos[3 * v], m->pos[3 * v + 1], m->pos[3 * v + 2]);
    for (int k = 0; k < m->nf; k++) {
        fprintf(f, "%d", q2n_face_size(m, k));
        for (int i = m->face_start[k]; i < m->face_start[k + 1]; i++) fprintf(f, " %d", m->face_vert[i]);
        fputs(k % 2 ? " 255 0 0\n" : "\n", f);   /* a colour on every other face: ignored */
    }
    fclose(f);
}

static void put_be_le(FILE *f, const void *p, int n, int big)
{
    const unsigned char *b = p;
    unsigned one = 1;
    int host_big = *(unsigned char *)&one == 0;
    for (int i = 0; i < n; i++) fputc(b[big != host_big ? n - 1 - i : i], f);
}

/* format: 0 ascii, 1 binary little endian, 2 binary big endian; flt: float coordinates */
static void write_ply(const q2n_mesh *m, const char *path, int format, int flt)
{
    static const char *fmt[] = {"ascii", "binary_little_endian", "binary_big_endian"};
    FILE *f = fopen(path, "wb");
    if (!f) return;
    fprintf(f, "ply\nformat %s 1.0\ncomment test_readers\nelement vertex %d\n", fmt[format], m->nv);
    fprintf(f, "property %s x\nproperty %s y\nproperty %s z\nproperty uchar red\n", flt ? "float" : "double",
            flt ? "float" : "double", flt ? "float" : "double");
    fprintf(f, "element face %d\nproperty list uchar int vertex_indices\nelement edge 1\nproperty int vertex1\n"
               "property int vertex2\nend_header\n", m->nf);
    for (int v = 0; v < m->nv; v++) {
        if (format == 0) { fprintf(f, "%.17g %.17g %.17g 7\n", m->pos[3 * v], m->pos[3 * v + 1], m->pos[3 * v + 2]); continue; }
        for (int c = 0; c < 3; c++) {
            double d = m->pos[3 * v + c];
            float x = (float)d;
            if (flt) put_be_le(f, &x, 4, format == 2);
            else put_be_le(f, &d, 8, format == 2);
        }
        fputc(7, f);
    }
    for (int k = 0; k < m->nf; k++) {
        unsigned char n = (unsigned char)q2n_face_size(m, k);
        if (format == 0) fprintf(f, "%d", n);
        else fputc(n, f);
        for (int i = m->face_start[k]; i < m->face_start[k + 1]; i++) {
            int x = m->face_vert[i];
            if (format == 0) fprintf(f, " %d", x);
            else put_be_le(f, &x, 4, format == 2);
        }
        if (format == 0) fputc('\n', f);
    }
    int e[2] = {0, 1};
    if (format == 0) fprintf(f, "%d %d\n", e[0], e[1]);
    else { put_be_le(f, &e[0], 4, format == 2); put_be_le(f, &e[1], 4, format == 2); }
    fclose(f);
}

/* ------------------------------------------------------------------ checks */

static int same_mesh(const q2n_mesh *a, const q2n_mesh *b)
{
    return a && b && a->nv == b->nv && a->nf == b->nf && !memcmp(a->pos, b->pos, 3 * sizeof(double) * (size_t)a->nv) &&
           !memcmp(a->face_start, b->face_start, sizeof(int) * (size_t)(a->nf + 1)) &&
           !memcmp(a->face_vert, b->face_vert, sizeof(int) * (size_t)a->face_start[a->nf]);
}

/* Every format of mesh m reads back to m itself (the OBJ reader's result). */
static void formats_agree(const char *what, q2n_mesh *m, int flt_exact)
{
    char obj[128], path[128];
    snprintf(obj, sizeof obj, "%s/m.obj", dir);
    write_obj(m, obj, 0);
    q2n_mesh *ref = NULL, *r = NULL;
    q2n_error err;
    q2n_mesh_read_info info;
    CHECK(q2n_mesh_read(obj, &ref, &info, &err) == Q2N_OK && !strcmp(info.format, "obj"), "%s: obj: %s", what, err.message);
    static const char *const names[] = {"m.off", "m_a.ply", "m_le.ply", "m_be.ply", "m_lef.ply", "m_bef.ply"};
    for (int i = 0; i < 6; i++) {
        if (i >= 4 && !flt_exact) continue;
        snprintf(path, sizeof path, "%s/%s", dir, names[i]);
        if (i == 0) write_off(m, path);
        else write_ply(m, path, i == 1 ? 0 : (i - 2) % 2 + 1, i >= 4);
        q2n_status st = q2n_mesh_read(path, &r, &info, &err);
        CHECK(st == Q2N_OK, "%s: %s: %s", what, names[i], err.message);
        CHECK(!strcmp(info.format, i == 0 ? "off" : "ply"), "%s: %s read as %s", what, names[i], info.format);
        CHECK(same_mesh(ref, r), "%s: %s gives a different mesh than the OBJ", what, names[i]);
        q2n_mesh_free(r);
        r = NULL;
    }
    q2n_mesh_free(ref);
}

/* ------------------------------------------------------------------ STL */

static void put_f32(FILE *f, double x)
{
    float v = (float)x;
    unsigned char b[4];
    uint32_t u;
    memcpy(&u, &v, 4);
    for (int i = 0; i < 4; i++) b[i] = (unsigned char)(u >> (8 * i));
    fwrite(b, 1, 4, f);
}

/* Triangle mesh m as binary STL (a header starting with "solid", as many exporters write) or ASCII
 * STL (%.17g: the same doubles). */
static void write_stl(const q2n_mesh *m, const char *path, int binary)
{
    FILE *f = fopen(path, binary ? "wb" : "w");
    if (!f) return;
    if (binary) {
        char head[80];
        memset(head, ' ', sizeof head);
        memcpy(head, "solid exported by a CAD system", 30);
        fwrite(head, 1, 80, f);
        uint32_t n = (uint32_t)m->nf;
        unsigned char nb[4] = {(unsigned char)n, (unsigned char)(n >> 8), (unsigned char)(n >> 16), (unsigned char)(n >> 24)};
        fwrite(nb, 1, 4, f);
    } else {
        fprintf(f, "solid part\n");
    }
    for (int k = 0; k < m->nf; k++) {
        if (binary) for (int c = 0; c < 3; c++) put_f32(f, 0.0);
        else fprintf(f, "  facet normal 0 0 1\n    outer loop\n");
        for (int i = 0; i < 3; i++) {
            const double *p = q2n_mesh_vpos(m, m->face_vert[m->face_start[k] + i]);
            if (binary) for (int c = 0; c < 3; c++) put_f32(f, p[c]);
            else fprintf(f, "      vertex %.17g %.17g %.17g\n", p[0], p[1], p[2]);
        }
        if (binary) fwrite("\0\0", 1, 2, f);
        else fprintf(f, "    endloop\n  endfacet\n");
    }
    if (!binary) fprintf(f, "endsolid part\n");
    fclose(f);
}

/* A quad torus with float-exact coordinates cut into triangles, as OBJ, binary STL and ASCII STL:
 * the STL readers weld the facets' corners back into the OBJ's vertices (the same count; every face
 * the same corner positions in the same order), and `quad2nurbs sample --pair-triangles` prints the
 * same bytes for all three. */
static void stl_agrees(void)
{
    q2n_mesh *q = mg_torus(6, 5, 3.0, 1.0, 0.0, 0, 1u);
    if (!q) { CHECK(0, "torus"); return; }
    int nf = 2 * q->nf, *fs = malloc(sizeof(int) * ((size_t)nf + 1)), *fv = malloc(sizeof(int) * 3 * (size_t)nf);
    for (int i = 0; i < 3 * q->nv; i++) q->pos[i] = (double)(float)q->pos[i];
    for (int k = 0; k < q->nf; k++) {
        const int *c = q->face_vert + q->face_start[k];
        int t[6] = {c[0], c[1], c[2], c[2], c[3], c[0]};
        memcpy(fv + 6 * k, t, sizeof t);
    }
    for (int k = 0; k <= nf; k++) fs[k] = 3 * k;
    q2n_mesh *t = NULL;
    q2n_error err;
    CHECK(q2n_mesh_from_arrays(q->nv, q->pos, nf, fs, fv, "tri", &t, &err) == Q2N_OK, "triangulated torus: %s", err.message);
    free(fs);
    free(fv);
    char obj[128], stl[2][128];
    snprintf(obj, sizeof obj, "%s/t.obj", dir);
    write_obj(t, obj, 0);
    for (int b = 0; b < 2; b++) {
        snprintf(stl[b], sizeof stl[b], "%s/%s", dir, b ? "t_bin.stl" : "t_ascii.stl");
        write_stl(t, stl[b], b);
        q2n_mesh *r = NULL;
        q2n_mesh_read_info info;
        q2n_status st = q2n_mesh_read(stl[b], &r, &info, &err);
        CHECK(st == Q2N_OK && !strcmp(info.format, "stl"), "%s: %s", stl[b], err.message);
        int same = r && r->nv == t->nv && r->nf == t->nf;
        for (int k = 0; same && k < t->nf; k++)
            for (int i = 0; i < 3; i++)
                same &= !memcmp(q2n_mesh_vpos(r, r->face_vert[3 * k + i]), q2n_mesh_vpos(t, t->face_vert[3 * k + i]),
                                3 * sizeof(double));
        CHECK(same, "%s: not the triangulated torus (%d vertices, %d faces; want %d, %d)", stl[b], r ? r->nv : -1,
              r ? r->nf : -1, t->nv, t->nf);
        q2n_mesh_free(r);
    }
    char cmd[1024], out[3][4096];
    const char *files[3] = {obj, stl[0], stl[1]};
    for (int i = 0; i < 3; i++) {
        snprintf(cmd, sizeof cmd, "%s sample %s --pair-triangles --grid 2 | md5sum", chk_exe(), files[i]);
        FILE *p = popen(cmd, "r");
        out[i][0] = 0;
        if (p) { if (!fgets(out[i], sizeof out[i], p)) out[i][0] = 0; pclose(p); }
    }
    CHECK(out[0][0] && !strcmp(out[0], out[1]) && !strcmp(out[0], out[2]), "sample of OBJ / ASCII STL / binary STL: %s %s %s",
          out[0], out[1], out[2]);
    q2n_mesh_free(t);
    q2n_mesh_free(q);
}

static void expect_error(const char *name, const char *text, size_t len, q2n_status code, const char *needle)
{
    char path[128];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    if (f) { fwrite(text, 1, len, f); fclose(f); }
    q2n_mesh *m = (q2n_mesh *)1;
    q2n_error err = {0};
    q2n_status st = q2n_mesh_read(path, &m, NULL, &err);
    CHECK(st == code && m == NULL, "%s: status %d (want %d): %s", name, st, code, err.message);
    CHECK(strstr(err.message, needle) != NULL, "%s: message '%s' lacks '%s'", name, err.message, needle);
    CHECK(!strchr(err.message, '\n'), "%s: message has a newline", name);
}
#define EXPECT(name, text, code, needle) expect_error(name, text, sizeof text - 1, code, needle)

static void bad_stl(void)
{
    const char *tri = "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n";
    char buf[512];
    snprintf(buf, sizeof buf, "%sendsolid x\n", tri);
    q2n_mesh *m = NULL;
    q2n_error err;
    CHECK(q2n_mesh_parse_stl(buf, strlen(buf), "one.stl", &m, &err) == Q2N_OK && m && m->nv == 3 && m->nf == 1,
          "one facet: %s", err.message);
    q2n_mesh_free(m);
    const char *caps = "SOLID X\nFACET NORMAL 0 0 1\nOUTER LOOP\nVERTEX 0 0 0\nVERTEX 1 0 0\nVERTEX 0 1 0\nENDLOOP\nENDFACET\nENDSOLID X\n";
    CHECK(q2n_mesh_parse_stl(caps, strlen(caps), "caps.stl", &m, &err) == Q2N_OK && m && m->nf == 1, "capitals: %s", err.message);
    q2n_mesh_free(m);
    /* a UTF-8 byte order mark before "solid" (it was read as a binary header: "binary STL of
     * 808922674 facets"), and before a PLY's "ply" (it was "not a PLY file") */
    snprintf(buf, sizeof buf, "\xEF\xBB\xBF%sendsolid x\n", tri);
    m = NULL;
    CHECK(q2n_mesh_parse_stl(buf, strlen(buf), "bom.stl", &m, &err) == Q2N_OK && m && m->nf == 1, "STL after a BOM: %s",
          err.message);
    q2n_mesh_free(m);
    const char *ply = "\xEF\xBB\xBFply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                      "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    m = NULL;
    CHECK(q2n_mesh_parse_ply(ply, strlen(ply), "bom.ply", &m, &err) == Q2N_OK && m && m->nf == 1 && m->nv == 3,
          "PLY after a BOM: %s", err.message);
    q2n_mesh_free(m);
    EXPECT("two.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid\n",
           Q2N_ERR_TOPOLOGY, "two.stl:2: a facet with 2 vertices");
    EXPECT("four.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\n",
           Q2N_ERR_TOPOLOGY, "four.stl:7: a facet with more than 3 vertices");
    EXPECT("nan.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex nan 0 0\nvertex 0 1 0\n",
           Q2N_ERR_PARSE, "nan.stl:5: non-finite coordinate");
    EXPECT("word.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\n"
           "endfacet\nfoo\n", Q2N_ERR_PARSE, "word.stl:9: unexpected 'foo'");
    EXPECT("open.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n", Q2N_ERR_PARSE,
           "open.stl:2: the file ends inside a facet");
    EXPECT("empty.stl", "solid x\nendsolid x\n", Q2N_ERR_TOPOLOGY, "empty.stl: no facets");
    EXPECT("short.stl", "not an stl", Q2N_ERR_PARSE, "short.stl: not an STL file");
    EXPECT("same.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 0\nendloop\n"
           "endfacet\nendsolid\n", Q2N_ERR_TOPOLOGY, "same.stl:2:");
    /* binary: a truncated file, a NaN corner (the facet and its byte) */
    unsigned char b[84 + 50];
    memset(b, 0, sizeof b);
    b[80] = 2; /* two facets declared, one present */
    expect_error("trunc.stl", (const char *)b, sizeof b, Q2N_ERR_PARSE, "binary STL of 2 facets should be 184 bytes, the file has 134");
    b[80] = 1;
    float nanf_ = NAN;
    memcpy(b + 84 + 12 + 12 + 4, &nanf_, 4); /* facet 0, vertex 1, y */
    expect_error("bnan.stl", (const char *)b, sizeof b, Q2N_ERR_PARSE, "bnan.stl: facet 0 (byte 112): non-finite");
}

static void bad_files(void)
{
    const char *quad = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n";
    char t[512];
    snprintf(t, sizeof t, "OFF\n4 1 0\n0 0 0\n1 0 0\n1 x 0\n0 1 0\n4 0 1 2 3\n");
    expect_error("num.off", t, strlen(t), Q2N_ERR_PARSE, "num.off:5: bad number 'x'");
    snprintf(t, sizeof t, "OFF\n4 1 0\n%s4 0 1 2 9\n", quad);
    expect_error("range.off", t, strlen(t), Q2N_ERR_TOPOLOGY, "range.off:7: face index 9 out of range");
    snprintf(t, sizeof t, "OFF 4 2 0\n%s4 0 1 2 3\n", quad);
    expect_error("short.off", t, strlen(t), Q2N_ERR_PARSE, "ends after 1 of 2 faces");
    snprintf(t, sizeof t, "OFF\n4 1 0\n%s2 0 1\n", quad);
    expect_error("two.off", t, strlen(t), Q2N_ERR_TOPOLOGY, "two.off:7: face with only 2 vertices");
    snprintf(t, sizeof t, "OFF\n4 1 0\n0 0 0\n1 0 nan\n1 1 0\n0 1 0\n4 0 1 2 3\n");
    expect_error("nan.off", t, strlen(t), Q2N_ERR_PARSE, "nan.off:4: non-finite coordinate");
    snprintf(t, sizeof t, "OFF\n4 1 0\n%s4 0 1 2 3\n4 0 1 2 3\n", quad);
    expect_error("extra.off", t, strlen(t), Q2N_ERR_PARSE, "extra.off:8: data after the last of 1 faces");
    snprintf(t, sizeof t, "OFF\n4 1 0\n%s4 0 1 1 3\n", quad);
    expect_error("rep.off", t, strlen(t), Q2N_ERR_TOPOLOGY, "rep.off:7:");
    EXPECT("dim.off", "4OFF\n1 1 0\n0 0 0 0\n", Q2N_ERR_UNSUPPORTED, "only 3-D OFF");
    EXPECT("bin.off", "OFF BINARY\n", Q2N_ERR_UNSUPPORTED, "binary OFF");
    EXPECT("cnt.off", "OFF\n4 x 0\n", Q2N_ERR_PARSE, "cnt.off:2: bad face count 'x'");
    /* PLY */
    const char *hdr = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    snprintf(t, sizeof t, "%s0 0 0\n1 0 0\n1 1 zz\n0 1 0\n4 0 1 2 3\n", hdr);
    expect_error("num.ply", t, strlen(t), Q2N_ERR_PARSE, "num.ply:12: bad number 'zz'");
    snprintf(t, sizeof t, "%s%s4 0 1 2 4\n", hdr, quad);
    expect_error("range.ply", t, strlen(t), Q2N_ERR_TOPOLOGY, "range.ply:14: face index 4 out of range");
    snprintf(t, sizeof t, "%s%s", hdr, quad);
    expect_error("short.ply", t, strlen(t), Q2N_ERR_PARSE, "ends inside face 0 of 1");
    EXPECT("hdr.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nfrobnicate\nend_header\n", Q2N_ERR_PARSE,
           "hdr.ply:5: unknown header keyword 'frobnicate'");
    EXPECT("noend.ply", "ply\nformat ascii 1.0\n", Q2N_ERR_PARSE, "no \"end_header\"");
    EXPECT("noz.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n",
           Q2N_ERR_PARSE, "lacks a scalar property x, y or z");
    EXPECT("fmt.ply", "ply\nformat ascii 2.0\nend_header\n", Q2N_ERR_PARSE, "fmt.ply:2:");
    /* binary: little endian floats, a NaN in vertex 2, then a file cut inside the face */
    {
        char b[400];
        const char *h = "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                        "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
        size_t n = strlen(h);
        memcpy(b, h, n);
        float v[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
        memcpy(b + n, v, sizeof v);
        unsigned char cnt = 4;
        int idx[4] = {0, 1, 2, 3};
        memcpy(b + n + sizeof v, &cnt, 1);
        memcpy(b + n + sizeof v + 1, idx, 8); /* two of the four indices */
        expect_error("cut.ply", b, n + sizeof v + 9, Q2N_ERR_PARSE, "face 0 (byte");
        v[7] = NAN;
        memcpy(b + n, v, sizeof v);
        memcpy(b + n + sizeof v + 1, idx, sizeof idx);
        char want[64];
        snprintf(want, sizeof want, "vertex 2 (byte %zu): non-finite", n + 7 * sizeof(float));
        expect_error("nan.ply", b, n + sizeof v + 1 + sizeof idx, Q2N_ERR_PARSE, want);
    }
}

/* OBJ tags: counted, named, ignored; found by content when the name has no known extension. */
static void tags_and_magic(q2n_mesh *m)
{
    char a[128], b[128];
    snprintf(a, sizeof a, "%s/tags.obj", dir);
    snprintf(b, sizeof b, "%s/plain.obj", dir);
    write_obj(m, a, 1);
    write_obj(m, b, 0);
    q2n_mesh *ma = NULL, *mb = NULL;
    q2n_mesh_read_info ia, ib;
    q2n_error err;
    CHECK(q2n_mesh_read(a, &ma, &ia, &err) == Q2N_OK, "tags: %s", err.message);
    CHECK(q2n_mesh_read(b, &mb, &ib, &err) == Q2N_OK, "plain: %s", err.message);
    CHECK(same_mesh(ma, mb), "tags change the mesh");
    CHECK(ia.tags == 4 && ia.tag_line == m->nv + 1 && !strcmp(ia.tag_names, "crease, corner, interpolateboundary"),
          "tags counted %ld (line %ld, '%s'), want 4 at line %d", ia.tags, ia.tag_line, ia.tag_names, m->nv + 1);
    CHECK(ib.tags == 0, "no tags in the plain file");
    q2n_mesh_free(ma);
    q2n_mesh_free(mb);
    /* no extension: the first line decides */
    char p[128];
    snprintf(p, sizeof p, "%s/mesh.dat", dir);
    write_ply(m, p, 1, 0);
    q2n_mesh *mc = NULL;
    q2n_mesh_read_info ic;
    CHECK(q2n_mesh_read(p, &mc, &ic, &err) == Q2N_OK && !strcmp(ic.format, "ply"), "PLY by magic: %s", err.message);
    q2n_mesh_free(mc);
    write_off(m, p);
    CHECK(q2n_mesh_read(p, &mc, &ic, &err) == Q2N_OK && !strcmp(ic.format, "off"), "OFF by magic: %s", err.message);
    q2n_mesh_free(mc);
    snprintf(p, sizeof p, "%s/MESH.OFF", dir);
    write_off(m, p);
    CHECK(q2n_mesh_read(p, &mc, &ic, &err) == Q2N_OK && !strcmp(ic.format, "off"), "upper-case .OFF: %s", err.message);
    q2n_mesh_free(mc);
}

/* The executable gives the same bytes for every format: `sample` and a STEP file. */
static void same_bytes_cli(void)
{
    const char *exe = chk_exe();
    if (access(exe, X_OK) != 0) { CHECK(0, "%s not built", exe); return; }
    static const char *const in[] = {"m.obj", "m.off", "m_a.ply", "m_le.ply", "m_be.ply"};
    char cmd[1024], *ref = NULL, *refstep = NULL;
    size_t lref = 0, lstep = 0;
    for (int i = 0; i < 5; i++) {
        snprintf(cmd, sizeof cmd, "mkdir -p %s/o%d && SOURCE_DATE_EPOCH=1700000000 %s sample --grid 3 %s/%s > %s/o%d/s.txt && "
                 "SOURCE_DATE_EPOCH=1700000000 %s -q %s/%s -o %s/o%d/m.step", dir, i, exe, dir, in[i], dir, i, exe, dir,
                 in[i], dir, i);
        int rc = system(cmd);
        CHECK(rc == 0, "%s: exit %d", in[i], rc);
        char p[160];
        size_t l = 0, ls = 0;
        snprintf(p, sizeof p, "%s/o%d/s.txt", dir, i);
        char *s = chk_slurp(p, &l);
        snprintf(p, sizeof p, "%s/o%d/m.step", dir, i);
        char *st = chk_slurp(p, &ls);
        if (i == 0) { ref = s; refstep = st; lref = l; lstep = ls; continue; }
        CHECK(s && ref && l == lref && l > 0 && !memcmp(s, ref, l), "%s: `sample` output differs from the OBJ's", in[i]);
        CHECK(st && refstep && ls == lstep && ls > 0 && !memcmp(st, refstep, ls), "%s: STEP differs from the OBJ's", in[i]);
        free(s);
        free(st);
    }
    free(ref);
    free(refstep);
}

int main(void)
{
    /* a folder in the scratch folder (relative to the repository, like the runner's) */
    if (chk_tmpdir(dir, sizeof dir, "readers") != 0) { CHECK(0, "no scratch folder %s", dir); CHECK_DONE("test_readers"); }
    q2n_mesh *torus = mg_torus(12, 8, 3.0, 1.0, 0.1, 1, 7u);
    formats_agree("jittered torus", torus, 0);
    /* float-exact coordinates: the float PLY variants must agree too */
    q2n_mesh *ft = mg_torus(6, 5, 3.0, 1.0, 0.0, 0, 1u);
    for (int i = 0; ft && i < 3 * ft->nv; i++) ft->pos[i] = (double)(float)ft->pos[i];
    formats_agree("float torus", ft, 1);
    const char *pawn = chk_shared_mesh("osd_catmark_rook.obj");
    if (pawn) {
        q2n_mesh *r = NULL;
        q2n_error err;
        if (q2n_mesh_read(pawn, &r, NULL, &err) == Q2N_OK) formats_agree("rook (triangles and quads)", r, 0);
        q2n_mesh_free(r);
    } else {
        SKIP("osd_catmark_rook.obj: ../shared/meshes absent");
    }
    bad_files();
    bad_stl();
    stl_agrees();
    tags_and_magic(torus);
    formats_agree("jittered torus", torus, 0); /* the files the executable reads */
    same_bytes_cli();
    q2n_mesh_free(torus);
    q2n_mesh_free(ft);
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd)) {}
    CHECK_DONE("test_readers");
}
