/* topology.c — builds and validates the half-edge structure of a q2n_mesh (see mesh.h).
 *
 * Construction order: face sizes and indices, finite coordinates, then per face (face order) a
 * repeated vertex, degenerate edges, coincident opposite quad corners and (near) zero area, all
 * relative to the bounding-box diagonal (mesh_policy.h), then edge pairing by sorting (min,max) vertex pairs (deterministic:
 * ties broken by half-edge index, so nothing depends on hash order), manifold and orientation
 * checks per edge, per-vertex fans (bow-tie detection), boundary loops.  Every error message is
 * one line "name:LINE: reason" (LINE = OBJ line of the offending face when known) or
 * "name: reason"; element indices in messages are 0-based.
 * Also here: the consistency checker, bounding box and frame (normalisation), section-polyline
 * continuation and ribbons. */
#include "mesh/mesh.h"
#include "mesh/mesh_policy.h"

#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------------ helpers */

static const char *mesh_name(const char *name) { return name && name[0] ? name : "mesh"; }

/* "name:LINE" when face f has a known line, else "name". */
static void face_loc(char *buf, size_t n, const char *name, const int *face_line, int f)
{
    if (face_line && f >= 0 && face_line[f] > 0)
        snprintf(buf, n, "%s:%d", mesh_name(name), face_line[f]);
    else
        snprintf(buf, n, "%s", mesh_name(name));
}

/* " (line N)" when known, else "". */
static void line_note(char *buf, size_t n, const int *face_line, int f)
{
    if (face_line && f >= 0 && face_line[f] > 0) snprintf(buf, n, " (line %d)", face_line[f]);
    else buf[0] = '\0';
}

void q2n_mesh_face_where(const q2n_mesh *m, int f, char *buf, size_t n) { face_loc(buf, n, m->name, m->face_line, f); }

void q2n_mesh_of(const q2n_mesh *m, int paren, char *buf, size_t n)
{
    if (m->derived[0]) snprintf(buf, n, paren ? " (of the %s mesh)" : " of the %s mesh", m->derived);
    else if (n) buf[0] = '\0';
}

void q2n_mesh_vertex_where(const q2n_mesh *m, int v, char *buf, size_t n)
{
    int f = m->vert_he[v] >= 0 ? m->he_face[m->vert_he[v]] : 0, line = m->face_line ? m->face_line[f] : 0;
    if (line > 0) snprintf(buf, n, "%s:%d", m->name, line);
    else snprintf(buf, n, "%s: face %d", m->name, f);
}

void q2n_mesh_free(q2n_mesh *m)
{
    if (!m) return;
    free(m->pos);
    free(m->face_start);
    free(m->face_vert);
    free(m->face_line);
    free(m->he_face);
    free(m->he_twin);
    free(m->he_edge);
    free(m->edge_he);
    free(m->vert_he);
    free(m->valence);
    free(m->vert_nfaces);
    free(m->vert_boundary);
    free(m);
}

static void *xmalloc(size_t count, size_t size)
{
    if (count == 0) count = 1;
    if (count > SIZE_MAX / size) return NULL;
    return malloc(count * size);
}

/* ------------------------------------------------------- validation stages */

static q2n_status check_faces(int nv, int nf, const int *face_start, const int *face_vert,
                              const int *face_line, const char *name, q2n_error *err)
{
    char loc[300];
    if (nf <= 0)
        return q2n_error_set(err, Q2N_ERR_TOPOLOGY, "%s: empty mesh (no faces)", mesh_name(name));
    if (face_start[0] != 0)
        return q2n_error_set(err, Q2N_ERR_ARG, "%s: face_start[0] = %d (must be 0)",
                             mesh_name(name), face_start[0]);
    for (int f = 0; f < nf; f++) {
        int n = face_start[f + 1] - face_start[f];
        if (face_start[f + 1] < face_start[f] || n < 3) {
            face_loc(loc, sizeof loc, name, face_line, f);
            return q2n_error_set(err, Q2N_ERR_TOPOLOGY, "%s: face %d has %d vertices (< 3)", loc,
                                 f, n);
        }
        for (int i = face_start[f]; i < face_start[f + 1]; i++)
            if (face_vert[i] < 0 || face_vert[i] >= nv) {
                face_loc(loc, sizeof loc, name, face_line, f);
                return q2n_error_set(err, Q2N_ERR_TOPOLOGY,
                                     "%s: face %d vertex index %d out of range (%d vertices)", loc,
                                     f, face_vert[i], nv);
            }
    }
    return Q2N_OK;
}

/* ----------------------------------------------------- scale-free geometry */

/* The frame of the referenced vertices (those some face uses): centre of their bounding box and
 * a power of two 2^exp such that every referenced coordinate lies within 2^exp of the centre and
 * the largest half-extent is at least 2^(exp-1); *mant = diagonal / 2^exp, in [1, 2 sqrt 3).
 * Half-extents are taken as hi/2 - lo/2 and lengths in units of 2^exp, so nothing overflows even
 * at the ends of the double range.  exp = 0, mant = 1 when all coincide. */
