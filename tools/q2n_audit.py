#!/usr/bin/python3
"""q2n_audit.py — import a STEP or IGES file with FreeCAD (OpenCASCADE) and audit it.

An importer nobody here wrote checks what quad2nurbs exported:
  * topology: face count, isValid(), shells, solids, edges, free edges (used by one face only),
    non-manifold edges (used by more than two faces), the largest edge / vertex tolerance OCCT
    assigned on import (it raises them to cover gaps it finds: 1e-7 means none), and with --check
    the full BRepCheck (shape.check(True), seconds on ~1000 faces);
  * continuity across every shared edge, in the terms of Rhino's EdgeContinuity, sampled at the
    points between the fit's collocation points (default: in every knot span of the edge curve, the 4
    midpoints between its 4 fit samples — the odd eighths of the span, the fit's rule in src/fit/ —
    so the audit samples the very points quad2nurbs' report measures; --samples N takes N points at
    t_i = t0 + (i + 0.5)/N (t1 - t0) instead):
      G0  gap |S_A - S_B| between the two faces' surfaces at the edge's p-curve points,
      G1  angle between the two (face-oriented) unit normals, degrees,
      G2  normal curvature across the edge (direction d = N_A x T) on each side: absolute jump
          |k_A - k_B| (g2_max_abs) and relative jump |k_A - k_B| / (|k_A| + |k_B|) (g2_max_rel_radii)
          — that is |(R_A - R_B)/(R_A + R_B)| for curvatures of equal sign, 1 for opposite signs —
          set to 0 where both sides are flatter than the cut-off (radius > FLAT x bbox diagonal);
          and g2_max_rel in the definition of quad2nurbs' fit report (src/fit/fit_report.c):
          max over the directions T, d and (T + d)/sqrt2 of |k_A - k_B|, divided by the largest
          |k| of both sides in those directions (at least 1/diagonal);
    each with the worst sample's location;
  * the rim (the free edges): at every vertex where free edges of two different faces meet, how far
    the boundary turns (rim.max_turn_deg: 0 where it runs on smoothly, as quad2nurbs draws it through
    every boundary vertex of two faces or more; corners of one face are counted apart) and how much
    its curvature vector jumps there (rim.curvature_jump_rel, over the larger, at least 1/diagonal);
  * with --mesh: the distance of every mesh vertex to the imported shape.
The diagonal of the relative figures (bbox_diag, and the source it came from, diag_source) is the
mesh's bounding box with --mesh, else the shape's; --report REPORT.json takes quad2nurbs' own (the
model's mesh: after --subdivide the subdivided one, whose limit points lie inside the input's box —
a coarse triangle mesh's by ~10 %), so that g0_max_rel and G2's 1/diagonal floor are the report's.
Run with /usr/bin/python3 (Debian freecad-python3), not freecadcmd.  Output: JSON (stdout or --json);
--batch LIST audits many files in one process (FreeCAD loads once, ~0.5 s saved per file).
Exit status 0 after a successful audit, 2 when FreeCAD is missing, 1 when the file cannot be read.
Summary fields g0_max_rel (gap / bbox diagonal), g1_max_deg, g2_max_rel and faces use the names of
quad2nurbs' own report, so tools/q2n_compare.py can put the two side by side.
As a module: audit_shape() audits a shape already read, with any per-face evaluator that has
FaceEval's methods (tools/q2n_report.py passes numpy ones, tools/q2n_nurbs.py); the continuity
measures run on arrays of samples (continuity_samples), the same arithmetic for every evaluator.
"""
import argparse
import json
import math
import os
import shlex
import sys
import time

try:
    import numpy as np
except ImportError:  # FreeCAD needs numpy: without it, load_freecad() fails the same way
    np = None

FREECAD_LIB = '/usr/lib/freecad-python3/lib'


def load_freecad():
    """FreeCAD must be imported before Part (the reverse order segfaults, docs/toolchain.md)."""
    if FREECAD_LIB not in sys.path:
        sys.path.append(FREECAD_LIB)
    try:
        import FreeCAD  # noqa: F401
        import Part
    except ImportError:
        return None
    return Part


def read_obj_vertices(path):
    verts = []
    with open(path) as f:
        for line in f:
            if line.startswith('v '):
                p = line.split()
                verts.append((float(p[1]), float(p[2]), float(p[3])))
    return verts


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def norm(a):
    return math.sqrt(dot(a, a))


def vec(v):
    return (v.x, v.y, v.z)


