/* mesh.h — polygon mesh input and half-edge topology (pipeline stage 1).
 *
 * A q2n_mesh owns its vertex positions and faces (CSR layout) and, once built,
 * a half-edge topology: half-edge h of face f at corner i runs from
 * face_vert[face_start[f]+i] to face_vert[face_start[f]+(i+1)%n]; the
 * half-edge index equals that CSR position, so for an all-quad mesh h = 4f+i.
 * Every constructor validates: manifold edges and vertices, consistent
 * orientation, no repeated vertex in a face, finite coordinates, at least one
 * face, and (relative to the bounding-box diagonal, mesh_policy.h) no degenerate
 * edge, no quad with coincident opposite corners, no face of (near) zero area.  Errors name the file and line (OBJ input)
 * or the element index.  Everything downstream (param, patch, acc, fit,
 * export) reads meshes through this header only. */
#ifndef Q2N_MESH_MESH_H
#define Q2N_MESH_MESH_H

#include <stddef.h>

#include "core/error.h"

typedef struct q2n_mesh {
    int nv;           /* vertices */
    int nf;           /* faces */
    double *pos;      /* 3*nv coordinates, xyz xyz ... */
    int *face_start;  /* nf+1 offsets into face_vert */
    int *face_vert;   /* vertex indices of each face, in file order */
    int *face_line;   /* nf: OBJ line of each face, or of its parent face after subdivision
                         (0 if not from a file) */

    /* half-edge topology (always present after a successful constructor) */
    int nh;           /* number of half-edges = face_start[nf] */
    int *he_face;     /* nh: face of each half-edge */
    int *he_twin;     /* nh: opposite half-edge, -1 on the boundary */
    int *he_edge;     /* nh: undirected edge index 0..ne-1 */
    int ne;           /* undirected edges */
    int *edge_he;     /* ne: one half-edge of each edge (the one with he < twin, or the boundary one) */
    int *vert_he;     /* nv: first outgoing half-edge of the vertex fan (see q2n_mesh_rotate);
                         for boundary vertices the outgoing boundary half-edge; -1 if isolated */
    int *valence;     /* nv: number of incident edges */
    int *vert_nfaces; /* nv: number of incident faces */
    unsigned char *vert_boundary; /* nv: 1 on the boundary */
    int n_boundary_loops;
    int all_quads;    /* 1 when every face has 4 vertices */
    char name[256];   /* file name (for messages) */
    char derived[18]; /* "" for the mesh as read, else what made it ("subdivided", "filled", at most
                         "paired and filled"): messages then say "face 13 (of the subdivided
                         mesh)" (q2n_mesh_of) */
} q2n_mesh;

/* Read a Wavefront OBJ file: `v x y z [w]`, `f a b c ...` with a, a/b, a//c, a/b/c forms and
 * negative (relative) indices; comments, vt, vn, vp, g, o, s, usemtl, mtllib, l ignored.
 * Fails with Q2N_ERR_IO / PARSE / TOPOLOGY / GEOMETRY and "file:line: reason". */
q2n_status q2n_mesh_read_obj(const char *path, q2n_mesh **out, q2n_error *err);

/* Same, from a text buffer (name is used in messages). */
q2n_status q2n_mesh_parse_obj(const char *text, size_t len, const char *name, q2n_mesh **out,
                              q2n_error *err);

/* What a reader saw besides the mesh, for the caller to report. */
typedef struct q2n_mesh_read_info {
    char format[8];       /* "obj", "off" or "ply" */
    long tags;            /* OBJ `t` lines ignored (OpenSubdiv tags; sharp features are not supported) */
    long tag_line;        /* the line of the first one */
    char tag_names[80];   /* their distinct names, e.g. "crease, corner" */
} q2n_mesh_read_info;

/* Any supported format, by extension (.obj, .off, .ply, .stl, any case), else by the first line ("ply",
 * "OFF", "COFF", ...), else OBJ; same validation and "file:line: reason" errors for all (binary
 * PLY: "file: face K (byte B): reason").  info may be NULL. */
