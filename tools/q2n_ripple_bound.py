#!/usr/bin/python3
"""q2n_ripple_bound.py — how much a fair interpolant of a height-field or a closed mesh must ripple and bend.

    /usr/bin/python3 tools/q2n_ripple_bound.py MESH.obj [--self-test]

Issue 11's ripple figure (../shared/tools/fairness.py: curvature oscillation per diagonal of the
faces at extraordinary vertices, osc = (TV(H) - |H_end - H_start|) * L / 2 along each diagonal)
asks an interpolant of the mesh's vertices for at most 0.3 per diagonal.  On meshes whose
vertices lie off any smooth surface (random heights, dropped creases) no interpolant may reach it.
This script measures that for meshes that are height fields over their best-fit plane (every face
keeps its orientation when projected): it builds the interpolant that minimises the (linearised)
curvature variation int |D^3 z|^2 over the whole plane — the polyharmonic spline
z(p) = sum_i w_i phi(|p - p_i|) + a quadratic, phi(r) = r^4 log r (Duchon), the third-order
analogue of the thin-plate spline, whose curvature is continuous at the data points (the
thin-plate spline's is log-singular there) — and reports its oscillation along the straight
diagonals (in the plane) of the faces at extraordinary vertices, with fairness.py's definitions
(extraordinary: interior valence != 4, boundary valence not 2 or 3; mean curvature of the graph).
It also prints the bending energy int (k1^2 + k2^2) dA over those faces (the planar quads lifted
to the graph) of that spline (E_ev) and of the thin-plate spline (phi = r^2 log r, E_ev_thin_plate),
the interpolant of least linearised bending energy int |D^2 z|^2, the reference for the energy
target.

Closed meshes (every edge in two faces; stop 45) get the same kind of reference in spherical terms,
where they are star-shaped about their vertices' centroid c: the radius along each direction,
r(w) = sum_i w_i |w - w_i|^3 + a0 + a . w (w on the unit sphere, |.| the chordal distance: the
third-order polyharmonic spline of R^3, r^3, restricted to the sphere, with a linear part), through
the vertices' radii, and the surface X(w) = c + r(w) w.  Every mesh whose vertices lie on a sphere
gets that sphere back (the spline reproduces constants).  The faces are the bilinear quads mapped
radially onto it, the lines their two parameter diagonals, and H, K come from finite differences
(step 1e-4 in the face's parameters) of that composed map; "reference": "radial" in the output, and
exit 1 with "star_shaped": false where a face's radial image turns over (its normal against the
radius somewhere), two vertices lie on one ray from c or one at c, or a face is not a quad.

It is an independent reference, not a lower bound in the strict sense: the construction minimises
a parametric energy per patch, fairness.py follows the patches' parameter diagonals; but where the
fairest interpolant of this kind ripples more than the target allows, the target asks the
interpolation for what the data do not have (docs/extraordinary.md, "Where the ripple target is
not met, and why").  numpy only.  Prints one JSON object; exit 0, 1 when an open mesh is not a height
field or a closed one not star-shaped, 2 on bad input.  --self-test checks the spline against a
quadratic it must reproduce, finite differences and its data, the energy quadrature against a sphere
cap's closed form, and the radial reference against a sphere (a cube's corners: bending energy 8 pi,
no oscillation) and its data, then exits.
"""
import json
import sys

import numpy as np


def read_obj(path):
    V, F = [], []
    with open(path, encoding='utf-8-sig') as fh:
        for line in fh:
            s = line.split()
            if not s:
                continue
            if s[0] == 'v':
                V.append([float(x) for x in s[1:4]])
            elif s[0] == 'f':
                F.append([int(x.split('/')[0]) for x in s[1:]])
    V = np.array(V, dtype=float)
    F = [[i - 1 if i > 0 else len(V) + i for i in f] for f in F]
    return V, F


def edge_counts(F):
    """{(a, b), a < b: the number of faces of F with that edge}"""
    edges = {}
    for f in F:
        for i in range(len(f)):
            a, b = f[i], f[(i + 1) % len(f)]
            k = (min(a, b), max(a, b))
            edges[k] = edges.get(k, 0) + 1
    return edges


def extraordinary(nv, F):
    edges = edge_counts(F)
    val = np.zeros(nv, int)
    bd = np.zeros(nv, bool)
    for (a, b), c in edges.items():
        val[a] += 1
        val[b] += 1
        if c == 1:
            bd[a] = bd[b] = True
    return {v for v in range(nv) if (bd[v] and val[v] not in (2, 3)) or (not bd[v] and val[v] != 4)}


