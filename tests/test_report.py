#!/usr/bin/python3
"""test_report.py — the HTML continuity report (tools/q2n_report.py) and what it is built on.

Run by build/tests/test_report (tests/test_report.c) with /usr/bin/python3 from the repository root;
prints FAIL/SKIP lines and "test_report: N passed, N failed, N skipped" like the C tests.
  numpy evaluation (tools/q2n_nurbs.py) against OpenCASCADE's own (Surface.value / getDN /
    curvature, Edge.tangentAt) on the faces of a fitted file and on a rational sphere and cylinder,
    and against closed forms (sphere radius, mean curvature 1/r and 1/(2r));
  the renderer (tools/q2n_render.py) against closed forms: pixel coverage of a square, the depth
    test, zebra stripes of a tessellated sphere against the stripes of its exact normals;
  the import audit on numpy-evaluated jets against the audit on OCCT's (tools/q2n_audit.py, the CLI);
  the report of the demo torus and of a mesh with an extraordinary vertex: every number the page
    shows from quad2nurbs' report equals the report JSON, every audit number the audit JSON, the
    count of extraordinary vertices the mesh's own, every image a decodable PNG data URI, nothing
    loaded from outside the file; headless Chromium loads the page with every image decoded and the
    screenshot is not blank where the images are;
  bad input: one line on stderr, exit 1, no output file.
Skips, saying so, when FreeCAD, matplotlib, Chromium, the executable or the shared meshes are missing.
"""
import base64
import glob
import html.parser
import io
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TOOLS = os.path.join(ROOT, 'tools')
OUT = os.path.join(ROOT, 'build', 'tests', 'report_')
EXE = os.path.join(ROOT, 'build', 'quad2nurbs')
PY = '/usr/bin/python3'
sys.path.insert(0, TOOLS)

passed = failed = skipped = 0


def check(cond, what):
    global passed, failed
    if cond:
        passed += 1
    else:
        failed += 1
        f = sys._getframe(1)
        print('FAIL %s:%d: %s' % (os.path.basename(f.f_code.co_filename), f.f_lineno, what), flush=True)
    return cond


def skip(what):
    global skipped
    skipped += 1
    print('SKIP %s' % what, flush=True)


def done():
    print('test_report: %d passed, %d failed, %d skipped' % (passed, failed, skipped))
    sys.exit(1 if failed else 0)


def shared_mesh(name):
    p = os.path.join(os.environ.get('Q2N_SHARED_MESHES', os.path.join(ROOT, '..', 'shared', 'meshes')), name)
    return p if os.access(p, os.R_OK) else None


def run(cmd, **kw):
    return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, universal_newlines=True, **kw)


# ---------------------------------------------------------------------------------------------

