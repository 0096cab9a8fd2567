"""q2n_nurbs.py — vectorised (numpy) evaluation of the B-spline faces FreeCAD imported.

FreeCAD evaluates a surface one point per call (~5 µs each, plus Python overhead); a report of a
3000-face part needs millions of points with first and second derivatives.  Here each face's
poles, weights and knots are read from FreeCAD once (SurfaceData.from_face) and evaluated with
numpy: all basis functions and their derivatives by the Cox-de Boor recursion (The NURBS Book,
Piegl & Tiller, 2nd ed., eq. 2.5 and 2.10), one array operation per degree over all parameters,
matrix products with the poles, and the quotient rule of eq. 4.20 / Algorithm A4.4 for rational
surfaces.  tests/test_report.py holds every value and
derivative to OCCT's own evaluation (Surface.value / getDN) on imported faces.

NumpyFaceEval has the interface of q2n_audit.FaceEval (uv_on_edge, jets, edge_tangents), so the
import audit's continuity code runs unchanged on numpy-evaluated jets.
"""
import numpy as np

import q2n_audit


def find_spans(knots, p, t):
    """Knot span index i with U[i] <= t < U[i+1] for every t (clamped to the valid spans, so the
    end parameter and parameters a rounding error outside take the first or last span)."""
    n = len(knots) - p - 1                      # number of basis functions
    span = np.searchsorted(knots, t, side='right') - 1
    return np.minimum(np.maximum(span, p), n - 1)


def _inv(d):
    """1/d with 0/0 := 0, the convention of the Cox-de Boor recursion for repeated knots."""
    return np.where(d > 0, 1.0 / np.where(d > 0, d, 1.0), 0.0)


_RECIPROCALS = {}


def knot_reciprocals(U, p):
    """[k] -> 1/(u_{i+k} - u_i) for i < len(U) - 1 - k + 1 (0 where the difference is 0), k = 1..p;
    cached per knot vector: a part's faces share a few knot vectors."""
    key = (U.tobytes(), p)
    r = _RECIPROCALS.get(key)
    if r is None:
        if len(_RECIPROCALS) > 4096:
            _RECIPROCALS.clear()
        r = [None] + [_inv(U[k:] - U[:-k])[:, None] for k in range(1, p + 1)]
        _RECIPROCALS[key] = r
    return r


_BASES = {}
_BASES_BYTES = [0]
BASES_CACHE_BYTES = 256 << 20     # cap of the basis cache: faces of one part share a few knot vectors
                                  # and parameter sets (grids, edge samples), so most calls are repeats


def basis_matrix(knots, p, t, nd):
    """basis_matrix_uncached, remembered per (knots, degree, parameters, order)."""
    U = np.ascontiguousarray(knots, dtype=float)
    t = np.ascontiguousarray(t, dtype=float)
    key = (U.tobytes(), p, t.tobytes(), nd)
    B = _BASES.get(key)
    if B is None:
        B = basis_matrix_uncached(U, p, t, nd)
        B.setflags(write=False)
        if _BASES_BYTES[0] + B.nbytes > BASES_CACHE_BYTES:
            _BASES.clear()
            _BASES_BYTES[0] = 0
        _BASES[key] = B
        _BASES_BYTES[0] += B.nbytes
    return B


def basis_matrix_uncached(knots, p, t, nd):
    """Every B-spline basis function of degree p and its derivatives up to nd at the
    parameters t: array (nd+1, n, m), n = len(knots) - p - 1, m = len(t).
    Cox-de Boor recursion (The NURBS Book eq. 2.5) level by level, each level one array operation
    over all functions and parameters; the r-th derivative applies eq. 2.9/2.10,
    N'_{i,k} = k N_{i,k-1}/(u_{i+k} - u_i) - k N_{i+1,k-1}/(u_{i+k+1} - u_{i+1}),
    r times to the degree p-r functions.  Degree 0 is the indicator of find_spans' span, so the
    end parameter and parameters a rounding error outside the range extend the end pieces."""
    U = np.asarray(knots, dtype=float)
    t = np.asarray(t, dtype=float)
    m = len(t)
    rec = knot_reciprocals(U, p)
    levels = [np.zeros((len(U) - 1, m))]
    levels[0][find_spans(U, p, t), np.arange(m)] = 1.0
    for k in range(1, p + 1):
        n = len(U) - 1 - k
        a = (t[None, :] - U[:n, None]) * rec[k][:n]                     # (t - u_i)/(u_{i+k} - u_i)
        b = (U[k + 1:k + 1 + n, None] - t[None, :]) * rec[k][1:n + 1]   # (u_{i+k+1} - t)/(u_{i+k+1} - u_{i+1})
        prev = levels[-1]
        levels.append(a * prev[:-1] + b * prev[1:])
    out = [levels[p]]
    for r in range(1, nd + 1):
        if r > p:                                    # derivatives beyond the degree vanish
            out.append(np.zeros_like(levels[p]))
            continue
        D = levels[p - r]
        for k in range(p - r + 1, p + 1):
            n = D.shape[0] - 1
            D = k * (D[:-1] * rec[k][:n] - D[1:] * rec[k][1:n + 1])
        out.append(D)
    return np.stack(out)