static void frame_of(const double *pos, int nh, const int *face_vert, double centre[3], int *exp,
                     double *mant)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    double half[3], hmax = 0, d2 = 0;
    for (int h = 0; h < nh; h++) {
        const double *p = pos + 3 * (size_t)face_vert[h];
        for (int c = 0; c < 3; c++) {
            if (p[c] < lo[c]) lo[c] = p[c];
            if (p[c] > hi[c]) hi[c] = p[c];
        }
    }
    for (int c = 0; c < 3; c++) {
        if (nh <= 0) lo[c] = hi[c] = 0;
        centre[c] = lo[c] / 2 + hi[c] / 2;
        half[c] = hi[c] / 2 - lo[c] / 2;
        if (half[c] > hmax) hmax = half[c];
    }
    *exp = hmax > 0 ? ilogb(hmax) + 1 : 0;
    for (int c = 0; c < 3; c++) d2 += ldexp(half[c], -*exp) * ldexp(half[c], -*exp);
    *mant = hmax > 0 ? 2 * sqrt(d2) : 1.0;
}

/* Position of vertex v in the frame, in units of 2^exp: (p - centre) / 2^exp (exact scaling,
 * one rounding). */
static void frame_point(const double *pos, int v, const double centre[3], int exp, double q[3])
{
    for (int c = 0; c < 3; c++)
        q[c] = ldexp(pos[3 * (size_t)v + c], -exp) - ldexp(centre[c], -exp);
}

static double dist3(const double *a, const double *b)
{
    double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

/* Distance of input points a, b in units of 2^exp, without under- or overflow (for messages: not
 * taken relative to the centre, so a short edge far from it keeps its length). */
static double frame_dist(const double *a, const double *b, int exp)
{
    double d[3];
    for (int c = 0; c < 3; c++) d[c] = ldexp(a[c], -exp) - ldexp(b[c], -exp);
    return sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

/* Corners of quad q[4] that are reflex when seen along its vector area `area` (the quad
 * projected on its mean plane): their signed sine is below -Q2N_MESH_REFLEX_SIN.  One reflex
 * corner is a dart (non-convex), two are a bow-tie (opposite sides cross); a convex or saddle-
 * shaped quad has none.  Returns the count, the corners in r[]. */
static int quad_reflex_corners(double q[4][3], const double area[3], int r[4])
{
    double alen = sqrt(area[0] * area[0] + area[1] * area[1] + area[2] * area[2]);
    int nr = 0;
    for (int i = 0; i < 4; i++) {
        const double *p = q[i], *a = q[(i + 1) & 3], *b = q[(i + 3) & 3];
        double x[3] = {a[0] - p[0], a[1] - p[1], a[2] - p[2]};
        double y[3] = {b[0] - p[0], b[1] - p[1], b[2] - p[2]};
        double c[3] = {x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]};
        double sine = (c[0] * area[0] + c[1] * area[1] + c[2] * area[2]) /
                      (alen * sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]) *
                       sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]));
        if (sine < -Q2N_MESH_REFLEX_SIN) r[nr++] = i;
    }
    return nr;
}

/* Per face, in face order: a vertex used twice, edges, opposite quad corners and the face's
 * width (|vector area| / longest edge) against Q2N_MESH_MIN_LENGTH_REL of the bounding-box
 * diagonal, all measured in the normalised frame (so the verdict does not depend on the scale).
 * Exactly coincident positions keep their own message. */