class FaceEval:
    """One face's surface (cached: Face.Surface returns a new copy on every access) and orientation,
    evaluated by OpenCASCADE one point at a time.  Any object with the same three methods can stand
    in for it (tools/q2n_report.py passes a numpy evaluator of the same B-spline data)."""

    def __init__(self, face):
        self.face = face
        self.surf = face.Surface
        self.flip = face.Orientation == 'Reversed'

    def uv_on_edge(self, edge, ts):
        """(u, v) of the edge's p-curve on this face at edge parameters ts, shape (n, 2);
        projection as fallback."""
        try:
            pc = self.face.curveOnSurface(edge)
        except Exception:
            pc = None
        if pc:
            c2 = pc[0]
            return np.array([(p.x, p.y) for p in (c2.value(t) for t in ts)], dtype=float).reshape(-1, 2)
        return np.array([self.surf.parameter(edge.valueAt(t)) for t in ts], dtype=float).reshape(-1, 2)

    def jets(self, uv):
        """Point, oriented unit normal, Su, Sv, Suu, Suv, Svv at the rows of uv: seven (n, 3) arrays."""
        s = self.surf
        rows = []
        for u, v in uv:
            rows.append([vec(s.value(u, v)), vec(s.getDN(u, v, 1, 0)), vec(s.getDN(u, v, 0, 1)),
                         vec(s.getDN(u, v, 2, 0)), vec(s.getDN(u, v, 1, 1)), vec(s.getDN(u, v, 0, 2))])
        a = np.array(rows, dtype=float).reshape(-1, 6, 3)
        p, su, sv, suu, suv, svv = (a[:, i] for i in range(6))
        n = unit_rows(cross_rows(su, sv))
        if self.flip:
            n = -n
        return p, n, su, sv, suu, suv, svv

    def edge_tangents(self, edge, ts, uv, jet):
        return occt_edge_tangents(edge, ts)


def occt_edge_tangents(edge, ts):
    """Unit tangents of the edge curve at ts (its own direction), shape (n, 3)."""
    return unit_rows(np.array([vec(edge.tangentAt(t)) for t in ts], dtype=float).reshape(-1, 3))


def dot_rows(a, b):
    return a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1] + a[:, 2] * b[:, 2]


def cross_rows(a, b):
    return np.stack([a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1], a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2],
                     a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]], axis=1)


def norm_rows(a):
    return np.sqrt(dot_rows(a, a))


def unit_rows(a):
    """Rows scaled to unit length; zero rows stay zero."""
    n = norm_rows(a)
    return a / np.where(n > 0, n, 1.0)[:, None]


def normal_curvature(jet, d):
    """Normal curvature in tangent directions d (rows): II(w,w)/I(w,w) with d = a Su + b Sv;
    0 where the first fundamental form degenerates."""
    _, n, su, sv, suu, suv, svv = jet
    E, F, G = dot_rows(su, su), dot_rows(su, sv), dot_rows(sv, sv)
    r1, r2 = dot_rows(d, su), dot_rows(d, sv)
    det = E * G - F * F
    ok = det > 0
    sdet = np.where(ok, det, 1.0)
    a = (G * r1 - F * r2) / sdet
    b = (E * r2 - F * r1) / sdet
    num = a * a * dot_rows(suu, n) + 2 * a * b * dot_rows(suv, n) + b * b * dot_rows(svv, n)
    den = a * a * E + 2 * a * b * F + b * b * G
    ok &= den > 0
    return np.where(ok, num / np.where(ok, den, 1.0), 0.0)


def continuity_samples(ja, jb, tan, k_flat, diag):
    """Per sample across an edge, sides A and B (jets from FaceEval.jets, edge tangents tan):
    G0 gap, G1 angle (deg), G2 absolute jump, G2 jump relative by radii, G2 in the fit report's
    measure (see the module comment).  Returns five arrays."""
    gap = norm_rows(ja[0] - jb[0])
    # atan2(|na x nb|, na . nb): accurate for tiny angles, where acos loses half the digits
    ang = np.degrees(np.arctan2(norm_rows(cross_rows(ja[1], jb[1])), dot_rows(ja[1], jb[1])))
    d = unit_rows(cross_rows(ja[1], tan))
    ka, kb = normal_curvature(ja, d), normal_curvature(jb, d)
    g2a = np.abs(ka - kb)
    flat = np.maximum(np.abs(ka), np.abs(kb)) < k_flat
    sden = np.abs(ka) + np.abs(kb)
    g2r_radii = np.where(flat, 0.0, g2a / np.where(sden > 0, sden, 1.0))
    # the fit report's measure: three directions, jump over the largest curvature (>= 1/diag)
    jmax = np.zeros(len(gap))
    kmax = np.full(len(gap), 1.0 / diag if diag > 0 else 0.0)
    for w in (tan, d, unit_rows(tan + d)):
        kwa, kwb = normal_curvature(ja, w), normal_curvature(jb, w)
        jmax = np.maximum(jmax, np.abs(kwa - kwb))
        kmax = np.maximum(kmax, np.maximum(np.abs(kwa), np.abs(kwb)))
    g2r = np.where(kmax > 0, jmax / np.where(kmax > 0, kmax, 1.0), 0.0)
    return gap, ang, g2a, g2r_radii, g2r