def rational_jets(D):
    """S, Su, Sv, Suu, Suv, Svv from homogeneous derivatives D[a, b] = d^(a+b) (w P, w) / du^a dv^b
    (last axis: x w, y w, z w, w).  The NURBS Book eq. 4.20 / Algorithm A4.4 up to second order."""
    w = D[..., 3]
    A = D[..., :3]
    wi = 1.0 / w[0, 0][..., None]
    S = A[0, 0] * wi
    Su = (A[1, 0] - w[1, 0][..., None] * S) * wi
    Sv = (A[0, 1] - w[0, 1][..., None] * S) * wi
    Suu = (A[2, 0] - 2 * w[1, 0][..., None] * Su - w[2, 0][..., None] * S) * wi
    Suv = (A[1, 1] - w[1, 1][..., None] * S - w[1, 0][..., None] * Sv - w[0, 1][..., None] * Su) * wi
    Svv = (A[0, 2] - 2 * w[0, 1][..., None] * Sv - w[0, 2][..., None] * S) * wi
    return S, Su, Sv, Suu, Suv, Svv


class SurfaceData:
    """One B-spline surface as numpy arrays: poles (nu, nv, 3), weights (nu, nv) or None when
    polynomial, full knot sequences, degrees; evaluation of points and derivatives to order 2."""

    def __init__(self, poles, weights, uknots, vknots, p, q):
        self.poles = np.asarray(poles, dtype=float)
        self.weights = None if weights is None else np.asarray(weights, dtype=float)
        self.uknots = np.asarray(uknots, dtype=float)
        self.vknots = np.asarray(vknots, dtype=float)
        self.p, self.q = int(p), int(q)
        if self.weights is None:
            self.cp = self.poles
        else:
            self.cp = np.concatenate([self.poles * self.weights[..., None], self.weights[..., None]], axis=2)

    @classmethod
    def from_surface(cls, s):
        """From a FreeCAD Part.BSplineSurface (a periodic one is first made non-periodic on a copy).
        Returns None for other surface types."""
        if type(s).__name__ != 'BSplineSurface':
            return None
        if s.isUPeriodic() or s.isVPeriodic():
            s = s.copy()
            if s.isUPeriodic():
                s.setUNotPeriodic()
            if s.isVPeriodic():
                s.setVNotPeriodic()
        pw = np.array(s.getPolesAndWeights(), dtype=float)      # (nu, nv, 4): x, y, z, w
        rational = s.isURational() or s.isVRational()
        return cls(pw[..., :3], pw[..., 3] if rational else None, s.UKnotSequence, s.VKnotSequence,
                   s.UDegree, s.VDegree)

    @property
    def pole_count(self):
        return self.poles.shape[0] * self.poles.shape[1]

    @property
    def span_count(self):
        return (len(np.unique(self.uknots)) - 1) * (len(np.unique(self.vknots)) - 1)

    def _jets(self, D):
        if self.weights is None:
            return D[0, 0], D[1, 0], D[0, 1], D[2, 0], D[1, 1], D[0, 2]
        return rational_jets(D)

    def _contract_v(self, Nv):
        """T[b, i, c, l] = sum_j Nv[b, j, l] cp[i, j, c]: one matrix product per derivative order."""
        nu, nv, c = self.cp.shape
        flat = self.cp.transpose(0, 2, 1).reshape(nu * c, nv)
        return np.stack([(flat @ Nv[b]).reshape(nu, c, -1) for b in range(Nv.shape[0])])

    def eval_points(self, u, v):
        """S, Su, Sv, Suu, Suv, Svv at the points (u[i], v[i]): six (n, 3) arrays."""
        Nu = basis_matrix(self.uknots, self.p, u, 2)
        Nv = basis_matrix(self.vknots, self.q, v, 2)
        D = np.einsum('aik,bick->abkc', Nu, self._contract_v(Nv))          # (3, 3, n, c)
        return self._jets(D)

    def eval_grid(self, us, vs):
        """S, Su, Sv, Suu, Suv, Svv on the tensor grid us x vs: six (len(us), len(vs), 3) arrays."""
        Nu = basis_matrix(self.uknots, self.p, us, 2)
        Nv = basis_matrix(self.vknots, self.q, vs, 2)
        D = np.einsum('aik,bicl->abklc', Nu, self._contract_v(Nv))         # (3, 3, nuq, nvq, c)
        return self._jets(D)