static q2n_status check_face_vertices(const q2n_mesh *m, const char *name, q2n_error *err)
{
    char loc[300];
    double centre[3], diag, q[4][3];
    int exp;
    frame_of(m->pos, m->nh, m->face_vert, centre, &exp, &diag);
    double tiny = Q2N_MESH_MIN_LENGTH_REL * diag;
    q2n_status st = Q2N_OK;
    int *stamp = xmalloc((size_t)m->nv, sizeof *stamp);
    if (!stamp) return q2n_error_set(err, Q2N_ERR_NOMEM, "%s: out of memory", mesh_name(name));
    for (int v = 0; v < m->nv; v++) stamp[v] = -1;
    for (int f = 0; f < m->nf && !st; f++) {
        int s = m->face_start[f], n = m->face_start[f + 1] - s;
        double area[3] = {0, 0, 0}, lmax = 0, a[3], b[3], first[3] = {0, 0, 0};
        face_loc(loc, sizeof loc, name, m->face_line, f);
        for (int i = 0; i < n && !st; i++) { /* topology before geometry: a repeat is not a short edge */
            int v = m->face_vert[s + i];
            if (stamp[v] == f) st = q2n_error_set(err, Q2N_ERR_TOPOLOGY, "%s: face %d repeats vertex %d", loc, f, v);
            stamp[v] = f;
        }
        for (int i = 0; i < n && !st; i++) {
            int v = m->face_vert[s + i], w = m->face_vert[s + (i + 1) % n];
            const double *pa = m->pos + 3 * (size_t)v, *pb = m->pos + 3 * (size_t)w;
            if (pa[0] == pb[0] && pa[1] == pb[1] && pa[2] == pb[2] && v != w) {
                st = q2n_error_set(err, Q2N_ERR_GEOMETRY, "%s: face %d has a zero-length edge %d-%d "
                                   "(coincident vertex positions)", loc, f, v, w);
                break;
            }
            frame_point(m->pos, v, centre, exp, a);
            frame_point(m->pos, w, centre, exp, b);
            if (i < 4) memcpy(q[i], a, sizeof a);
            if (i == 0) memcpy(first, a, sizeof a);
            double len = dist3(a, b);
            if (len < tiny) {
                st = q2n_error_set(err, Q2N_ERR_GEOMETRY, "%s: face %d has a degenerate edge %d-%d: "
                                   "length %.3g, %.2g of the bounding-box diagonal (< %.0e)", loc, f, v,
                                   w, ldexp(frame_dist(pa, pb, exp), exp), frame_dist(pa, pb, exp) / diag,
                                   Q2N_MESH_MIN_LENGTH_REL);
                break;
            }
            if (len > lmax) lmax = len;
            /* Newell's vector area, relative to the first corner */
            double x[3] = {a[0] - first[0], a[1] - first[1], a[2] - first[2]};
            double y[3] = {b[0] - first[0], b[1] - first[1], b[2] - first[2]};
            area[0] += 0.5 * (x[1] * y[2] - x[2] * y[1]);
            area[1] += 0.5 * (x[2] * y[0] - x[0] * y[2]);
            area[2] += 0.5 * (x[0] * y[1] - x[1] * y[0]);
        }
        if (st) break;
        for (int i = 0; n == 4 && i < 2; i++) { /* opposite corners of a quad: v0-v2, v1-v3 */
            double d = dist3(q[i], q[i + 2]);
            if (d < tiny)
                st = q2n_error_set(err, Q2N_ERR_GEOMETRY, "%s: face %d has opposite corners %d and %d "
                                   "at the same position (distance %.3g, %.2g of the bounding-box "
                                   "diagonal): a degenerate quad", loc, f, m->face_vert[s + i],
                                   m->face_vert[s + i + 2],
                                   ldexp(frame_dist(m->pos + 3 * (size_t)m->face_vert[s + i],
                                                    m->pos + 3 * (size_t)m->face_vert[s + i + 2], exp), exp),
                                   frame_dist(m->pos + 3 * (size_t)m->face_vert[s + i],
                                              m->pos + 3 * (size_t)m->face_vert[s + i + 2], exp) / diag);
        }
        double alen = sqrt(area[0] * area[0] + area[1] * area[1] + area[2] * area[2]);
        double width = alen / lmax;
        if (!st && !(width >= tiny))
            st = q2n_error_set(err, Q2N_ERR_GEOMETRY, "%s: face %d has (near) zero area: width "
                               "%.3g, %.2g of the bounding-box diagonal (< %.0e): collinear vertices "
                               "or a symmetric bow-tie", loc, f, ldexp(width, exp), width / diag,
                               Q2N_MESH_MIN_LENGTH_REL);
    }
    free(stamp);
    return st;
}

static int he_min(const q2n_mesh *m, int h)
{
    int v = q2n_he_origin(m, h), w = q2n_he_dest(m, h);
    return v < w ? v : w;
}

static int he_max(const q2n_mesh *m, int h)
{
    int v = q2n_he_origin(m, h), w = q2n_he_dest(m, h);
    return v < w ? w : v;
}

/* Error for the bad edge group {a,b} (half-edges `list`, increasing), found at half-edge `at`. */
static q2n_status edge_error(const q2n_mesh *m, const char *name, const int *list, int n, int a,
                             int b, int at, q2n_error *err)
{
    char loc[300], msg[400] = "", note[64];
    int hs[4], len = 0;
    for (int i = 0; i < n; i++) {
        if (he_max(m, list[i]) != b) continue;
        if (len < 4) hs[len] = list[i];
        len++;
    }
    face_loc(loc, sizeof loc, name, m->face_line, m->he_face[at]);
    for (int t = 0; t < len && t < 4; t++) {
        int f = m->he_face[hs[t]];
        size_t used = strlen(msg);
        line_note(note, sizeof note, m->face_line, f);
        snprintf(msg + used, sizeof msg - used, "%s%d%s", t ? ", " : "", f, note);
    }
    if (len == 2)
        return q2n_error_set(err, Q2N_ERR_TOPOLOGY,
                             "%s: inconsistent orientation: faces %s both use edge %d->%d in the "
                             "same direction", loc, msg, q2n_he_origin(m, hs[0]),
                             q2n_he_dest(m, hs[0]));
    return q2n_error_set(err, Q2N_ERR_TOPOLOGY, "%s: non-manifold edge %d-%d used by %d faces: %s%s",
                         loc, a, b, len, msg, len > 4 ? ", ..." : "");
}