def test_evaluator(Part, step):
    """numpy values and derivatives = OCCT's at random points (and the corners) of every face."""
    import numpy as np
    import q2n_nurbs
    shape = Part.read(step)
    rng = np.random.default_rng(7)
    worst = worst_h = 0.0
    for f in shape.Faces[::4]:
        S = f.Surface
        d = q2n_nurbs.SurfaceData.from_surface(S)
        u = np.r_[0.0, 1.0, 0.0, 1.0, rng.random(8)]
        v = np.r_[0.0, 0.0, 1.0, 1.0, rng.random(8)]
        jet = d.eval_points(u, v)
        scale = np.abs(d.poles).max()
        n = q2n_nurbs.unit_normals(jet[1], jet[2], False)
        H = q2n_nurbs.mean_curvature(jet, n)
        for i in range(len(u)):
            ref = [S.value(u[i], v[i])] + [S.getDN(u[i], v[i], a, b) for a, b in ((1, 0), (0, 1), (2, 0), (1, 1), (0, 2))]
            for k in range(6):
                r = np.array([ref[k].x, ref[k].y, ref[k].z])
                worst = max(worst, np.abs(jet[k][i] - r).max() / (scale + np.abs(r).max()))
            hr = S.curvature(u[i], v[i], 'Mean')
            worst_h = max(worst_h, abs(H[i] - hr) / max(1.0, abs(hr)))
    check(worst < 1e-11, 'numpy point and derivatives vs OCCT getDN: relative error %.3g (> 1e-11)' % worst)
    check(worst_h < 1e-7, 'numpy mean curvature vs OCCT Surface.curvature: relative error %.3g (> 1e-7)' % worst_h)
    # a grid equals the same points one by one
    d = q2n_nurbs.SurfaceData.from_surface(shape.Faces[0].Surface)
    us, vs = np.linspace(0, 1, 7), np.linspace(0, 1, 5)
    g = d.eval_grid(us, vs)
    p = d.eval_points(np.repeat(us, 5), np.tile(vs, 7))
    check(max(np.abs(g[k].reshape(-1, 3) - p[k]).max() for k in range(6)) < 1e-13, 'eval_grid != eval_points')
    # edge tangents = OCCT's tangentAt (the edge's own direction)
    import q2n_audit
    worst_t = 0.0
    for e, _ in q2n_audit.edge_faces(shape)[:60]:
        c = q2n_nurbs.CurveData.from_edge(e)
        ts = q2n_audit.edge_sample_params(e, 0)
        worst_t = max(worst_t, np.abs(q2n_audit.unit_rows(c.derivative(ts)) - q2n_audit.occt_edge_tangents(e, ts)).max())
    check(worst_t < 1e-10, 'edge tangents vs OCCT tangentAt: %.3g' % worst_t)


def test_rational(Part):
    """Rational B-splines (FreeCAD's NURBS form of a sphere and a cylinder): OCCT and closed forms."""
    import numpy as np
    import q2n_nurbs
    rng = np.random.default_rng(3)
    for shape, r, h_expect, name in ((Part.makeSphere(2.0), 2.0, 1 / 2.0, 'sphere'),
                                     (Part.makeCylinder(1.5, 4.0), 1.5, 1 / 3.0, 'cylinder')):
        f = shape.toNurbs().Faces[0]
        S = f.Surface
        d = q2n_nurbs.SurfaceData.from_surface(S)
        check(d is not None and d.weights is not None, '%s: not read as a rational B-spline' % name)
        u0, u1, v0, v1 = f.ParameterRange
        u = u0 + (u1 - u0) * (0.05 + 0.9 * rng.random(20))
        v = v0 + (v1 - v0) * (0.05 + 0.9 * rng.random(20))
        jet = d.eval_points(u, v)
        err = 0.0
        for i in range(20):
            ref = [S.value(u[i], v[i])] + [S.getDN(u[i], v[i], a, b) for a, b in ((1, 0), (0, 1), (2, 0), (1, 1), (0, 2))]
            for k in range(6):
                rv = np.array([ref[k].x, ref[k].y, ref[k].z])
                err = max(err, np.abs(jet[k][i] - rv).max() / (1 + np.abs(rv).max()))
        check(err < 1e-11, '%s: rational derivatives vs OCCT: %.3g' % (name, err))
        P = jet[0] - (np.array([0, 0, 0]) if name == 'sphere' else np.c_[np.zeros((20, 2)), jet[0][:, 2]])
        check(np.abs(np.linalg.norm(P, axis=1) - r).max() < 1e-12, '%s: points off radius %g' % (name, r))
        n = q2n_nurbs.unit_normals(jet[1], jet[2], f.Orientation == 'Reversed')
        H = np.abs(q2n_nurbs.mean_curvature(jet, n))
        check(np.abs(H - h_expect).max() < 1e-10, '%s: |H| %s != %g' % (name, H[:3], h_expect))