def quad_basis(P):
    x, y = P[:, 0], P[:, 1]
    o, z = np.ones_like(x), np.zeros_like(x)
    return (np.stack([o, x, y, x * x, x * y, y * y], 1), np.stack([z, o, z, 2 * x, y, z], 1),
            np.stack([z, z, o, z, x, 2 * y], 1))


def solve_spline(P, h, phi, Q):
    """weights w and polynomial coefficients a of sum_i w_i phi(|p - p_i|^2) + Q(p) . a through
    (P, h), with Q(P)^T w = 0 (the side conditions of a polyharmonic spline)"""
    n, q = len(P), Q.shape[1]
    r2 = ((P[:, None, :] - P[None, :, :]) ** 2).sum(2)
    with np.errstate(divide='ignore', invalid='ignore'):
        K = np.where(r2 > 0, phi(r2), 0.0)
    A = np.zeros((n + q, n + q))
    A[:n, :n], A[:n, n:], A[n:, :n] = K, Q, Q.T
    sol = np.linalg.solve(A, np.concatenate([h, np.zeros(q)]))
    return sol[:n], sol[n:]


def fit(P, h):
    """the r^4 log r spline through (P, h): phi = s^2 log(s) / 4 = r^4 log(r) / 2 (s = r^2), a quadratic"""
    return solve_spline(P, h, lambda s: 0.25 * s * s * np.log(s), quad_basis(P)[0])


def evaluate(P, w, a, X):
    """value, gradient (2) and Hessian (xx, xy, yy) of the spline at X"""
    d = X[:, None, :] - P[None, :, :]
    s = np.maximum((d ** 2).sum(2), 1e-300)
    ls = np.log(s)
    # phi = s^2 log(s) / 4: dphi/ds = s log(s) / 2 + s / 4, d2phi/ds2 = log(s) / 2 + 3 / 4
    f1, f2 = 0.5 * s * ls + 0.25 * s, 0.5 * ls + 0.75
    Q, Qx, Qy = quad_basis(X)
    z = (w * 0.25 * s * s * ls).sum(1) + Q @ a
    g = (w[None, :, None] * 2 * d * f1[..., None]).sum(1) + np.stack([Qx @ a, Qy @ a], 1)
    hxx = (w * (2 * f1 + 4 * d[..., 0] ** 2 * f2)).sum(1) + 2 * a[3]
    hyy = (w * (2 * f1 + 4 * d[..., 1] ** 2 * f2)).sum(1) + 2 * a[5]
    hxy = (w * 4 * d[..., 0] * d[..., 1] * f2).sum(1) + a[4]
    return z, g, hxx, hxy, hyy


def fit_thin_plate(P, h):
    """the thin-plate spline through (P, h): phi = s log(s) / 2 = r^2 log r, a linear part"""
    return solve_spline(P, h, lambda s: 0.5 * s * np.log(s), np.hstack([np.ones((len(P), 1)), P]))


def evaluate_thin_plate(P, w, a, X):
    """gradient and Hessian of the thin-plate spline at X (its curvature is log-singular at P)"""
    d = X[:, None, :] - P[None, :, :]
    s = np.maximum((d ** 2).sum(2), 1e-300)
    f1, f2 = 0.5 * (np.log(s) + 1), 0.5 / s
    g = (w[None, :, None] * 2 * d * f1[..., None]).sum(1) + a[1:]
    hxx = (w * (2 * f1 + 4 * d[..., 0] ** 2 * f2)).sum(1)
    hyy = (w * (2 * f1 + 4 * d[..., 1] ** 2 * f2)).sum(1)
    hxy = (w * 4 * d[..., 0] * d[..., 1] * f2).sum(1)
    return g, hxx, hxy, hyy