/* Pair half-edges into twins in linear time: half-edges are bucketed by their smaller vertex
 * (counting sort, increasing half-edge order inside a bucket), then grouped by the larger vertex
 * with per-vertex scratch slots.  Deterministic; reports the invalid edge that becomes invalid
 * first in face order (the 2nd half-edge of a same-direction pair, the 3rd of a fan). */
static q2n_status pair_edges(q2n_mesh *m, const char *name, q2n_error *err)
{
    int nh = m->nh, nv = m->nv;
    int *start = xmalloc((size_t)nv + 1, sizeof *start), *list = xmalloc((size_t)nh, sizeof *list);
    int *head = xmalloc((size_t)nv, sizeof *head), *cnt = xmalloc((size_t)nv, sizeof *cnt);
    int *third = xmalloc((size_t)nv, sizeof *third);
    q2n_status st = Q2N_OK;
    if (!start || !list || !head || !cnt || !third) {
        st = q2n_error_set(err, Q2N_ERR_NOMEM, "%s: out of memory", mesh_name(name));
        goto done;
    }
    memset(start, 0, ((size_t)nv + 1) * sizeof *start);
    for (int h = 0; h < nh; h++) start[he_min(m, h) + 1]++;
    for (int v = 0; v < nv; v++) start[v + 1] += start[v];
    for (int h = 0; h < nh; h++) list[start[he_min(m, h)]++] = h;
    for (int v = nv; v > 0; v--) start[v] = start[v - 1];
    start[0] = 0;
    for (int v = 0; v < nv; v++) head[v] = -1;
    int bad_at = INT_MAX, bad_a = -1, bad_b = -1;
    for (int a = 0; a < nv; a++) {
        const int *l = list + start[a];
        int n = start[a + 1] - start[a];
        for (int i = 0; i < n; i++) { /* group by the larger vertex b */
            int h = l[i], b = he_max(m, h);
            m->he_twin[h] = -1;
            if (head[b] < 0) { head[b] = h; cnt[b] = 1; continue; }
            if (++cnt[b] == 2) {
                int g = head[b];
                if (q2n_he_origin(m, g) != q2n_he_origin(m, h)) m->he_twin[g] = h, m->he_twin[h] = g;
                else if (h < bad_at) bad_at = h, bad_a = a, bad_b = b;
            } else if (cnt[b] == 3) {
                third[b] = h;
            }
        }
        for (int i = 0; i < n; i++) {
            int h = l[i], b = he_max(m, h);
            if (head[b] < 0) continue;
            if (cnt[b] > 2) {
                m->he_twin[head[b]] = -1;
                if (third[b] < bad_at) bad_at = third[b], bad_a = a, bad_b = b;
            }
            head[b] = -1;
        }
    }
    if (bad_a >= 0)
        st = edge_error(m, name, list + start[bad_a], start[bad_a + 1] - start[bad_a], bad_a,
                        bad_b, bad_at, err);
done:
    free(start);
    free(list);
    free(head);
    free(cnt);
    free(third);
    return st;
}

/* Undirected edges numbered by first appearance in face (= half-edge) order. */
static void number_edges(q2n_mesh *m)
{
    m->ne = 0;
    for (int h = 0; h < m->nh; h++) m->he_edge[h] = -1;
    for (int h = 0; h < m->nh; h++) {
        if (m->he_edge[h] >= 0) continue;
        int e = m->ne++, t = m->he_twin[h];
        m->he_edge[h] = e;
        m->edge_he[e] = h;
        if (t >= 0) m->he_edge[t] = e;
    }
}