q2n_status q2n_mesh_read(const char *path, q2n_mesh **out, q2n_mesh_read_info *info, q2n_error *err);
/* The OBJ reader with its info (tags). */
q2n_status q2n_mesh_read_obj_info(const char *path, q2n_mesh **out, q2n_mesh_read_info *info, q2n_error *err);
q2n_status q2n_mesh_parse_obj_info(const char *text, size_t len, const char *name, q2n_mesh **out,
                                   q2n_mesh_read_info *info, q2n_error *err);
/* ASCII OFF: optional keyword line [ST][C][N]OFF, "NV NF NE", NV lines "x y z [more numbers:
 * normal, colour, texture]", NF lines "n i_1 .. i_n [colour]" with 0-based indices; '#' comments. */
q2n_status q2n_mesh_parse_off(const char *text, size_t len, const char *name, q2n_mesh **out, q2n_error *err);
/* PLY 1.0, ascii / binary_little_endian / binary_big_endian: element vertex with x, y, z (any
 * numeric type), element face with the list vertex_indices (or vertex_index); other elements and
 * properties are skipped. */
q2n_status q2n_mesh_parse_ply(const char *data, size_t len, const char *name, q2n_mesh **out, q2n_error *err);
/* STL, binary (84 + 50 N bytes) or ASCII ("solid" ... "endsolid"): every facet a triangle, corners with
 * the same coordinates welded into one vertex (stl_reader.c); errors name the facet (ASCII: its line). */
q2n_status q2n_mesh_parse_stl(const char *data, size_t len, const char *name, q2n_mesh **out, q2n_error *err);

/* Build (and validate) a mesh from borrowed arrays: face k has vertices
 * face_vert[face_start[k] .. face_start[k+1]-1]. Arrays are copied. */
q2n_status q2n_mesh_from_arrays(int nv, const double *pos, int nf, const int *face_start,
                                const int *face_vert, const char *name, q2n_mesh **out,
                                q2n_error *err);

/* Same as q2n_mesh_from_arrays, with the source line of each face (face_line[k] > 0, or NULL)
 * so that validation errors read "name:LINE: reason"; face_line is copied into the mesh. */
q2n_status q2n_mesh_from_arrays_lines(int nv, const double *pos, int nf, const int *face_start,
                                      const int *face_vert, const int *face_line, const char *name,
                                      q2n_mesh **out, q2n_error *err);

void q2n_mesh_free(q2n_mesh *m); /* NULL is a no-op */

/* Where a message about vertex v points: "NAME:LINE" (the input line of a face at v), or
 * "NAME: face F" when the mesh has no lines; the message goes on with "vertex V (of this face)". */
void q2n_mesh_vertex_where(const q2n_mesh *m, int v, char *buf, size_t n);
/* " of the subdivided mesh" (m->derived; paren: " (of the subdivided mesh)") or "": what a message
 * adds to the face or vertex it numbers when the numbers are not the input's. */
void q2n_mesh_of(const q2n_mesh *m, int paren, char *buf, size_t n);
/* Where a message about face f points: "NAME:LINE" (its input line), or "NAME"; the message goes on
 * with ": face F ...", as the validation messages do. */
void q2n_mesh_face_where(const q2n_mesh *m, int f, char *buf, size_t n);

/* Internal consistency check of the half-edge structure (tests): Q2N_OK or a message. */
q2n_status q2n_mesh_check(const q2n_mesh *m, q2n_error *err);

/* Write an OBJ (v and f records only), e.g. after subdivision. Atomic (temp file + rename). */
q2n_status q2n_mesh_write_obj(const q2n_mesh *m, const char *path, q2n_error *err);

/* Bounding-box diagonal length of the vertices that faces use (the scale every relative
 * tolerance uses); no overflow inside the double range. */
double q2n_mesh_bbox_diag(const q2n_mesh *m);

/* Vector area of face f (Newell; its direction is the face's normal, its length the area of a
 * planar face). */
void q2n_mesh_face_area(const q2n_mesh *m, int f, double a[3]);

/* The mesh's frame: centre of the bounding box of the vertices faces use, and its diagonal as
 * mant * 2^exp with mant in [1, 2 sqrt 3) (no overflow even where the diagonal exceeds the double
 * range; mant = 1, exp = 0 when all coincide). */
void q2n_mesh_frame(const q2n_mesh *m, double centre[3], double *mant, int *exp);

