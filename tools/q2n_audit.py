#!/usr/bin/python3
"""q2n_audit.py — import a STEP or IGES file with FreeCAD (OpenCASCADE) and audit it.

An importer nobody here wrote checks what quad2nurbs exported:
  * topology: face count, isValid(), shells, solids, edges, free edges (used by one face only),
    non-manifold edges (used by more than two faces), the largest edge / vertex tolerance OCCT
    assigned on import (it raises them to cover gaps it finds: 1e-7 means none), and with --check
    the full BRepCheck (shape.check(True), seconds on ~1000 faces);
  * continuity across every shared edge, in the terms of Rhino's EdgeContinuity, sampled between
    the fit's collocation points (default: in every knot span of the edge curve, the 4 midpoints
    between its 4 fit samples — the odd eighths of the span, the fit's rule in src/fit/ — so the
    audit samples the very points quad2nurbs' report measures; --samples N takes N points at
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
  * with --mesh: the distance of every mesh vertex to the imported shape.
Run with /usr/bin/python3 (Debian freecad-python3), not freecadcmd.  Output: JSON (stdout or --json);
--batch LIST audits many files in one process (FreeCAD loads once, ~0.5 s saved per file).
Exit status 0 after a successful audit, 2 when FreeCAD is missing, 1 when the file cannot be read.
Summary fields g0_max_rel (gap / bbox diagonal), g1_max_deg, g2_max_rel and faces use the names of
quad2nurbs' own report, so tools/q2n_compare.py can put the two side by side.
"""
import argparse
import json
import math
import os
import shlex
import sys
import time

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


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def norm(a):
    return math.sqrt(dot(a, a))


def unit(a):
    n = norm(a)
    return (a[0] / n, a[1] / n, a[2] / n) if n > 0 else a


def vec(v):
    return (v.x, v.y, v.z)


class FaceEval:
    """One face's surface (cached: Face.Surface returns a new copy on every access) and orientation."""

    def __init__(self, face):
        self.face = face
        self.surf = face.Surface
        self.flip = face.Orientation == 'Reversed'

    def uv_on_edge(self, edge, ts):
        """(u, v) of the edge's p-curve on this face at edge parameters ts; projection as fallback."""
        try:
            pc = self.face.curveOnSurface(edge)
        except Exception:
            pc = None
        if pc:
            c2 = pc[0]
            out = []
            for t in ts:
                p = c2.value(t)
                out.append((p.x, p.y))
            return out
        return [self.surf.parameter(edge.valueAt(t)) for t in ts]

    def jet(self, u, v):
        """Point, oriented unit normal, Su, Sv, Suu, Suv, Svv."""
        s = self.surf
        p = vec(s.value(u, v))
        su, sv = vec(s.getDN(u, v, 1, 0)), vec(s.getDN(u, v, 0, 1))
        suu, suv, svv = vec(s.getDN(u, v, 2, 0)), vec(s.getDN(u, v, 1, 1)), vec(s.getDN(u, v, 0, 2))
        n = unit(cross(su, sv))
        if self.flip:
            n = (-n[0], -n[1], -n[2])
        return p, n, su, sv, suu, suv, svv

    @staticmethod
    def normal_curvature(jet, d):
        """Normal curvature in tangent direction d: II(w,w)/I(w,w) with d = a Su + b Sv."""
        _, n, su, sv, suu, suv, svv = jet
        E, F, G = dot(su, su), dot(su, sv), dot(sv, sv)
        r1, r2 = dot(d, su), dot(d, sv)
        det = E * G - F * F
        if det <= 0:
            return 0.0
        a = (G * r1 - F * r2) / det
        b = (E * r2 - F * r1) / det
        num = a * a * dot(suu, n) + 2 * a * b * dot(suv, n) + b * b * dot(svv, n)
        den = a * a * E + 2 * a * b * F + b * b * G
        return num / den if den > 0 else 0.0


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


def edge_params(edge, nsamp):
    """Sample parameters on this edge: nsamp points at (i + 0.5)/nsamp of its range, or (nsamp == 0)
    the fit's rule: in every knot span of the edge curve, the midpoints between its 4 samples per
    span, i.e. the odd eighths (src/fit/fit_basis.c, q2n_fit_check_params)."""
    t0, t1 = edge.ParameterRange
    if nsamp <= 0:
        try:
            kn = list(edge.Curve.getKnots())
        except Exception:  # not a B-spline edge curve
            kn = []
        if len(kn) >= 2:
            return [a + (b - a) * (2 * j + 1) / 8.0 for a, b in zip(kn[:-1], kn[1:]) for j in range(4)]
        nsamp = 16
    return [t0 + (i + 0.5) / nsamp * (t1 - t0) for i in range(nsamp)]