/* Per-vertex fans: vert_he, valence, vert_nfaces, vert_boundary; rejects bow-tie vertices. */
static q2n_status build_fans(q2n_mesh *m, const char *name, q2n_error *err)
{
    int nv = m->nv, nh = m->nh;
    int *start = xmalloc((size_t)nv + 1, sizeof *start), *out = xmalloc((size_t)nh, sizeof *out);
    unsigned char *seen = calloc((size_t)nh ? (size_t)nh : 1, 1);
    q2n_status st = Q2N_OK;
    if (!start || !out || !seen) {
        st = q2n_error_set(err, Q2N_ERR_NOMEM, "%s: out of memory", mesh_name(name));
        goto done;
    }
    /* outgoing half-edges of each vertex, CSR, in increasing half-edge order */
    memset(start, 0, ((size_t)nv + 1) * sizeof *start);
    for (int h = 0; h < nh; h++) start[m->face_vert[h] + 1]++;
    for (int v = 0; v < nv; v++) start[v + 1] += start[v];
    for (int h = 0; h < nh; h++) out[start[m->face_vert[h]]++] = h;
    for (int v = nv; v > 0; v--) start[v] = start[v - 1];
    start[0] = 0;

    for (int v = 0; v < nv && st == Q2N_OK; v++) {
        int s = start[v], cnt = start[v + 1] - s, h0 = -1, nb = 0;
        m->vert_nfaces[v] = cnt;
        if (cnt == 0) {
            m->vert_he[v] = -1; m->valence[v] = 0; m->vert_boundary[v] = 0;
            continue;
        }
        for (int i = s; i < s + cnt; i++)
            if (m->he_twin[out[i]] < 0) { if (!nb++) h0 = out[i]; }
        if (h0 < 0) h0 = out[s];
        int visited = 0, h = h0;
        do {
            seen[h] = 1;
            visited++;
            h = q2n_mesh_rotate(m, h);
        } while (h >= 0 && h != h0 && visited <= cnt);
        if (nb > 1 || visited != cnt) {
            int other = -1;
            for (int i = s; i < s + cnt && other < 0; i++)
                if (!seen[out[i]]) other = out[i];
            int fa = m->he_face[h0], fb = other >= 0 ? m->he_face[other] : fa;
            char loc[300], na[64], nb2[64];
            face_loc(loc, sizeof loc, name, m->face_line, fb > fa ? fb : fa);
            line_note(na, sizeof na, m->face_line, fa);
            line_note(nb2, sizeof nb2, m->face_line, fb);
            st = q2n_error_set(err, Q2N_ERR_TOPOLOGY,
                               "%s: non-manifold vertex %d (bow-tie): its %d faces form more than "
                               "one fan, e.g. faces %d%s and %d%s", loc, v, cnt, fa, na, fb, nb2);
        }
        for (int i = s; i < s + cnt; i++) seen[out[i]] = 0;
        m->vert_he[v] = h0;
        m->vert_boundary[v] = (unsigned char)(nb > 0);
        m->valence[v] = cnt + (nb > 0);
    }
done:
    free(start);
    free(out);
    free(seen);
    return st;
}

/* Boundary loops: follow boundary half-edge h -> vert_he[dest(h)]. */
static int count_boundary_loops(const q2n_mesh *m, unsigned char *seen)
{
    int loops = 0;
    for (int h = 0; h < m->nh; h++) {
        if (m->he_twin[h] >= 0 || seen[h]) continue;
        loops++;
        for (int g = h, guard = 0; g >= 0 && !seen[g] && guard <= m->nh; guard++) {
            seen[g] = 1;
            g = m->vert_he[q2n_he_dest(m, g)];
            if (g >= 0 && m->he_twin[g] >= 0) break; /* not a boundary fan start: corrupt */
        }
    }
    return loops;
}

/* ------------------------------------------------------------ constructors */

q2n_status q2n_mesh_from_arrays_lines(int nv, const double *pos, int nf, const int *face_start,
                                      const int *face_vert, const int *face_line, const char *name,
                                      q2n_mesh **out, q2n_error *err)
{
    if (!out) return q2n_error_set(err, Q2N_ERR_ARG, "%s: no output pointer", mesh_name(name));
    *out = NULL;
    if (nv < 0 || nf < 0 || (nv > 0 && !pos) || !face_start || (nf > 0 && !face_vert))
        return q2n_error_set(err, Q2N_ERR_ARG, "%s: invalid mesh arrays", mesh_name(name));
    q2n_status st = check_faces(nv, nf, face_start, face_vert, face_line, name, err);
    if (st) return st;
    for (size_t i = 0; i < 3 * (size_t)nv; i++)
        if (!isfinite(pos[i]))
            return q2n_error_set(err, Q2N_ERR_PARSE, "%s: vertex %d has a non-finite coordinate",
                                 mesh_name(name), (int)(i / 3));

    q2n_mesh *m = calloc(1, sizeof *m);
    if (!m) return q2n_error_set(err, Q2N_ERR_NOMEM, "%s: out of memory", mesh_name(name));
    int nh = face_start[nf];
    m->nv = nv; m->nf = nf; m->nh = nh;
    snprintf(m->name, sizeof m->name, "%s", mesh_name(name));
    m->pos = xmalloc(3 * (size_t)nv, sizeof *m->pos);
    m->face_start = xmalloc((size_t)nf + 1, sizeof *m->face_start);
    m->face_vert = xmalloc((size_t)nh, sizeof *m->face_vert);
    m->face_line = xmalloc((size_t)nf, sizeof *m->face_line);
    m->he_face = xmalloc((size_t)nh, sizeof *m->he_face);
    m->he_twin = xmalloc((size_t)nh, sizeof *m->he_twin);
    m->he_edge = xmalloc((size_t)nh, sizeof *m->he_edge);
    m->edge_he = xmalloc((size_t)nh, sizeof *m->edge_he);
    m->vert_he = xmalloc((size_t)nv, sizeof *m->vert_he);
    m->valence = xmalloc((size_t)nv, sizeof *m->valence);
    m->vert_nfaces = xmalloc((size_t)nv, sizeof *m->vert_nfaces);
    m->vert_boundary = xmalloc((size_t)nv, sizeof *m->vert_boundary);
    if (!m->pos || !m->face_start || !m->face_vert || !m->face_line || !m->he_face ||
        !m->he_twin || !m->he_edge || !m->edge_he || !m->vert_he || !m->valence ||
        !m->vert_nfaces || !m->vert_boundary) {
        q2n_mesh_free(m);
        return q2n_error_set(err, Q2N_ERR_NOMEM, "%s: out of memory", mesh_name(name));
    }
    if (nv) memcpy(m->pos, pos, 3 * (size_t)nv * sizeof *pos);
    memcpy(m->face_start, face_start, ((size_t)nf + 1) * sizeof *face_start);
    memcpy(m->face_vert, face_vert, (size_t)nh * sizeof *face_vert);
    for (int f = 0; f < nf; f++) m->face_line[f] = face_line ? face_line[f] : 0;
    m->all_quads = 1;
    for (int f = 0; f < nf; f++) {
        if (face_start[f + 1] - face_start[f] != 4) m->all_quads = 0;
        for (int h = face_start[f]; h < face_start[f + 1]; h++) m->he_face[h] = f;
    }
    if ((st = check_face_vertices(m, name, err)) || (st = pair_edges(m, name, err))) {
        q2n_mesh_free(m);
        return st;
    }
    number_edges(m);
    if ((st = build_fans(m, name, err))) {
        q2n_mesh_free(m);
        return st;
    }
    unsigned char *seen = calloc((size_t)nh, 1);
    if (!seen) {
        q2n_mesh_free(m);
        return q2n_error_set(err, Q2N_ERR_NOMEM, "%s: out of memory", mesh_name(name));
    }
    m->n_boundary_loops = count_boundary_loops(m, seen);
    free(seen);
    *out = m;
    return Q2N_OK;
}