def last_argmax(a):
    return len(a) - 1 - int(np.argmax(a[::-1]))


def reduce_edge(gap, ang, g2a, g2r_radii, g2r, pts):
    """One edge's maxima and the worst samples' points (G0/G1: the last maximum, G2: the first)."""
    if len(gap) == 0:
        return {'g0': 0.0, 'g1_deg': 0.0, 'g2_abs': 0.0, 'g2_rel_radii': 0.0, 'g2_rel': 0.0,
                'g0_at': None, 'g1_at': None, 'g2_at': None}
    i0, i1, i2 = last_argmax(gap), last_argmax(ang), int(np.argmax(g2r))
    return {'g0': float(gap[i0]), 'g1_deg': float(ang[i1]), 'g2_abs': float(g2a.max()),
            'g2_rel_radii': float(g2r_radii.max()), 'g2_rel': float(g2r[i2]),
            'g0_at': tuple(map(float, pts[i0])), 'g1_at': tuple(map(float, pts[i1])),
            'g2_at': tuple(map(float, pts[i2]))}


def edge_faces(shape):
    """Map edge hash -> (edge, [face indices]) for every edge of every face."""
    emap = {}
    order = []
    for fi, face in enumerate(shape.Faces):
        for e in face.Edges:
            k = e.hashCode()
            if k not in emap:
                emap[k] = (e, [])
                order.append(k)
            lst = emap[k][1]
            if fi not in lst:
                lst.append(fi)
    return [emap[k] for k in order]