class CurveData:
    """One B-spline edge curve as numpy arrays; first derivatives (the edge's own direction, as
    OCCT's Edge.tangentAt, which ignores the edge's orientation in a face)."""

    def __init__(self, poles, weights, knots, p):
        self.knots = np.asarray(knots, dtype=float)
        self.p = int(p)
        poles = np.asarray(poles, dtype=float)
        self.rational = weights is not None
        self.cp = poles if weights is None else np.concatenate(
            [poles * np.asarray(weights, dtype=float)[:, None], np.asarray(weights, dtype=float)[:, None]], axis=1)

    @classmethod
    def from_edge(cls, edge):
        """From a FreeCAD edge whose curve is a Part.BSplineCurve (non-periodic); None otherwise."""
        try:
            c = edge.Curve
        except Exception:
            return None
        if type(c).__name__ != 'BSplineCurve' or c.isPeriodic():
            return None
        poles = [(v.x, v.y, v.z) for v in c.getPoles()]
        return cls(poles, c.getWeights() if c.isRational() else None, c.KnotSequence, c.Degree)

    def derivative(self, ts):
        """C'(t) at every t, shape (n, 3) (eq. 4.8 of The NURBS Book for rational curves)."""
        D = np.einsum('krn,rc->knc', basis_matrix(self.knots, self.p, ts, 1), self.cp)
        if not self.rational:
            return D[1]
        C = D[0, :, :3] / D[0, :, 3:]
        return (D[1, :, :3] - D[1, :, 3:] * C) / D[0, :, 3:]


def unit_normals(su, sv, flip):
    """Unit normals Su x Sv (reversed for a reversed face), rows of the last axis."""
    a, b = np.moveaxis(su, -1, 0), np.moveaxis(sv, -1, 0)
    n = np.stack([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]], axis=-1)
    ln = np.sqrt((n * n).sum(axis=-1, keepdims=True))
    n = n / np.where(ln > 0, ln, 1.0)
    return -n if flip else n


def mean_curvature(jet, n):
    """Mean curvature (k1 + k2)/2 with respect to the unit normals n:
    H = (e G - 2 f F + g E) / (2 (E G - F^2)), e = Suu.n, f = Suv.n, g = Svv.n (do Carmo §3-3).
    Positive where the surface bends towards n; 0 where the first fundamental form degenerates."""
    _, su, sv, suu, suv, svv = jet
    E, F, G = (su * su).sum(-1), (su * sv).sum(-1), (sv * sv).sum(-1)
    e, f, g = (suu * n).sum(-1), (suv * n).sum(-1), (svv * n).sum(-1)
    det = E * G - F * F
    ok = det > 0
    return np.where(ok, (e * G - 2 * f * F + g * E) / (2 * np.where(ok, det, 1.0)), 0.0)


class NumpyFaceEval:
    """q2n_audit.FaceEval's interface on numpy: p-curves that are lines (what OCCT builds for the
    four-sided untrimmed faces quad2nurbs writes) are evaluated as the affine maps they are;
    anything else falls back to OCCT per point (q2n_audit.FaceEval)."""

    def __init__(self, face, data=None):
        self.face = face
        self.flip = face.Orientation == 'Reversed'
        self.data = data if data is not None else SurfaceData.from_surface(face.Surface)
        self.occt = None if self.data is not None else q2n_audit.FaceEval(face)
        self._lines = {}

    def _pcurve_line(self, edge):
        """(uv at t0, duv/dt, t0) when the edge's p-curve on this face is a line, else None."""
        key = edge.hashCode()
        if key not in self._lines:
            line = None
            try:
                c2, a, b = self.face.curveOnSurface(edge)
                if type(c2).__name__ in ('Line2d', 'Line2dSegment') and b > a:
                    pa, pb = c2.value(a), c2.value(b)
                    uva = np.array([pa.x, pa.y])
                    line = (uva, (np.array([pb.x, pb.y]) - uva) / (b - a), a)
            except Exception:
                line = None
            self._lines[key] = line
        return self._lines[key]

    def uv_on_edge(self, edge, ts):
        line = self._pcurve_line(edge) if self.occt is None else None
        if line is None:
            if self.occt is None:
                self.occt_uv = getattr(self, 'occt_uv', None) or q2n_audit.FaceEval(self.face)
                return self.occt_uv.uv_on_edge(edge, ts)
            return self.occt.uv_on_edge(edge, ts)
        uv0, duv, t0 = line
        return uv0[None, :] + (np.asarray(ts) - t0)[:, None] * duv[None, :]

    def jets(self, uv):
        if self.occt is not None:
            return self.occt.jets(uv)
        uv = np.asarray(uv, dtype=float).reshape(-1, 2)
        S, Su, Sv, Suu, Suv, Svv = self.data.eval_points(uv[:, 0], uv[:, 1])
        return S, unit_normals(Su, Sv, self.flip), Su, Sv, Suu, Suv, Svv

    def edge_tangents(self, edge, ts, uv, jet):
        """Unit tangents of the edge's B-spline curve (the same as OCCT's edge.tangentAt, which is
        used for other curves)."""
        c = CurveData.from_edge(edge)
        if c is None:
            return q2n_audit.occt_edge_tangents(edge, ts)
        return q2n_audit.unit_rows(c.derivative(np.asarray(ts, dtype=float)))