q2n_status q2n_mesh_from_arrays(int nv, const double *pos, int nf, const int *face_start,
                                const int *face_vert, const char *name, q2n_mesh **out,
                                q2n_error *err)
{
    return q2n_mesh_from_arrays_lines(nv, pos, nf, face_start, face_vert, NULL, name, out, err);
}

/* ------------------------------------------------------------------ checker */

#define CHECK_OR_FAIL(cond, ...)                                                          \
    do {                                                                                  \
        if (!(cond)) { st = q2n_error_set(err, Q2N_ERR_TOPOLOGY, __VA_ARGS__); goto done; } \
    } while (0)

/* Verifies every half-edge identity from scratch (independent of the construction code path
 * where possible): twin involution, origin/destination swap, edge numbering, fans, counts. */
q2n_status q2n_mesh_check(const q2n_mesh *m, q2n_error *err)
{
    q2n_status st = Q2N_OK;
    unsigned char *seen = NULL;
    int *first = NULL;
    if (!m) return q2n_error_set(err, Q2N_ERR_ARG, "mesh check: NULL mesh");
    const char *nm = m->name;
    CHECK_OR_FAIL(m->nf > 0 && m->nv >= 0 && m->face_start[0] == 0 && m->nh == m->face_start[m->nf],
                  "%s: check: bad counts", nm);
    int quads = 1;
    for (int f = 0; f < m->nf; f++) {
        int n = q2n_face_size(m, f);
        CHECK_OR_FAIL(n >= 3, "%s: check: face %d has %d vertices", nm, f, n);
        if (n != 4) quads = 0;
        for (int h = m->face_start[f]; h < m->face_start[f + 1]; h++) {
            CHECK_OR_FAIL(m->he_face[h] == f, "%s: check: he_face[%d] != %d", nm, h, f);
            CHECK_OR_FAIL(m->face_vert[h] >= 0 && m->face_vert[h] < m->nv,
                          "%s: check: face %d vertex out of range", nm, f);
        }
    }
    CHECK_OR_FAIL(quads == m->all_quads, "%s: check: all_quads = %d, expected %d", nm,
                  m->all_quads, quads);
    CHECK_OR_FAIL(m->ne >= 0 && m->ne <= m->nh, "%s: check: ne = %d", nm, m->ne);
    first = malloc(((size_t)m->ne + 1) * sizeof *first);
    seen = calloc((size_t)m->nh + 1, 1);
    if (!first || !seen) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "%s: out of memory", nm); goto done; }
    for (int e = 0; e < m->ne; e++) first[e] = -1;
    int nbh = 0;
    for (int h = 0; h < m->nh; h++) {
        int t = m->he_twin[h], e = m->he_edge[h];
        CHECK_OR_FAIL(e >= 0 && e < m->ne, "%s: check: he_edge[%d] = %d", nm, h, e);
        if (first[e] < 0) {
            CHECK_OR_FAIL(e == 0 || (first[e - 1] >= 0 && first[e - 1] < h),
                          "%s: check: edge %d not numbered in order of first appearance", nm, e);
            first[e] = h;
        }
        CHECK_OR_FAIL(m->edge_he[e] == first[e], "%s: check: edge_he[%d] = %d, expected %d", nm,
                      e, m->edge_he[e], first[e]);
        if (t < 0) { nbh++; continue; }
        CHECK_OR_FAIL(t < m->nh && t != h && m->he_twin[t] == h, "%s: check: twin(twin(%d)) != %d",
                      nm, h, h);
        CHECK_OR_FAIL(q2n_he_origin(m, t) == q2n_he_dest(m, h) &&
                      q2n_he_dest(m, t) == q2n_he_origin(m, h),
                      "%s: check: half-edges %d and %d are not opposite", nm, h, t);
        CHECK_OR_FAIL(m->he_edge[t] == e, "%s: check: twins %d, %d on different edges", nm, h, t);
        CHECK_OR_FAIL(m->he_face[t] != m->he_face[h], "%s: check: face %d is its own neighbour",
                      nm, m->he_face[h]);
    }
    CHECK_OR_FAIL(m->ne == 0 || first[m->ne - 1] >= 0, "%s: check: unused edge numbers", nm);
    CHECK_OR_FAIL(2 * m->ne - nbh == m->nh, "%s: check: %d edges, %d boundary half-edges, %d "
                  "half-edges", nm, m->ne, nbh, m->nh);
    long long valsum = 0;
    int nfsum = 0;
    for (int v = 0; v < m->nv; v++) {
        int h0 = m->vert_he[v], nfc = m->vert_nfaces[v];
        valsum += m->valence[v];
        nfsum += nfc;
        if (h0 < 0) {
            CHECK_OR_FAIL(nfc == 0 && m->valence[v] == 0 && !m->vert_boundary[v],
                          "%s: check: isolated vertex %d has counts", nm, v);
            continue;
        }
        CHECK_OR_FAIL(h0 < m->nh && q2n_he_origin(m, h0) == v, "%s: check: vert_he[%d] = %d does "
                      "not leave the vertex", nm, v, h0);
        CHECK_OR_FAIL((m->he_twin[h0] < 0) == (m->vert_boundary[v] != 0),
                      "%s: check: boundary flag of vertex %d", nm, v);
        int k = 0, h = h0, last = h0;
        do {
            CHECK_OR_FAIL(q2n_he_origin(m, h) == v, "%s: check: rotation leaves vertex %d", nm, v);
            k++;
            last = h;
            h = q2n_mesh_rotate(m, h);
            if (h >= 0) {
                CHECK_OR_FAIL(q2n_mesh_rotate_back(m, h) == last,
                              "%s: check: rotate_back(rotate(%d)) != %d", nm, last, last);
            }
        } while (h >= 0 && h != h0 && k <= nfc);
        CHECK_OR_FAIL(k == nfc, "%s: check: fan of vertex %d has %d faces, vert_nfaces %d", nm, v,
                      k, nfc);
        CHECK_OR_FAIL((h < 0) == (m->vert_boundary[v] != 0),
                      "%s: check: fan of vertex %d open/closed mismatch", nm, v);
        CHECK_OR_FAIL(m->valence[v] == nfc + (m->vert_boundary[v] ? 1 : 0),
                      "%s: check: valence of vertex %d", nm, v);
    }
    CHECK_OR_FAIL(nfsum == m->nh, "%s: check: face-vertex incidences %d != %d", nm, nfsum, m->nh);
    CHECK_OR_FAIL(valsum == 2LL * m->ne, "%s: check: valence sum %lld != 2E = %d", nm, valsum,
                  2 * m->ne);
    memset(seen, 0, (size_t)m->nh);
    int loops = count_boundary_loops(m, seen);
    CHECK_OR_FAIL(loops == m->n_boundary_loops, "%s: check: %d boundary loops, recorded %d", nm,
                  loops, m->n_boundary_loops);