def rim_audit(edges, diag):
    """The boundary's turns: at every vertex where two free edges of different faces meet (a
    boundary vertex of two faces or more, through which quad2nurbs draws the rim smoothly), the angle
    between the one edge's tangent and the other's continuation, degrees (0: the rim is G1 there), and
    the jump of the two edge curves' curvature vectors (c'' - (c''.t) t/|t|^2)/|t|^2 over the larger
    one, at least 1/diag (0: G2 there).  Vertices whose two free edges belong to one face (corners of
    the mesh's boundary) are counted apart: there the rim keeps the face's corner."""
    ends = {}
    for e, fl in edges:
        if len(fl) != 1:
            continue
        t0, t1 = e.FirstParameter, e.LastParameter
        p0, p1 = e.valueAt(t0), e.valueAt(t1)
        for v in e.Vertexes:
            first = (v.Point - p0).Length <= (v.Point - p1).Length
            t = t0 if first else t1
            d1, d2 = vec(e.derivative1At(t)), vec(e.derivative2At(t))
            l2 = dot(d1, d1)
            k = [(d2[i] - dot(d2, d1) / l2 * d1[i]) / l2 for i in range(3)] if l2 > 0 else [0.0] * 3
            d = d1 if first else [-c for c in d1]
            ends.setdefault(v.hashCode(), (v, []))[1].append((fl[0], d, k))
    worst, at, kworst, n, corners = 0.0, None, 0.0, 0, 0
    for v, lst in ends.values():
        if len(lst) != 2:
            continue
        if lst[0][0] == lst[1][0]:
            corners += 1
            continue
        a, b = lst[0][1], lst[1][1]
        x = (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
        turn = 180.0 - math.degrees(math.atan2(norm(x), dot(a, b)))  # atan2: exact near 180
        ka, kb = lst[0][2], lst[1][2]
        kj = norm(sub(ka, kb)) / max(norm(ka), norm(kb), 1.0 / diag if diag > 0 else 0.0, 1e-300)
        n += 1
        kworst = max(kworst, kj)
        if turn > worst or at is None:
            worst, at = turn, vec(v.Point)
    return {'vertices': n, 'max_turn_deg': worst, 'curvature_jump_rel': kworst, 'worst_at': at, 'corners': corners}


def edge_sample_params(edge, nsamp):
    """Sample parameters on this edge: nsamp points at (i + 0.5)/nsamp of its range, or (nsamp == 0)
    the fit's rule: in every knot span of the edge curve, the midpoints between its 4 samples per
    span, i.e. the odd eighths (src/fit/fit_basis.c, q2n_fit_check_params)."""
    t0, t1 = edge.ParameterRange
    if nsamp <= 0:
        try:
            kn = np.asarray(edge.Curve.getKnots(), dtype=float)
        except Exception:  # not a B-spline edge curve
            kn = np.zeros(0)
        if len(kn) >= 2:
            a, b = kn[:-1, None], kn[1:, None]
            return (a + (b - a) * (2 * np.arange(4) + 1) / 8.0).ravel()
        nsamp = 16
    return t0 + (np.arange(nsamp) + 0.5) / nsamp * (t1 - t0)


def audit_edge(edge, fa, fb, nsamp, k_flat, diag):
    return audit_edges([(edge, fa, fb)], nsamp, k_flat, diag)[0]


def jets_grouped(requests):
    """jets(uv) for every (evaluator, uv) request, in order, with one call per evaluator over all
    of its requests (a vectorised evaluator pays its overhead once per face, not once per edge)."""
    by_eval = {}
    for k, (ev, uv) in enumerate(requests):
        by_eval.setdefault(id(ev), (ev, []))[1].append(k)
    out = [None] * len(requests)
    for ev, ks in by_eval.values():
        sizes = [len(requests[k][1]) for k in ks]
        jet = ev.jets(np.concatenate([requests[k][1] for k in ks]))
        start = 0
        for k, n in zip(ks, sizes):
            out[k] = tuple(a[start:start + n] for a in jet)
            start += n
    return out


def audit_edges(pairs, nsamp, k_flat, diag):
    """Continuity of every (edge, evaluator A, evaluator B) in pairs: one dict per pair with
    g0, g1_deg, g2_abs, g2_rel_radii, g2_rel and the worst samples' points.  The samples of all
    edges go through continuity_samples at once."""
    if not pairs:
        return []
    params, requests, bounds = [], [], [0]
    for edge, fa, fb in pairs:
        ts = edge_sample_params(edge, nsamp)
        params.append(ts)
        requests += [(fa, fa.uv_on_edge(edge, ts)), (fb, fb.uv_on_edge(edge, ts))]
        bounds.append(bounds[-1] + len(ts))
    jets = jets_grouped(requests)
    tans = [fa.edge_tangents(edge, ts, requests[2 * k][1], jets[2 * k])
            for k, ((edge, fa, _), ts) in enumerate(zip(pairs, params))]
    ja = tuple(np.concatenate([j[i] for j in jets[0::2]]) for i in range(7))
    jb = tuple(np.concatenate([j[i] for j in jets[1::2]]) for i in range(7))
    s = continuity_samples(ja, jb, np.concatenate(tans), k_flat, diag)
    return [reduce_edge(*(a[b0:b1] for a in s), ja[0][b0:b1]) for b0, b1 in zip(bounds[:-1], bounds[1:])]


def box_array(boxes):
    """FreeCAD BoundBoxes as an array (n, 6): XMin, YMin, ZMin, XMax, YMax, ZMax."""
    return np.array([(b.XMin, b.YMin, b.ZMin, b.XMax, b.YMax, b.ZMax) for b in boxes], dtype=float).reshape(-1, 6)


def vertex_distance(Part, faces, boxes, p):
    """Distance from p to the union of faces: exact distToShape per face, nearest bounding boxes
    first (boxes: box_array; their distance to p is a lower bound), stopping when the next box is
    farther than the best distance found (the whole-shape distToShape costs ~90 ms per point,
    this ~2 ms)."""
    import FreeCAD
    q = np.asarray(p, dtype=float)
    gap = np.maximum(np.maximum(boxes[:, :3] - q, 0.0), q - boxes[:, 3:])
    lbs = np.sqrt((gap * gap).sum(axis=1))
    vx = Part.Vertex(FreeCAD.Vector(*p))
    best = math.inf
    for k in np.lexsort((np.arange(len(lbs)), lbs)):
        if lbs[k] >= best:
            break
        best = min(best, faces[k].distToShape(vx)[0])
    return best


def bbox_diag_of(shape):
    bb = shape.BoundBox
    return math.sqrt(bb.XLength ** 2 + bb.YLength ** 2 + bb.ZLength ** 2)


def full_check(shape):
    """'ok' or BRepCheck's first message (shape.check(True) raises on the first problem)."""
    try:
        shape.check(True)
        return 'ok'
    except Exception as ex:
        return str(ex).strip().splitlines()[0][:300] if str(ex).strip() else 'failed'


def audit(path, mesh=None, nsamp=0, flat=100.0, per_edge=True, check=False, diag=None):
    """Read path with FreeCAD and audit it (see the module comment); None when FreeCAD is missing."""
    Part = load_freecad()
    if Part is None:
        return None
    t_start = time.time()
    shape = Part.read(path)
    t_read = time.time() - t_start
    out = audit_shape(Part, shape, path, mesh, nsamp, flat, per_edge, check, diag=diag)
    out['seconds_read'] = t_read
    out['seconds_audit'] = time.time() - t_start - t_read
    return out


def mesh_diag(verts):
    lo = [min(v[i] for v in verts) for i in range(3)]
    hi = [max(v[i] for v in verts) for i in range(3)]
    return norm(sub(hi, lo))


def audit_shape(Part, shape, path, mesh=None, nsamp=0, flat=100.0, per_edge=True, check=False,
                evals=None, edges=None, mass=True, diag=None):
    """The audit of an imported shape.  evals: one evaluator per face (default FaceEval, OCCT per
    point); edges: edge_faces(shape) when the caller has it already; mass=False leaves out area
    and volume (OCCT integrates them: seconds on large parts); diag: the diagonal the relative
    figures use (default: the mesh's bounding box, else the shape's; see --report)."""
    faces = shape.Faces
    if evals is None:
        evals = [FaceEval(f) for f in faces]
    verts = read_obj_vertices(mesh) if mesh else None
    diag_source = 'given' if diag else 'mesh' if verts else 'shape'
    if not diag:
        diag = mesh_diag(verts) if verts else bbox_diag_of(shape)
    k_flat = 1.0 / (flat * diag) if diag > 0 else 0.0
    if edges is None:
        edges = edge_faces(shape)
    out = {
        'file': os.path.basename(path),
        'format': 'iges' if path.lower().endswith(('.igs', '.iges')) else 'step',
        'shape_type': shape.ShapeType,
        'faces': len(faces),
        'reversed_faces': sum(1 for f in faces if f.Orientation == 'Reversed'),
        'valid': bool(shape.isValid()),
        'shells': len(shape.Shells),
        'solids': len(shape.Solids),
        'edges': len(edges),
        'free_edges': sum(1 for _, fl in edges if len(fl) == 1),
        'nonmanifold_edges': sum(1 for _, fl in edges if len(fl) > 2),
        'shared_edges': sum(1 for _, fl in edges if len(fl) == 2),
        'bbox_diag': diag,
        'diag_source': diag_source,
        'samples_per_edge': nsamp if nsamp > 0 else '4 per knot span',
        'flat_radius': flat * diag,
        'area': shape.Area if mass else None,
        'max_edge_tolerance': max((e.Tolerance for e in shape.Edges), default=0.0),
        'max_vertex_tolerance': max((v.Tolerance for v in shape.Vertexes), default=0.0),
        'volume': shape.Volume if mass and shape.Solids else None,
    }
    worst = {'g0': (0.0, None, None), 'g1_deg': (0.0, None, None), 'g2_rel': (0.0, None, None)}
    g2_abs = g2_radii = 0.0
    detail = []
    shared = [ei for ei, (_, fl) in enumerate(edges) if len(fl) == 2]
    results = audit_edges([(edges[ei][0], evals[edges[ei][1][0]], evals[edges[ei][1][1]]) for ei in shared],
                          nsamp, k_flat, diag)
    for ei, r in zip(shared, results):
        fl = edges[ei][1]
        g2_abs = max(g2_abs, r['g2_abs'])
        g2_radii = max(g2_radii, r['g2_rel_radii'])
        for key, at in (('g0', 'g0_at'), ('g1_deg', 'g1_at'), ('g2_rel', 'g2_at')):
            if r[key] > worst[key][0] or worst[key][1] is None:
                worst[key] = (r[key], ei, r[at])
        if per_edge:
            detail.append({'edge': ei, 'faces': fl, 'g0': r['g0'], 'g1_deg': r['g1_deg'],
                           'g2_abs': r['g2_abs'], 'g2_rel_radii': r['g2_rel_radii'], 'g2_rel': r['g2_rel'],
                           'worst_g0_at': r['g0_at'], 'worst_g1_at': r['g1_at'], 'worst_g2_at': r['g2_at']})
    out['g0_max'] = worst['g0'][0]
    out['g0_max_rel'] = worst['g0'][0] / diag if diag > 0 else worst['g0'][0]
    out['g1_max_deg'] = worst['g1_deg'][0]
    out['g2_max_abs'] = g2_abs
    out['g2_max_rel'] = worst['g2_rel'][0]
    out['g2_max_rel_radii'] = g2_radii
    out['worst'] = {k: {'value': v[0], 'edge': v[1], 'point': v[2]} for k, v in worst.items()}
    out['rim'] = rim_audit(edges, diag)
    if verts is not None:
        dmax, imax = 0.0, -1
        boxes = box_array(f.BoundBox for f in faces)
        for i, v in enumerate(verts):
            d = vertex_distance(Part, faces, boxes, v)
            if d > dmax or imax < 0:
                dmax, imax = max(d, dmax), i
        out['mesh'] = {'file': os.path.basename(mesh), 'vertices': len(verts),
                       'max_vertex_dist': dmax, 'max_vertex_dist_rel': dmax / diag if diag > 0 else dmax,
                       'worst_vertex': imax}
    if check:
        out['check'] = full_check(shape)
    if per_edge:
        out['edge_detail'] = detail
    return out


def make_parser():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('file', nargs='?', help='.step/.stp or .igs/.iges file')
    ap.add_argument('--mesh', help='the quad mesh (.obj): report vertex distances to the shape')
    ap.add_argument('--samples', type=int, default=0,
                    help='samples per edge, at (i+0.5)/N (default 0: 4 per knot span, as the fit report)')
    ap.add_argument('--flat', type=float, default=100.0,
                    help='G2 flatness cut-off: radii above FLAT x bbox diagonal count as flat (default 100)')
    ap.add_argument('--no-edges', action='store_true', help='omit the per-edge table')
    ap.add_argument('--check', action='store_true', help="also run BRepCheck (shape.check(True)): field 'check'")
    ap.add_argument('--report', metavar='REPORT.json',
                    help="quad2nurbs' report of the same run: its bbox_diag becomes the audit's diagonal (the "
                         "relative figures and G2's 1/diagonal floor then match the report's definitions, also "
                         "after --subdivide, whose diagonal is the subdivided mesh's)")
    ap.add_argument('--diag', type=float, help='the diagonal the relative figures use (overrides --report)')
    ap.add_argument('--json', help='write the JSON here instead of stdout')
    ap.add_argument('--batch', metavar='LIST',
                    help='run many audits in one process (FreeCAD loads once): each line of LIST holds the '
                         'arguments of one run, e.g. "a.step --mesh a.obj --no-edges --json a.json"')
    return ap


def run_one(a):
    """One audit from parsed arguments; returns the exit status."""
    if not a.file or not os.path.exists(a.file):
        sys.stderr.write('q2n_audit: %s: no such file\n' % a.file)
        return 1
    diag = a.diag
    if not diag and a.report:
        try:
            with open(a.report) as f:
                diag = float(json.load(f)['bbox_diag'])
        except (OSError, ValueError, KeyError, TypeError) as ex:
            sys.stderr.write('q2n_audit: %s: no bbox_diag in it (%s)\n' % (a.report, ex))
            return 1
    try:
        res = audit(a.file, a.mesh, max(0, a.samples), a.flat, not a.no_edges, a.check, diag)
    except Exception as ex:  # FreeCAD raises plain exceptions for unreadable files
        sys.stderr.write('q2n_audit: %s: %s\n' % (a.file, ex))
        return 1
    text = json.dumps(res, indent=1, sort_keys=True)
    if a.json:
        with open(a.json, 'w') as f:
            f.write(text + '\n')
    else:
        print(text)
    return 0


def main():
    ap = make_parser()
    a = ap.parse_args()
    if load_freecad() is None:
        sys.stderr.write('q2n_audit: FreeCAD is not installed (apt-get install freecad-python3)\n')
        return 2
    if not a.batch:
        return run_one(a)
    rc = 0
    with open(a.batch) as f:
        for line in f:
            if not line.strip() or line.lstrip().startswith('#'):
                continue
            try:
                rc = max(rc, run_one(make_parser().parse_args(shlex.split(line))))
            except SystemExit:  # argparse error in this line
                rc = max(rc, 1)
    return rc


if __name__ == '__main__':
    sys.exit(main())