def bending_energy(P, F, faces, derivs, n=40):
    """int (k1^2 + k2^2) dA of the graph over the planar quads `faces` (Gauss-Legendre n x n on the
    bilinear map of each quad)"""
    x, wq = np.polynomial.legendre.leggauss(n)
    x, wq = (x + 1) / 2, wq / 2
    U, V = (t.ravel() for t in np.meshgrid(x, x))
    WW = np.outer(wq, wq).ravel()
    E = 0.0
    for k in faces:
        p = P[F[k]]
        X = ((1 - U) * (1 - V))[:, None] * p[0] + (U * (1 - V))[:, None] * p[1] + (U * V)[:, None] * p[2] + ((1 - U) * V)[:, None] * p[3]
        Xu = (1 - V)[:, None] * (p[1] - p[0]) + V[:, None] * (p[2] - p[3])
        Xv = (1 - U)[:, None] * (p[3] - p[0]) + U[:, None] * (p[2] - p[1])
        J = np.abs(Xu[:, 0] * Xv[:, 1] - Xu[:, 1] * Xv[:, 0])
        g, hxx, hxy, hyy = derivs(X)
        p_, q_ = g[:, 0], g[:, 1]
        Wd = 1 + p_ * p_ + q_ * q_
        e1, f1, g1 = 1 + p_ * p_, p_ * q_, 1 + q_ * q_
        l, m, nn = hxx / np.sqrt(Wd), hxy / np.sqrt(Wd), hyy / np.sqrt(Wd)
        det = e1 * g1 - f1 * f1
        H = (e1 * nn - 2 * f1 * m + g1 * l) / (2 * det)
        K = (l * nn - m * m) / det
        E += float(((4 * H * H - 2 * K) * np.sqrt(Wd) * J * WW).sum())
    return E


def mean_curvature(g, hxx, hxy, hyy):
    p, q = g[:, 0], g[:, 1]
    W = 1 + p * p + q * q
    return ((1 + q * q) * hxx - 2 * p * q * hxy + (1 + p * p) * hyy) / (2 * W ** 1.5)


def osc(H, X3):
    """fairness.py's oscillation of one line"""
    L = float(np.linalg.norm(np.diff(X3, axis=0), axis=1).sum())
    return (float(np.abs(np.diff(H)).sum()) - abs(float(H[-1] - H[0]))) * L / 2


def closed(F):
    """every edge of F in exactly two faces"""
    edges = edge_counts(F)
    return bool(edges) and all(c == 2 for c in edges.values())


def fit_radial(V, c):
    """the radius function r(w) = sum_i w_i |w - w_i|^3 + a0 + a . w through the vertices' radii about c:
    returns X(P), the radial surface point of the points P (m x 3)"""
    q = V - c
    r = np.linalg.norm(q, axis=1)
    Om = q / r[:, None]
    n = len(V)
    K = np.sqrt(((Om[:, None] - Om[None]) ** 2).sum(2)) ** 3
    Q = np.hstack([np.ones((n, 1)), Om])
    A = np.zeros((n + 4, n + 4))
    A[:n, :n], A[:n, n:], A[n:, :n] = K, Q, Q.T
    sol = np.linalg.solve(A, np.concatenate([r, np.zeros(4)]))
    w, a = sol[:n], sol[n:]

    def X(P):
        o = P - c
        o = o / np.linalg.norm(o, axis=1)[:, None]
        D = np.sqrt(np.maximum(((o[:, None] - Om[None]) ** 2).sum(2), 0.0))
        return c + ((D ** 3) @ w + a[0] + o @ a[1:])[:, None] * o
    return X


def radial_derivs(X, p, S, T, h=1e-4):
    """position, unit normal, H, K and area element of the radial image of the bilinear quad p at (S, T)"""
    def B(s, t):
        s, t = s[:, None], t[:, None]
        return (1 - s) * (1 - t) * p[0] + s * (1 - t) * p[1] + s * t * p[2] + (1 - s) * t * p[3]
    x = X(B(S, T))
    xp, xm, yp, ym = X(B(S + h, T)), X(B(S - h, T)), X(B(S, T + h)), X(B(S, T - h))
    xs, xt = (xp - xm) / (2 * h), (yp - ym) / (2 * h)
    xss, xtt = (xp - 2 * x + xm) / (h * h), (yp - 2 * x + ym) / (h * h)
    xst = (X(B(S + h, T + h)) - X(B(S + h, T - h)) - X(B(S - h, T + h)) + X(B(S - h, T - h))) / (4 * h * h)
    N = np.cross(xs, xt)
    J = np.linalg.norm(N, axis=1)
    N = N / J[:, None]
    E, Fm, G = (xs * xs).sum(1), (xs * xt).sum(1), (xt * xt).sum(1)
    L, M, Nn = (xss * N).sum(1), (xst * N).sum(1), (xtt * N).sum(1)
    det = E * G - Fm * Fm
    return x, N, (E * Nn - 2 * Fm * M + G * L) / (2 * det), (L * Nn - M * M) / det, J