done:
    free(first);
    free(seen);
    return st;
}

/* ---------------------------------------------------------- simple queries */

double q2n_mesh_bbox_diag(const q2n_mesh *m)
{
    double centre[3], mant;
    int exp;
    if (!m) return 0.0;
    q2n_mesh_frame(m, centre, &mant, &exp);
    return ldexp(mant, exp);
}

void q2n_mesh_face_area(const q2n_mesh *m, int f, double a[3])
{
    int s = m->face_start[f], n = m->face_start[f + 1] - s;
    const double *o = q2n_mesh_vpos(m, m->face_vert[s]);
    a[0] = a[1] = a[2] = 0;
    for (int i = 1; i + 1 < n; i++) { /* Newell: sum of the fan triangles from corner 0 */
        const double *p = q2n_mesh_vpos(m, m->face_vert[s + i]), *q = q2n_mesh_vpos(m, m->face_vert[s + i + 1]);
        double x[3] = {p[0] - o[0], p[1] - o[1], p[2] - o[2]}, y[3] = {q[0] - o[0], q[1] - o[1], q[2] - o[2]};
        a[0] += 0.5 * (x[1] * y[2] - x[2] * y[1]);
        a[1] += 0.5 * (x[2] * y[0] - x[0] * y[2]);
        a[2] += 0.5 * (x[0] * y[1] - x[1] * y[0]);
    }
}