/* Move the mesh into its frame, in place: p <- (p - centre) / (mant * 2^exp) for every vertex a
 * face uses, so the bounding-box diagonal is 1 (up to rounding) whatever the input's scale, and
 * meshes that differ by a power-of-two scale give bit-identical coordinates.  Unreferenced
 * vertices keep their coordinates.  Everything downstream is affine-equivariant, so results map
 * back as centre + 2^exp * (mant * x) (derivatives: 2^exp * (mant * d)). */
void q2n_mesh_normalize(q2n_mesh *m, double centre[3], double *mant, int *exp);

/* Self-crossing (bow-tie) quads: seen along the quad's vector area, two of its corners turn
 * against it (mesh_policy.h), so two opposite sides cross.  Fine as a Catmull–Clark control face,
 * not as the face of an interpolating patch (its boundary curves would cross): the model checks
 * the mesh the augmented surface is built on.  Q2N_ERR_GEOMETRY naming the face and line. */
q2n_status q2n_mesh_check_crossing(const q2n_mesh *m, q2n_error *err);

/* Catmull–Clark subdivision, `steps` times (n-gons allowed; boundary edges follow the cubic
 * B-spline boundary curve, valence-2 boundary vertices stay fixed as corners).  After one step
 * every face is a quad.  Vertex order: old vertices first (same indices), then one face point per
 * old face, then one edge point per old edge; face order: each old face's sub-quads in corner order,
 * the sub-quad at corner i being (v_i, e_i, f, e_{i-1}) so u runs along the old edge i. */
q2n_status q2n_mesh_subdivide(const q2n_mesh *m, int steps, q2n_mesh **out, q2n_error *err);

/* Triangles paired into quads (pair.c): the shared edge of two triangles is removed where the quad
 * they make is convex with a margin and the two are not bent far apart (mesh_policy.h), the best
 * shaped quads first, then more through augmenting paths.  Face order: the input's, each quad in the place of its lower-numbered
 * triangle (the other one dropped), starting at that triangle's first vertex; other faces as they
 * were, with their OBJ lines (a quad takes its first triangle's).  *paired: quads made; *left:
 * triangles left (either may be NULL).  Vertices keep their indices. */
q2n_status q2n_mesh_pair_triangles(const q2n_mesh *m, q2n_mesh **out, int *paired, int *left, q2n_error *err);
/* How many pairs q2n_mesh_pair_triangles would make (without building the mesh), and the mesh's
 * triangles (may be NULL); -1 when out of memory. */
int q2n_mesh_pair_count(const q2n_mesh *m, int *triangles);

/* Faces of an even number n >= 6 of sides filled with quads (fill.c): a ring of n quads inside the
 * polygon and an a x (n/2 - a) grid of quads inside the ring, on new vertices at their discrete
 * harmonic positions, a and the ring's start those of the best-shaped quads.  Odd polygons of 5 or
 * more sides are first paired by strips of quads between them (each strip quad split in two, each
 * polygon a vertex more, on the crossed edges by the four-point rule), then filled; an odd polygon
 * without a strip to another is left as it is.  Face order: the input's, each filled face replaced
 * in place by its ring (quad k from the polygon's vertex s + k) and then its grid, each split strip
 * quad by its two halves, all with the face's OBJ line; other faces as they were; the new vertices
 * after the input's, which keep their indices.  A face
 * whose fill would have a corner turning against the face's vector area fails (Q2N_ERR_GEOMETRY,
 * naming it).  *filled: faces filled; *quads: quads made (either may be NULL). */
q2n_status q2n_mesh_fill_ngons(const q2n_mesh *m, q2n_mesh **out, int *filled, int *quads, q2n_error *err);
/* How many faces of at least min_sides sides q2n_mesh_fill_ngons would fill (odd ones included). */
int q2n_mesh_fill_count(const q2n_mesh *m, int min_sides);

/* The same mesh with every vertex moved to its Catmull–Clark limit position (the rules of
 * q2n_mesh_subdivide, boundaries as infinitely sharp creases; subdivide.c for the masks): an
 * interpolant of the result passes through points of the subdivision surface.  Every face around an
 * interior vertex must be a quad (Q2N_ERR_UNSUPPORTED naming the face otherwise). */
q2n_status q2n_mesh_limit_points(const q2n_mesh *m, q2n_mesh **out, q2n_error *err);