def radial_reference(V, F, path):
    """the radial reference of a closed mesh (module docstring): its JSON object and exit status"""
    c = V.mean(0)
    rad = np.linalg.norm(V - c, axis=1)
    if any(len(f) != 4 for f in F) or not (rad.min() > 1e-9 * rad.max()):
        return {'mesh': path, 'reference': 'radial', 'star_shaped': False}, 1   # not all quads, or a vertex at c
    try:
        X = fit_radial(V, c)
    except np.linalg.LinAlgError:   # two vertices on one ray from c
        return {'mesh': path, 'reference': 'radial', 'star_shaped': False}, 1
    ev = extraordinary(len(V), F)
    gx, gw = np.polynomial.legendre.leggauss(16)
    gx, gw = (gx + 1) / 2, gw / 2
    U, W = (t.ravel() for t in np.meshgrid(gx, gx))
    WW = np.outer(gw, gw).ravel()
    t = np.linspace(0.0005, 0.9995, 400)
    E_ev, E, lines, turned = 0.0, 0.0, [], 0
    for f in F:
        if len(f) != 4:
            continue
        p = V[f]
        x, N, H, K, J = radial_derivs(X, p, U, W)
        turned += int((((x - c) * N).sum(1) <= 0).sum())
        e = float(((4 * H * H - 2 * K) * J * WW).sum())
        E += e
        if ev.intersection(f):
            E_ev += e
            for s_, t_ in ((t, t), (1 - t, t)):
                x, N, H, K, J = radial_derivs(X, p, s_, t_)
                turned += int((((x - c) * N).sum(1) <= 0).sum())
                lines.append(osc(H, x))
    if turned or not (np.isfinite(E) and all(np.isfinite(lines))):
        return {'mesh': path, 'reference': 'radial', 'star_shaped': False}, 1
    return {'mesh': path, 'reference': 'radial', 'star_shaped': True, 'extraordinary_vertices': len(ev), 'lines': len(lines),
            'osc_ev_mean': float(np.mean(lines)) if lines else 0.0, 'osc_ev_max': float(np.max(lines)) if lines else 0.0,
            'E_ev': E_ev, 'E': E}, 0


def self_test():
    rng = np.random.default_rng(1)
    P = rng.uniform(-1, 1, (30, 2))
    quad = lambda X: 0.3 * X[:, 0] ** 2 - 0.2 * X[:, 0] * X[:, 1] + 0.1 * X[:, 1] ** 2 + 0.5 * X[:, 0]
    w, a = fit(P, quad(P))
    X = rng.uniform(-1, 1, (50, 2))
    err_quad = float(np.abs(evaluate(P, w, a, X)[0] - quad(X)).max())
    w, a = fit(P, rng.uniform(0, 1, 30))
    h, e = 1e-5, np.array([1.0, 0.0])
    z, g, hxx, hxy, hyy = evaluate(P, w, a, X)
    zp, gp = evaluate(P, w, a, X + h * e)[:2]
    zm, gm = evaluate(P, w, a, X - h * e)[:2]
    err_fd = max(float(np.abs((zp - zm) / (2 * h) - g[:, 0]).max()), float(np.abs((gp[:, 0] - gm[:, 0]) / (2 * h) - hxx).max()),
                 float(np.abs((gp[:, 1] - gm[:, 1]) / (2 * h) - hxy).max()))
    wt, at = fit_thin_plate(P, rng.uniform(0, 1, 30))
    gt, txx, txy, _ = evaluate_thin_plate(P, wt, at, X)
    gtp, gtm = evaluate_thin_plate(P, wt, at, X + h * e)[0], evaluate_thin_plate(P, wt, at, X - h * e)[0]
    err_fd = max(err_fd, float(np.abs((gtp[:, 0] - gtm[:, 0]) / (2 * h) - txx).max()),
                 float(np.abs((gtp[:, 1] - gtm[:, 1]) / (2 * h) - txy).max()))
    hv = rng.uniform(0, 1, 30)
    w, a = fit(P, hv)
    err_interp = float(np.abs(evaluate(P, w, a, P)[0] - hv).max())
    # bending energy of a sphere cap of radius R over the square [-b, b]^2 (four quads): 2 / R^2 times
    # its area, R * int 2 arcsin(b / sqrt(R^2 - x^2)) dx over [-b, b] (a 1-D Gauss sum)
    R, b = 2.0, 0.5
    Pq = np.array([[x, y] for y in (-b, 0, b) for x in (-b, 0, b)])
    Fq = [[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]]

    def sphere(X):
        x, y = X[:, 0], X[:, 1]
        r = np.sqrt(R * R - x * x - y * y)
        return (np.stack([-x / r, -y / r], 1), -(R * R - y * y) / r ** 3, -x * y / r ** 3, -(R * R - x * x) / r ** 3)
    xg, wg = np.polynomial.legendre.leggauss(60)
    area = float((b * wg * R * 2 * np.arcsin(b / np.sqrt(R * R - (b * xg) ** 2))).sum())
    err_energy = abs(bending_energy(Pq, Fq, range(4), sphere) / (2 * area / R ** 2) - 1)
    # the radial reference: a cube's corners lie on a sphere, which it must give back (bending energy
    # 8 pi, every vertex extraordinary, no oscillation); an ellipsoid's octahedron, through its vertices
    Vc = np.array([[x, y, z] for x in (-1.0, 1.0) for y in (-1.0, 1.0) for z in (-1.0, 1.0)])
    Fc = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
    rad, rc = radial_reference(Vc, Fc, 'cube')
    err_radial_energy = abs(rad.get('E', 0) / (8 * np.pi) - 1) if rc == 0 else 1.0
    osc_sphere = rad.get('osc_ev_mean', 1.0)
    Ve = rng.uniform(-1, 1, (40, 3))
    Ve = Ve / np.linalg.norm(Ve, axis=1)[:, None] * np.array([2.0, 1.0, 0.5])
    err_radial_interp = float(np.abs(fit_radial(Ve, Ve.mean(0))(Ve) - Ve).max())
    ok = (err_quad < 1e-9 and err_fd < 1e-5 and err_interp < 1e-9 and err_energy < 1e-9 and err_radial_energy < 1e-6
          and osc_sphere < 1e-3 and err_radial_interp < 1e-9)
    print(json.dumps({'self_test': 'ok' if ok else 'FAILED', 'quadratic_reproduction': err_quad, 'finite_differences': err_fd,
                      'interpolation': err_interp, 'sphere_energy_rel': err_energy, 'radial_sphere_energy_rel': err_radial_energy,
                      'radial_sphere_osc': osc_sphere, 'radial_interpolation': err_radial_interp}))
    return 0 if ok else 1