def test_renderer():
    import numpy as np
    import q2n_render as R
    cam = R.Camera((0.0, 0.0, 1.0), (0.0, 1.0, 0.0))            # screen x = world x, y = world y
    check(np.allclose(cam.R, np.eye(3)), 'camera looking down -z is not the identity: %s' % cam.R)
    frame = R.Frame(cam, (50.0, 50.0), 1.0, 100, 100)           # world (x, y) -> pixel (x, 100 - y)
    V = np.array([[10, 40, 0], [50, 40, 0], [50, 80, 0], [10, 80, 0],        # square x 10..50, y 40..80
                  [30, 20, 1], [90, 20, 1], [90, 60, 1], [30, 60, 1.0]])     # nearer square x 30..90, y 20..60
    T = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]])
    ras = R.rasterize(frame, V[:4], T[:2])
    check(int(ras.covered.sum()) == 40 * 40, 'square of 40 x 40 pixels covers %d' % ras.covered.sum())
    ras = R.rasterize(frame, V, T)
    tri = ras.tri.reshape(100, 100)
    check(int(ras.covered.sum()) == 1600 + 2400 - 400, '40 x 40 and 60 x 40 squares overlapping 20 x 20 cover %d'
          % ras.covered.sum())
    check(bool((tri[45:60, 30:50] >= 2).all()), 'the nearer square does not win the overlap')
    check(bool((tri[25:40, 10:30] < 2).all() & (tri[25:40, 10:30] >= 0).all()), 'the farther square lost its own pixels')
    # zebra of a tessellated unit sphere = zebra of its exact normals (the sphere's point = normal)
    n = 61
    th, ph = np.meshgrid(np.linspace(0, np.pi, n), np.linspace(0, 2 * np.pi, 2 * n))
    P = np.stack([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)], -1).reshape(-1, 3)
    g = np.arange(n - 1)
    q = (np.arange(2 * n - 1)[:, None] * n + g[None, :]).ravel()
    T = np.concatenate([np.stack([q, q + n, q + n + 1], 1), np.stack([q, q + n + 1, q + 1], 1)])
    cam = R.Camera((0.3, -0.5, 0.8), (0.0, 0.0, 1.0))
    size = 400
    frame = R.Frame.fit(cam, P, size, size)
    ras = R.rasterize(frame, P, T)
    got = R.zebra(ras, T, P, cam)[:, 0] > 0.5
    culled = R.rasterize(frame, P, T, P)          # closed sphere: culling back faces changes nothing
    check(bool((culled.tri == ras.tri).all()), 'back-face culling changed %d pixels' % (culled.tri != ras.tri).sum())
    # exact: the pixel's world point on the sphere, its normal = itself
    idx = np.nonzero(ras.covered)[0]
    x = (idx % size + 0.5 - size / 2) / frame.s + frame.c[0]
    y = -(idx // size + 0.5 - size / 2) / frame.s + frame.c[1]
    z = np.sqrt(np.clip(1 - x * x - y * y, 0, None))
    exact_n = np.stack([x, y, z], 1) @ cam.R                 # camera -> world
    e = cam.R[2]
    ne = exact_n @ e
    r = 2 * ne[:, None] * exact_n - e
    a = cam.R[1]
    b1 = R.unit(np.cross(a, e))
    b2 = np.cross(a, b1)
    phi = np.arctan2(r @ b2, r @ b1)
    want = np.floor((phi + np.pi) / (2 * np.pi) * 2 * R.ZEBRA_STRIPES).astype(int) % 2 == 1
    inner = x * x + y * y < 0.8 ** 2          # away from the silhouette, where stripes crowd
    agree = (got == want)[inner].mean()
    check(agree > 0.985, 'zebra of the tessellated sphere agrees with the exact stripes on %.4f of the pixels' % agree)
    check(0.3 < want[inner].mean() < 0.7, 'sphere zebra: stripes missing (white fraction %.2f)' % want[inner].mean())


def test_audit_numpy_vs_occt(Part, step, audit_occt):
    """The audit on numpy jets (the report's) = the audit on OCCT jets (q2n_audit.py's CLI)."""
    import q2n_audit
    import q2n_nurbs
    shape = Part.read(step)
    ev = [q2n_nurbs.NumpyFaceEval(f) for f in shape.Faces]
    a = q2n_audit.audit_shape(Part, shape, step, evals=ev, mass=False)
    b = audit_occt
    check(a['faces'] == b['faces'] and a['shared_edges'] == b['shared_edges'], 'counts differ')
    worst = {'g0': 0.0, 'g1_deg': 0.0, 'g2_rel': 0.0, 'g2_abs': 0.0}
    for x, y in zip(a['edge_detail'], b['edge_detail']):
        for k in worst:
            worst[k] = max(worst[k], abs(x[k] - y[k]))
    diag = a['bbox_diag']
    check(worst['g0'] <= 1e-13 * diag, 'per-edge G0 numpy vs OCCT: %.3g' % worst['g0'])
    check(worst['g1_deg'] <= 1e-8, 'per-edge G1 numpy vs OCCT: %.3g deg' % worst['g1_deg'])
    check(worst['g2_rel'] <= 1e-7, 'per-edge G2 numpy vs OCCT: %.3g' % worst['g2_rel'])
    check(worst['g2_abs'] <= 1e-7 * max(1.0, b['g2_max_abs']), 'per-edge G2 abs numpy vs OCCT: %.3g' % worst['g2_abs'])


class Collect(html.parser.HTMLParser):
    """Images and elements with data-src of a report page."""

    def __init__(self):
        super().__init__()
        self.imgs, self.cells, self.links, self.scripts = [], [], [], 0
        self._open = []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == 'img':
            self.imgs.append(a.get('src', ''))
        if tag == 'script':
            self.scripts += 1
        for k in ('href', 'src'):                 # anything but an image or an anchor in the page
            if k in a and tag != 'img' and not a[k].startswith('#'):
                self.links.append(a[k])
        if 'data-src' in a:
            self._open.append([tag, a, ''])

    def handle_data(self, data):
        for o in self._open:
            o[2] += data

    def handle_endtag(self, tag):
        if self._open and self._open[-1][0] == tag:
            t, a, text = self._open.pop()
            self.cells.append((a, text.strip()))


def lookup(obj, dotted):
    for k in dotted.split('.'):
        obj = obj[k]
    return obj


def same_number(text, value):
    if isinstance(value, bool):
        return text == ('yes' if value else 'no')
    try:
        x = float(text)
    except ValueError:
        return False
    return abs(x - value) <= 1e-5 * abs(value) + 1e-300 or ('%.6g' % value) == text or ('%.4g' % value) == text


def obj_ev_count(path):
    """Extraordinary vertices of a quad mesh, from its faces: interior valence != 4, boundary > 2."""
    faces, nv = [], 0
    with open(path) as f:
        for line in f:
            if line.startswith('v '):
                nv += 1
            elif line.startswith('f '):
                faces.append([int(t.split('/')[0]) for t in line.split()[1:]])
    faces = [[i - 1 if i > 0 else nv + i for i in fc] for fc in faces]
    val, edges = [0] * nv, {}
    for fc in faces:
        for i, a in enumerate(fc):
            val[a] += 1
            b = fc[(i + 1) % len(fc)]
            edges[(min(a, b), max(a, b))] = edges.get((min(a, b), max(a, b)), 0) + 1
    bnd = set()
    for (a, b), c in edges.items():
        if c == 1:
            bnd |= {a, b}
    return sum(1 for i in range(nv) if val[i] and ((i not in bnd and val[i] != 4) or (i in bnd and val[i] > 2)))


def check_page(page_path, rep, audit, n_images, ev_expect, label):
    import numpy as np
    with open(page_path, encoding='utf-8') as f:
        text = f.read()
    c = Collect()
    c.feed(text)
    check(len(c.imgs) == n_images, '%s: %d images, expected %d' % (label, len(c.imgs), n_images))
    check(c.scripts == 0 and not c.links, '%s: scripts or links to other resources: %s' % (label, c.links[:3]))
    check(not re.search(r'(src|href)\s*=\s*"(https?:|file:|//)', text), '%s: refers to an outside resource' % label)
    from PIL import Image
    for k, src in enumerate(c.imgs):
        ok = src.startswith('data:image/png;base64,')
        if check(ok, '%s: image %d is not a PNG data URI' % (label, k)):
            im = np.asarray(Image.open(io.BytesIO(base64.b64decode(src.split(',', 1)[1]))).convert('L'), dtype=float)
            check(im.shape[0] > 100 and im.shape[1] > 300 and im.std() > 20,
                  '%s: image %d blank or tiny (%s, std %.1f)' % (label, k, im.shape, im.std()))
    n = {'report': 0, 'audit': 0, 'edge': 0, 'topology': 0}
    edges = {d['edge']: d for d in audit['edge_detail']}
    for a, t in c.cells:
        src, key = a['data-src'], a['data-key']
        n[src] = n.get(src, 0) + 1
        if src == 'report':
            check(same_number(t, lookup(rep, key)), '%s: page shows %s = %r, report has %r' % (label, key, t, lookup(rep, key)))
        elif src == 'audit':
            check(same_number(t, lookup(audit, key)), '%s: page shows audit %s = %r, audit has %r' % (label, key, t, lookup(audit, key)))
        elif src == 'edge':
            d = edges[int(a['data-edge'])]
            v = d[key] / audit['bbox_diag'] if key == 'g0' else d[key]
            check(same_number(t, v), '%s: edge %s %s = %r, audit has %r' % (label, a['data-edge'], key, t, v))
        elif src == 'topology':
            check(int(t) == ev_expect, '%s: %s extraordinary vertices shown, the mesh has %d' % (label, t, ev_expect))
    check(n['report'] >= 9, '%s: only %d numbers tied to the report' % (label, n['report']))
    check(n['audit'] >= 3 + ('mesh' in audit) and n['edge'] >= 30 and n['topology'] == 1,
          '%s: tied numbers %s' % (label, n))
    return text


def test_chromium(page_path):
    """Headless Chromium: every image decoded (naturalWidth), screenshot not blank where images are."""
    import numpy as np
    from PIL import Image
    exe = shutil.which('chromium') or shutil.which('chromium-browser')
    if not exe:
        skip('Chromium (Debian chromium) is not installed: page not rendered')
        return
    tmp = tempfile.mkdtemp(prefix='q2n_report_test_')
    try:
        with open(page_path, encoding='utf-8') as f:
            page = f.read()
        probe = page.replace('</body>', '<script>window.addEventListener("load", function () {'
                             'for (const im of document.images) { const r = im.getBoundingClientRect();'
                             'im.setAttribute("data-probe", [r.left + scrollX, r.top + scrollY, r.width, r.height,'
                             'im.complete ? im.naturalWidth : -1].join(",")); }'
                             'document.body.setAttribute("data-height", document.documentElement.scrollHeight);'
                             '});</script></body>')
        probe_path = os.path.join(tmp, 'probe.html')
        with open(probe_path, 'w', encoding='utf-8') as f:
            f.write(probe)
        flags = [exe, '--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
                 '--disable-background-networking', '--disable-component-update', '--disable-sync']
        r = run(flags + ['--user-data-dir=' + os.path.join(tmp, 'u1'), '--window-size=1400,1000', '--dump-dom',
                         'file://' + probe_path], timeout=120)
        rects = [list(map(float, m.split(','))) for m in re.findall(r'data-probe="([^"]*)"', r.stdout)]
        hm = re.search(r'data-height="(\d+)"', r.stdout)
        if not check(r.returncode == 0 and rects and hm, 'chromium --dump-dom failed (%d): %s' % (
                r.returncode, r.stderr.strip().splitlines()[-1:] if r.stderr.strip() else '')):
            return
        check(all(x[4] > 0 for x in rects), 'chromium: images not decoded: %s' % [x[4] for x in rects])
        height = int(hm.group(1))
        shot = os.path.join(tmp, 'shot.png')
        r = run(flags + ['--user-data-dir=' + os.path.join(tmp, 'u2'), '--window-size=1400,%d' % height,
                         '--hide-scrollbars', '--screenshot=' + shot, 'file://' + page_path], timeout=120)
        if not check(r.returncode == 0 and os.path.exists(shot), 'chromium --screenshot failed: %s' % r.stderr[-300:]):
            return
        im = np.asarray(Image.open(shot).convert('L'), dtype=float)
        check(im.shape[0] >= height - 2 and im.shape[1] == 1400, 'screenshot %s, page 1400 x %d' % (im.shape, height))
        for k, (x, y, w, h, nw) in enumerate(rects):
            reg = im[int(y):int(y + h), int(x):int(x + w)]
            dark = (reg < 200).mean() if reg.size else 0.0
            check(reg.size > 0 and reg.std() > 20 and dark > 0.02,
                  'screenshot blank at image %d (%d,%d %dx%d): std %.1f, dark %.3f' % (
                      k, x, y, w, h, reg.std() if reg.size else 0, dark))
        # and the page is not just images: the summary table's text is there (dark pixels above the first image)
        top = im[:int(rects[0][1])]
        check((top < 128).mean() > 0.005, 'screenshot: no text above the first image')
        keep = OUT + 'demo_screenshot.png'
        shutil.copyfile(shot, keep)
    except subprocess.TimeoutExpired:
        check(False, 'chromium timed out')
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def test_targets():
    """The summary's held / missed marks follow the numbers: a G1 figure above 0.01 deg is missed,
    a G2 figure is no target for a G1 fit, the deviation target is the report's tol."""
    import q2n_report
    audit = {'g0_max_rel': 1e-16, 'g1_max_deg': 0.002, 'g2_max_rel': 0.5}
    rep = {'tol': 1e-5, 'continuity': 'G2', 'g0_max_rel': 1e-16, 'g1_max_deg': 0.5, 'g2_max_rel': 0.004,
           'max_dev_rel': 2e-5, 'vertex_dev_max_rel': 0.0, 'construction': {'g1_max_deg': 1e-12, 'g2_max_rel': 1e-12},
           'tol_met': False, 'g1_met': False, 'g2_met': True}

    def marks(a, r, extra):
        text = q2n_report.targets_html(a, r, extra)
        return [('✔' in row, '✘' in row) for row in text.split('<tr>')[2:]]
    m = marks(audit, rep, {})
    check(m[0] == (True, False), 'G0 within target not held: %s' % (m[0],))
    check(m[1] == (False, True), 'G1 0.5 deg in the report not missed: %s' % (m[1],))
    check(m[2] == (False, True), 'G2 0.5 in the import not missed: %s' % (m[2],))
    check(m[3] == (False, True), 'deviation 2e-5 > tol 1e-5 not missed: %s' % (m[3],))
    check(m[4] == (True, False), 'vertex interpolation 0 not held: %s' % (m[4],))
    rep_g1 = dict(rep, continuity='G1', g1_max_deg=0.001, max_dev_rel=1e-6)
    m = marks(audit, rep_g1, {})
    check(m[1] == (True, False) and m[2] == (False, False) and m[3] == (True, False),
          'G1 fit: G2 should be no target, G1 and deviation held: %s' % (m,))
    text = q2n_report.targets_html(dict(audit, mesh={'max_vertex_dist_rel': 3e-6, 'vertices': 9}), None, {})
    check('✘' in text.split('<tr>')[-1], 'a mesh vertex 3e-6 x diagonal off the surface not missed')
    # ... but a run through the limit points (--limit-points, the default after --subdivide) does not put
    # the given mesh's vertices on the surface: shown, not judged (stop 43: the page said "missed")
    rep_lp = dict(rep, construction=dict(rep['construction'], vertices_moved_max_rel=0.027))
    last = q2n_report.targets_html(dict(audit, mesh={'max_vertex_dist_rel': 0.063, 'vertices': 40}), rep_lp, {}).split('<tr>')[-1]
    check('✘' not in last and '✔' in last and 'not judged' in last and '0.063' in last,
          'limit points: the given mesh\'s vertices shown, not judged: %s' % last[:300])
    # the run's own targets (--tol 1e-4 loosens the defaults; --angle-tol sets them): G1 0.05 deg is
    # held against 0.1, missed against the 0.01 of a report that does not say
    rep_loose = dict(rep, g1_max_deg=0.05, g1_tol_deg=0.1, g2_tol_rel=0.1)
    m = marks(dict(audit, g1_max_deg=0.05, g2_max_rel=0.05), rep_loose, {})
    check(m[1] == (True, False) and m[2] == (True, False), 'G1 0.05 / G2 0.05 against targets 0.1: %s' % (m[:3],))
    m = marks(dict(audit, g1_max_deg=0.05, g2_max_rel=0.05), dict(rep, g1_max_deg=0.05), {})
    check(m[1] == (False, True), 'G1 0.05 against the default 0.01: %s' % (m[1],))


def test_units(mesh):
    """The unit the file says: quad2nurbs --units in / mm, STEP and IGES."""
    import q2n_report
    for unit in ('in', 'mm'):
        base = OUT + 'units_' + unit
        r = run([EXE, '-q', mesh, '--units', unit, '-o', base + '.step', '-o', base + '.igs'])
        if check(r.returncode == 0, 'quad2nurbs --units %s: %s' % (unit, r.stderr.strip())):
            for ext in ('.step', '.igs'):
                got = q2n_report.file_units(base + ext)
                check(got == unit, '%s%s: unit %r, written as %r' % (base, ext, got, unit))


def test_bad_input(step):
    out = OUT + 'bad.html'
    garbage = OUT + 'garbage.step'
    with open(garbage, 'w') as f:
        f.write('ISO-10303-21;\nnot a step file\n')
    bad_samples = OUT + 'bad_samples.txt'
    with open(bad_samples, 'w') as f:
        f.write('0 0 0 1 2\nthis is not a number\n')
    for args, what in (([OUT + 'missing.step'], 'missing file'), ([garbage], 'garbage STEP'),
                       ([step, '--samples', bad_samples], 'bad samples file'),
                       ([step, '--json', garbage], 'report that is not JSON')):
        if os.path.exists(out):
            os.remove(out)
        r = run([PY, os.path.join(TOOLS, 'q2n_report.py')] + args + ['-o', out])
        lines = r.stderr.strip().splitlines()
        check(r.returncode == 1, '%s: exit %d, expected 1' % (what, r.returncode))
        check(len(lines) == 1 and lines[0].startswith('q2n_report: ') and os.path.basename(args[-1]) in lines[0],
              '%s: stderr should be one line naming the file: %r' % (what, r.stderr[-300:]))
        check(not os.path.exists(out) and not glob.glob(out + '.tmp*'), '%s: an output file was left' % what)


def main():
    os.chdir(ROOT)
    import q2n_audit
    Part = q2n_audit.load_freecad()
    if Part is None:
        skip('FreeCAD (Debian freecad-python3) is not installed: report not tested')
        done()
    try:
        import matplotlib  # noqa: F401
        import PIL  # noqa: F401  (matplotlib's own dependency)
    except ImportError:
        skip('matplotlib (Debian python3-matplotlib) is not installed: report not tested')
        done()
    if not os.access(EXE, os.X_OK):
        skip('%s not built: report not tested' % EXE)
        done()
    os.makedirs(os.path.dirname(OUT), exist_ok=True)
    t0 = time.time()
    test_renderer()
    test_targets()
    test_rational(Part)
    # the demo torus: fit, report, audit by OCCT
    base = OUT + 'demo'
    mesh = os.path.join(ROOT, 'data', 'demo_torus.obj')
    for p in glob.glob(base + '*'):
        os.remove(p)
    r = run([EXE, '-q', mesh, '-o', base + '.step', '-o', base + '.json'])
    if not check(r.returncode == 0, 'quad2nurbs on the demo mesh: %s' % r.stderr.strip()):
        done()
    with open(base + '_samples.txt', 'w') as f:
        r = subprocess.run([EXE, 'sample', mesh, '--grid', '5'], stdout=f)
    check(r.returncode == 0, 'quad2nurbs sample failed')
    test_evaluator(Part, base + '.step')
    r = run([PY, os.path.join(TOOLS, 'q2n_report.py'), base + '.step', '--mesh', mesh, '--json', base + '.json',
             '--samples', base + '_samples.txt', '--audit-json', base + '_audit.json', '-o', base + '_report.html'])
    if not check(r.returncode == 0 and os.path.exists(base + '_report.html'), 'q2n_report on the demo: exit %d %s'
                 % (r.returncode, r.stderr.strip())):
        done()
    print(r.stderr.strip())
    r2 = run([PY, os.path.join(TOOLS, 'q2n_audit.py'), base + '.step', '--mesh', mesh, '--json', base + '_occt.json'])
    check(r2.returncode == 0, 'q2n_audit.py on the demo: %s' % r2.stderr.strip())
    with open(base + '.json') as f:
        rep = json.load(f)
    with open(base + '_audit.json') as f:
        audit = json.load(f)
    with open(base + '_occt.json') as f:
        occt = json.load(f)
    test_audit_numpy_vs_occt(Part, base + '.step', occt)
    for k in ('faces', 'shells', 'solids', 'free_edges', 'valid'):
        check(audit[k] == occt[k], 'report audit %s = %r, q2n_audit.py %r' % (k, audit[k], occt[k]))
    check(abs(audit['mesh']['max_vertex_dist_rel'] - occt['mesh']['max_vertex_dist_rel']) <= 1e-15,
          'vertex distances differ')
    # demo: zebra, G1 close-up (no EV on the torus), curvature, histograms, deviation, control points
    check_page(base + '_report.html', rep, audit, 6, obj_ev_count(mesh), 'demo')
    test_chromium(base + '_report.html')
    test_bad_input(base + '.step')
    test_units(mesh)
    # a mesh with an extraordinary vertex: the EV close-up appears, the EV count is the mesh's
    ev_mesh = shared_mesh('gismo_ev_valence5_carpet.obj')
    if not ev_mesh:
        skip('gismo_ev_valence5_carpet.obj not in ../shared/meshes: extraordinary-vertex report not tested')
    else:
        base = OUT + 'ev5'
        r = run([EXE, '-q', ev_mesh, '-o', base + '.step', '-o', base + '.json'])
        if check(r.returncode == 0, 'quad2nurbs on %s: %s' % (ev_mesh, r.stderr.strip())):
            import q2n_report
            rc = q2n_report.main([base + '.step', '--json', base + '.json', '--audit-json', base + '_audit.json',
                                  '-o', base + '_report.html'])
            if check(rc == 0, 'q2n_report on the EV mesh: exit %d' % rc):
                with open(base + '.json') as f:
                    rep = json.load(f)
                with open(base + '_audit.json') as f:
                    audit = json.load(f)
                nev = obj_ev_count(ev_mesh)
                check(nev >= 1, 'the EV mesh has no extraordinary vertex')
                text = check_page(base + '_report.html', rep, audit, 6, nev, 'ev5')
                check('extraordinary vertex of valence 5' in text, 'ev5: no close-up of the valence-5 vertex')
    print('test_report: %.1f s' % (time.time() - t0))
    done()


if __name__ == '__main__':
    main()