/* The mesh's isotropic frame (frame.c): the symmetric linear map A of determinant 1 under which the
 * edges of the faces around each vertex are most nearly isotropic in its tangent plane, in the
 * least-squares sense over all vertices (docs/extraordinary.md, "The isotropic frame").  A mesh
 * that is the image of a well-shaped one under a linear map S gets A = S^-1 up to a rotation.
 * Returns A's condition number (its largest stretch over its smallest; 1 and A = I where the
 * estimate fails); Ainv its inverse. */
double q2n_mesh_isotropic_frame(const q2n_mesh *m, double A[3][3], double Ainv[3][3]);

/* A copy of m with every vertex p mapped to A p (validated again: Q2N_ERR_GEOMETRY where the map
 * makes an edge or a face degenerate). */
q2n_status q2n_mesh_mapped(const q2n_mesh *m, const double A[3][3], q2n_mesh **out, q2n_error *err);

/* The regions of a set of faces (in_set[f] != 0) joined by their corners: root[v] (nv ints) the
 * smallest vertex of the region whose faces vertex v is a corner of, v itself where it is a corner of
 * none.  The extraordinary regions' construction solves each region apart (patch/ev_fair*.c) and the
 * model chooses their gluing per region (api/model.c). */
void q2n_mesh_corner_regions(const q2n_mesh *m, const char *in_set, int *root);

/* ---- half-edge navigation (all O(1)) ---- */
static inline int q2n_he_face(const q2n_mesh *m, int h) { return m->he_face[h]; }
static inline int q2n_he_twin(const q2n_mesh *m, int h) { return m->he_twin[h]; }
static inline int q2n_face_size(const q2n_mesh *m, int f) { return m->face_start[f + 1] - m->face_start[f]; }
static inline int q2n_he_next(const q2n_mesh *m, int h)
{
    int f = m->he_face[h], s = m->face_start[f], n = m->face_start[f + 1] - s;
    return s + (h - s + 1) % n;
}
static inline int q2n_he_prev(const q2n_mesh *m, int h)
{
    int f = m->he_face[h], s = m->face_start[f], n = m->face_start[f + 1] - s;
    return s + (h - s + n - 1) % n;
}
static inline int q2n_he_origin(const q2n_mesh *m, int h) { return m->face_vert[h]; }
static inline int q2n_he_dest(const q2n_mesh *m, int h) { return m->face_vert[q2n_he_next(m, h)]; }
/* Next outgoing half-edge around the origin vertex, counter-clockwise (same side as the face
 * normal of a counter-clockwise face): twin(prev(h)); -1 when that crosses the boundary. */
static inline int q2n_mesh_rotate(const q2n_mesh *m, int h)
{
    return m->he_twin[q2n_he_prev(m, h)];
}
/* Inverse of q2n_mesh_rotate: next(twin(h)); -1 when h is a boundary half-edge. */
static inline int q2n_mesh_rotate_back(const q2n_mesh *m, int h)
{
    int t = m->he_twin[h];
    return t < 0 ? -1 : q2n_he_next(m, t);
}
/* Outgoing half-edge of face f at corner i (the edge v_i -> v_{i+1}). */
static inline int q2n_face_he(const q2n_mesh *m, int f, int i) { return m->face_start[f] + i; }
static inline const double *q2n_mesh_vpos(const q2n_mesh *m, int v) { return m->pos + 3 * (size_t)v; }

/* The outgoing half-edge that continues a section polyline straight through vertex v = dest(h_in)
 * (h_in arrives at v):
 *   - v interior of valence 4: the opposite outgoing edge, two rotations away from twin(h_in);
 *   - v on the boundary with valence 3 and h_in a boundary half-edge: the other boundary edge
 *     (the outgoing boundary half-edge vert_he[v]);
 *   - otherwise -1: the polyline ends there (boundary) or is not defined (extraordinary vertex). */
int q2n_mesh_continue(const q2n_mesh *m, int h_in);

/* Edge ribbons: chains of pairwise opposite edges of quads.  ribbon[e] in 0..nribbons-1 for each
 * undirected edge (non-quad faces do not link their edges).  Caller frees *ribbon. */
q2n_status q2n_mesh_ribbons(const q2n_mesh *m, int **ribbon, int *nribbons, q2n_error *err);

#endif