def audit_edge(edge, fa, fb, nsamp, k_flat, diag):
    ts = edge_params(edge, nsamp)
    uva, uvb = fa.uv_on_edge(edge, ts), fb.uv_on_edge(edge, ts)
    res = {'g0': 0.0, 'g1_deg': 0.0, 'g2_abs': 0.0, 'g2_rel_radii': 0.0, 'g2_rel': 0.0,
           'g0_at': None, 'g1_at': None, 'g2_at': None}
    for t, (ua, va), (ub, vb) in zip(ts, uva, uvb):
        ja, jb = fa.jet(ua, va), fb.jet(ub, vb)
        pa, pb = ja[0], jb[0]
        gap = norm(sub(pa, pb))
        # atan2(|na x nb|, na . nb): accurate for tiny angles, where acos loses half the digits
        ang = math.degrees(math.atan2(norm(cross(ja[1], jb[1])), dot(ja[1], jb[1])))
        tan = unit(vec(edge.tangentAt(t)))
        d = unit(cross(ja[1], tan))
        ka = FaceEval.normal_curvature(ja, d)
        kb = FaceEval.normal_curvature(jb, d)
        g2a = abs(ka - kb)
        g2r = 0.0 if max(abs(ka), abs(kb)) < k_flat else g2a / (abs(ka) + abs(kb))
        res['g2_rel_radii'] = max(res['g2_rel_radii'], g2r)
        # the fit report's measure: three directions, jump over the largest curvature (>= 1/diag)
        jmax, kmax = 0.0, 1.0 / diag if diag > 0 else 0.0
        for w in (tan, d, unit((tan[0] + d[0], tan[1] + d[1], tan[2] + d[2]))):
            kwa, kwb = FaceEval.normal_curvature(ja, w), FaceEval.normal_curvature(jb, w)
            jmax, kmax = max(jmax, abs(kwa - kwb)), max(kmax, abs(kwa), abs(kwb))
        g2r = jmax / kmax if kmax > 0 else 0.0
        if gap >= res['g0']:
            res['g0'], res['g0_at'] = gap, pa
        if ang >= res['g1_deg']:
            res['g1_deg'], res['g1_at'] = ang, pa
        if g2r > res['g2_rel'] or res['g2_at'] is None:
            res['g2_rel'], res['g2_at'] = max(res['g2_rel'], g2r), pa
        res['g2_abs'] = max(res['g2_abs'], g2a)
    return res


def box_distance(bb, p):
    """Lower bound: distance from p to an axis-aligned box."""
    dx = max(bb.XMin - p[0], 0.0, p[0] - bb.XMax)
    dy = max(bb.YMin - p[1], 0.0, p[1] - bb.YMax)
    dz = max(bb.ZMin - p[2], 0.0, p[2] - bb.ZMax)
    return math.sqrt(dx * dx + dy * dy + dz * dz)


def vertex_distance(Part, faces, boxes, p):
    """Distance from p to the union of faces: exact distToShape per face, nearest bounding boxes
    first, stopping when the next box is farther than the best distance found (the whole-shape
    distToShape costs ~90 ms per point, this ~2 ms)."""
    import FreeCAD
    order = sorted((box_distance(bb, p), k) for k, bb in enumerate(boxes))
    vx = Part.Vertex(FreeCAD.Vector(*p))
    best = math.inf
    for lb, k in order:
        if lb >= best:
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


def audit(path, mesh=None, nsamp=0, flat=100.0, per_edge=True, check=False):
    Part = load_freecad()
    if Part is None:
        return None
    t_start = time.time()
    shape = Part.read(path)
    t_read = time.time() - t_start
    faces = shape.Faces
    evals = [FaceEval(f) for f in faces]
    verts = read_obj_vertices(mesh) if mesh else None
    if verts:
        lo = [min(v[i] for v in verts) for i in range(3)]
        hi = [max(v[i] for v in verts) for i in range(3)]
        diag = norm(sub(hi, lo))
    else:
        diag = bbox_diag_of(shape)
    k_flat = 1.0 / (flat * diag) if diag > 0 else 0.0
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
        'samples_per_edge': nsamp if nsamp > 0 else '4 per knot span',
        'flat_radius': flat * diag,
        'area': shape.Area,
        'max_edge_tolerance': max((e.Tolerance for e in shape.Edges), default=0.0),
        'max_vertex_tolerance': max((v.Tolerance for v in shape.Vertexes), default=0.0),
        'volume': shape.Volume if shape.Solids else None,
    }
    worst = {'g0': (0.0, None, None), 'g1_deg': (0.0, None, None), 'g2_rel': (0.0, None, None)}
    g2_abs = g2_radii = 0.0
    detail = []
    for ei, (e, fl) in enumerate(edges):
        if len(fl) != 2:
            continue
        r = audit_edge(e, evals[fl[0]], evals[fl[1]], nsamp, k_flat, diag)
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
    if verts is not None:
        dmax, imax = 0.0, -1
        boxes = [f.BoundBox for f in faces]
        for i, v in enumerate(verts):
            d = vertex_distance(Part, faces, boxes, v)
            if d > dmax or imax < 0:
                dmax, imax = max(d, dmax), i
        out['mesh'] = {'file': os.path.basename(mesh), 'vertices': len(verts),
                       'max_vertex_dist': dmax, 'max_vertex_dist_rel': dmax / diag if diag > 0 else dmax,
                       'worst_vertex': imax}
    if check:
        out['check'] = full_check(shape)
    out['seconds_read'] = t_read
    out['seconds_audit'] = time.time() - t_start - t_read
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
    try:
        res = audit(a.file, a.mesh, max(0, a.samples), a.flat, not a.no_edges, a.check)
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