def main(argv):
    if '--self-test' in argv:
        return self_test()
    if len(argv) != 1:
        print(__doc__.split('\n\n')[1], file=sys.stderr)
        return 2
    try:
        V, F = read_obj(argv[0])
    except (OSError, ValueError, IndexError) as e:
        print(f'q2n_ripple_bound: {argv[0]}: {e}', file=sys.stderr)
        return 2
    if len(V) < 7 or not F:
        print(f'q2n_ripple_bound: {argv[0]}: too few vertices or no faces', file=sys.stderr)
        return 2
    if closed(F):
        out, rc = radial_reference(V, F, argv[0])
        print(json.dumps(out))
        return rc
    c = V.mean(0)
    W = np.linalg.svd(V - c)[2]
    P = np.stack([(V - c) @ W[0], (V - c) @ W[1]], 1)
    h = (V - c) @ W[2]
    signs = [np.sign(sum(P[f[i], 0] * P[f[(i + 1) % len(f)], 1] - P[f[(i + 1) % len(f)], 0] * P[f[i], 1]
                          for i in range(len(f)))) for f in F]
    if len(set(signs)) != 1 or signs[0] == 0:
        print(json.dumps({'mesh': argv[0], 'height_field': False}))
        return 1
    w, a = fit(P, h)
    ev = extraordinary(len(V), F)
    lines = []
    t = np.linspace(0, 1, 400)[:, None]
    for f in F:
        if len(f) != 4 or not ev.intersection(f):
            continue
        for i, j in ((0, 2), (1, 3)):
            X = P[f[i]] * (1 - t) + P[f[j]] * t
            z, g, hxx, hxy, hyy = evaluate(P, w, a, X)
            lines.append(osc(mean_curvature(g, hxx, hxy, hyy), np.hstack([X, z[:, None]])))
    evf = [k for k, f in enumerate(F) if len(f) == 4 and ev.intersection(f)]
    wt, at = fit_thin_plate(P, h)
    out = {'mesh': argv[0], 'reference': 'height_field', 'height_field': True, 'extraordinary_vertices': len(ev), 'lines': len(lines),
           'osc_ev_mean': float(np.mean(lines)) if lines else 0.0, 'osc_ev_max': float(np.max(lines)) if lines else 0.0,
           'E_ev': bending_energy(P, F, evf, lambda X: evaluate(P, w, a, X)[1:]),
           'E_ev_thin_plate': bending_energy(P, F, evf, lambda X: evaluate_thin_plate(P, wt, at, X))}
    print(json.dumps(out))
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