void q2n_mesh_frame(const q2n_mesh *m, double centre[3], double *mant, int *exp)
{
    frame_of(m->pos, m->nh, m->face_vert, centre, exp, mant);
}

void q2n_mesh_normalize(q2n_mesh *m, double centre[3], double *mant, int *exp)
{
    double q[3];
    frame_of(m->pos, m->nh, m->face_vert, centre, exp, mant);
    for (int v = 0; v < m->nv; v++) {
        if (m->vert_nfaces[v] == 0) continue; /* unreferenced: kept as read */
        frame_point(m->pos, v, centre, *exp, q);
        for (int c = 0; c < 3; c++) m->pos[3 * (size_t)v + c] = q[c] / *mant;
    }
}

q2n_status q2n_mesh_check_crossing(const q2n_mesh *m, q2n_error *err)
{
    char loc[300];
    double q[4][3], area[3];
    int r[4];
    for (int f = 0; f < m->nf; f++) {
        if (q2n_face_size(m, f) != 4) continue;
        for (int i = 0; i < 4; i++) memcpy(q[i], q2n_mesh_vpos(m, m->face_vert[m->face_start[f] + i]), sizeof q[i]);
        q2n_mesh_face_area(m, f, area);
        if (quad_reflex_corners(q, area, r) < 2) continue;
        face_loc(loc, sizeof loc, m->name, m->face_line, f);
        char par[56];
        q2n_mesh_of(m, 1, par, sizeof par);
        return q2n_error_set(err, Q2N_ERR_GEOMETRY, "%s: face %d%s is self-crossing (a bow-tie): seen "
                             "along its normal, its corners at vertices %d and %d turn the other way",
                             loc, f, par, m->face_vert[m->face_start[f] + r[0]],
                             m->face_vert[m->face_start[f] + r[1]]);
    }
    return Q2N_OK;
}

int q2n_mesh_continue(const q2n_mesh *m, int h_in)
{
    if (!m || h_in < 0 || h_in >= m->nh) return -1;
    int v = q2n_he_dest(m, h_in), t = m->he_twin[h_in];
    if (!m->vert_boundary[v]) {
        if (m->valence[v] != 4 || t < 0) return -1;
        int h = q2n_mesh_rotate(m, t);
        return h < 0 ? -1 : q2n_mesh_rotate(m, h);
    }
    if (m->valence[v] == 3 && t < 0) return m->vert_he[v];
    return -1;
}

static int uf_find(int *parent, int x)
{
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

static void uf_union(int *parent, int a, int b)
{
    a = uf_find(parent, a);
    b = uf_find(parent, b);
    if (a != b) parent[a > b ? a : b] = a < b ? a : b;
}

q2n_status q2n_mesh_ribbons(const q2n_mesh *m, int **ribbon, int *nribbons, q2n_error *err)
{
    if (!m || !ribbon || !nribbons) return q2n_error_set(err, Q2N_ERR_ARG, "ribbons: NULL argument");
    *ribbon = NULL;
    *nribbons = 0;
    int *parent = xmalloc((size_t)m->ne, sizeof *parent);
    int *id = xmalloc((size_t)m->ne, sizeof *id);
    if (!parent || !id) {
        free(parent);
        free(id);
        return q2n_error_set(err, Q2N_ERR_NOMEM, "%s: out of memory", m->name);
    }
    for (int e = 0; e < m->ne; e++) parent[e] = e, id[e] = -1;
    for (int f = 0; f < m->nf; f++) {
        if (q2n_face_size(m, f) != 4) continue;
        for (int i = 0; i < 2; i++) /* opposite sides of a quad: corners i and i+2 */
            uf_union(parent, m->he_edge[q2n_face_he(m, f, i)], m->he_edge[q2n_face_he(m, f, i + 2)]);
    }
    /* numbering by smallest edge index of each ribbon: independent of union order */
    int n = 0;
    for (int e = 0; e < m->ne; e++) {
        int r = uf_find(parent, e);
        if (id[r] < 0) id[r] = n++;
        parent[e] = r;
    }
    for (int e = 0; e < m->ne; e++) id[e] = id[parent[e]];
    free(parent);
    *ribbon = id;
    *nribbons = n;
    return Q2N_OK;
}

void q2n_mesh_corner_regions(const q2n_mesh *m, const char *in_set, int *root)
{
    for (int v = 0; v < m->nv; v++) root[v] = v;
    for (int f = 0; f < m->nf; f++) {
        if (!in_set[f]) continue;
        const int *fv = m->face_vert + m->face_start[f];
        for (int i = 1; i < q2n_face_size(m, f); i++) uf_union(root, fv[0], fv[i]);
    }
    for (int v = 0; v < m->nv; v++) root[v] = uf_find(root, v); /* the smallest vertex: union keeps it */
}
