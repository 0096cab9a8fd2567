#!/usr/bin/python3
"""q2n_report.py — continuity audit report of a STEP or IGES file as one self-contained HTML page.

usage: /usr/bin/python3 tools/q2n_report.py PART.step|PART.igs [--mesh MESH.obj] [--json REPORT.json]
                                           [--samples SAMPLES.txt] [--up x|y|z] [--audit-json AUDIT.json]
                                           -o PART_report.html

FreeCAD (OpenCASCADE) imports the file, as in tools/q2n_audit.py, whose audit runs here as a module
(per shared edge: G0 gap, G1 normal angle, G2 curvature jump at the fit's own check points), with
the faces' B-splines read once and evaluated by numpy (tools/q2n_nurbs.py).  The page holds:
  1. summary: file, faces, shells/solids, free edges, validity, units, bounding box; each target
     (G0, G1, G2, deviation, vertex interpolation) with the construction and the fitted surface side
     by side (from quad2nurbs' report, --json) and the import's own figure, and whether it held;
  2. zebra (reflection lines) of the whole part from 3 views, patch edges thin, extraordinary
     vertices marked, and close-ups of the worst G1 edge and of the extraordinary vertex whose
     neighbourhood has the largest mean-curvature variation;
  3. mean curvature maps (diverging colours, symmetric limits at a robust percentile);
  4. per-edge continuity: log histograms of G0, G1, G2 over all shared edges with the targets,
     and the 10 worst edges for each;
  5. deviation from the construction per face (with --samples, the output of `quad2nurbs sample`
     for the same mesh and options) and control points per face.
Images are PNG data URIs (matplotlib, Agg), rendered by tools/q2n_render.py; no script, no network.
Every number the page shows from quad2nurbs' report or from the audit carries data-src/data-key
attributes, so tests can read them back.  --audit-json writes the audit (q2n_audit's JSON fields,
without area/volume) for comparison.
Exit status: 0 written, 1 the input cannot be read (one line on stderr, no output file), 2 usage or
a missing dependency (freecad-python3, python3-matplotlib).
"""
import argparse
import base64
import html
import io
import json
import math
import os
import re
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import q2n_audit  # noqa: E402
try:
    import numpy as np
    import q2n_nurbs
    import q2n_render as R
except ImportError:  # main() says what is missing
    np = None

# Policy (report): targets and sizes, each with why.
TARGET_G0_REL = 1e-9      # watertight: the writers' resolution, 1e-9 x diagonal (docs/export.md)
TARGET_G1_DEG = 0.01      # the fit's default G1 acceptance at --tol 1e-5, g1_met (docs/fit.md)
TARGET_G2_REL = 0.01      # the fit's default G2 acceptance at --tol 1e-5, g2_met: 1 % in the report's measure


def continuity_targets(rep):
    """The run's G1 and G2 acceptance targets: the fit report's (they follow --tol, --angle-tol and
    --curvature-tol), else the defaults at --tol 1e-5."""
    if not rep:
        return TARGET_G1_DEG, TARGET_G2_REL
    return rep.get('g1_tol_deg') or TARGET_G1_DEG, rep.get('g2_tol_rel') or TARGET_G2_REL
TARGET_VERTEX_REL = 1e-6  # vertices on the imported surface: OCCT's distToShape is good to ~1e-7 (tests use 1e-6)
TESS_TRIANGLES = 240000   # whole-part tessellation: a few triangles per supersampled pixel at most
TESS_MIN, TESS_MAX = 5, 25  # points per face side: coarse faces still curve, fine ones stay cheap
CLOSEUP_TESS = 33         # points per face side in the close-ups (a few faces only)
VIEW_PX = 440             # pixels per view; three side by side fit a 1400 px page
VIEWS = ((-55.0, 25.0), (125.0, 25.0), (35.0, 70.0))   # (azimuth, elevation) of the 3 views, degrees
CURV_PERCENTILE = 98.0    # mean-curvature colour limit: robust to spikes at a few points
WORST_EDGES = 10          # rows of the worst-edge tables
HIST_BINS = 40            # histogram bins over the decades spanned
HIST_DECADES = 14         # decades shown below the largest value or target (smaller values pile up left)
CLOSEUP_RADIUS = 1.0      # close-up half-width in edge lengths (worst G1 edge) or ring radii (EV)
CLOSEUP_REACH = 1.5       # close-ups draw the faces reaching within 1.5 half-widths: the corners lie at sqrt 2


class ReportError(Exception):
    """Bad input: the message names the file and what is wrong."""


def fmt(x, digits=6):
    if x is None:
        return '–'
    if isinstance(x, bool):
        return 'yes' if x else 'no'
    if isinstance(x, int):
        return str(x)
    return '%.*g' % (digits, x)


def esc(s):
    return html.escape(str(s), quote=True)


# ---------------------------------------------------------------------------------------------
# Input
# ---------------------------------------------------------------------------------------------

def file_units(path):
    """The length unit written in the file: STEP LENGTH_UNIT, IGES global parameters 14/15."""
    with open(path, 'rb') as f:
        data = f.read()
    if path.lower().endswith(('.igs', '.iges')):
        glob = b''.join(line[:72] for line in data.splitlines() if len(line) >= 73 and line[72:73] == b'G')
        fields = iges_global_fields(glob.decode('latin-1'))
        names = {1: 'in', 2: 'mm', 4: 'ft', 5: 'mi', 6: 'm', 7: 'km', 8: 'mil', 9: 'µm', 10: 'cm', 11: 'µin'}
        try:
            return names.get(int(fields[13]), fields[14] or '?')
        except (IndexError, ValueError):
            return '?'
    ent = None
    g = re.search(rb'GLOBAL_UNIT_ASSIGNED_CONTEXT\s*\(\s*\(([^)]*)\)', data)
    for ref in (g.group(1).split(b',') if g else []):
        m = re.search(rb'(?m)^\s*' + re.escape(ref.strip()) + rb'\s*=([^;]*);', data)
        if m and b'LENGTH_UNIT' in m.group(1):
            ent = m.group(1)
            break
    if ent is None:                              # no context: the first length unit in the file
        m = re.search(rb'=([^;=]*LENGTH_UNIT[^;]*);', data)
        ent = m.group(1) if m else b''
    c = re.search(rb"CONVERSION_BASED_UNIT\s*\(\s*'([^']*)'", ent)
    if c:
        name = c.group(1).decode('latin-1').lower()
        return {'inch': 'in', 'foot': 'ft', 'mile': 'mi'}.get(name, name)
    s = re.search(rb'SI_UNIT\s*\(\s*(\.\w+\.|\$)\s*,\s*\.METRE\.', ent)
    if s:
        prefix = s.group(1).decode()
        return {'$': 'm', '.MILLI.': 'mm', '.CENTI.': 'cm', '.MICRO.': 'µm', '.KILO.': 'km'}.get(prefix, prefix)
    return '?'


def iges_global_fields(text):
    """IGES global section split into fields (Hollerith strings nH... honoured)."""
    delim, rec = ',', ';'
    if text.startswith('1H'):
        delim = text[2]
    fields, cur, i = [], '', 0
    while i < len(text):
        m = re.match(r'\s*(\d+)H', text[i:])
        if m and cur.strip() == '':
            n = int(m.group(1))
            start = i + m.end()
            cur = text[start:start + n]
            i = start + n
            continue
        ch = text[i]
        if ch == delim or ch == rec:
            fields.append(cur.strip())
            cur = ''
            if ch == rec:
                break
        else:
            cur += ch
        i += 1
    return fields


def read_samples(path):
    """`quad2nurbs sample` output: rows k u v x y z xu yu zu xv yv zv -> (k, u, v, xyz) arrays."""
    try:
        a = np.loadtxt(path, ndmin=2)
    except (OSError, ValueError) as ex:
        raise ReportError('%s: %s' % (path, str(ex).splitlines()[0] if str(ex) else 'unreadable'))
    if a.size == 0 or a.shape[1] < 6:
        raise ReportError('%s: expected lines "k u v x y z ..." (quad2nurbs sample)' % path)
    return a[:, 0].astype(int), a[:, 1], a[:, 2], a[:, 3:6]


def read_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError) as ex:
        raise ReportError('%s: %s' % (path, ex))


# ---------------------------------------------------------------------------------------------
# Geometry: tessellation, extraordinary vertices, deviation
# ---------------------------------------------------------------------------------------------

class Tess:
    """Triangles over faces: V (n, 3), oriented unit normals N, convexity-signed mean curvature H
    (positive where the part bulges towards its face normals, i.e. outwards on a solid),
    triangles T (m, 3), face of each triangle and of each vertex."""

    def __init__(self, V, N, H, T, tri_face, vert_face):
        self.V, self.N, self.H, self.T, self.tri_face, self.vert_face = V, N, H, T, tri_face, vert_face


def face_datas(faces):
    """q2n_nurbs.SurfaceData per face (faces that are not B-splines: FreeCAD's NURBS conversion)."""
    out = []
    for f in faces:
        d = q2n_nurbs.SurfaceData.from_surface(f.Surface)
        if d is None:
            try:
                d = q2n_nurbs.SurfaceData.from_surface(f.toNurbs().Faces[0].Surface)
            except Exception:
                d = None
        out.append(d)
    return out


def tessellate(faces, datas, which, n):
    Vs, Ns, Hs, Ts, tf, vf = [], [], [], [], [], []
    base = 0
    g = np.arange(n - 1)
    quad = (g[:, None] * n + g[None, :]).ravel()
    tri_local = np.concatenate([np.stack([quad, quad + n, quad + n + 1], 1),
                                np.stack([quad, quad + n + 1, quad + 1], 1)])
    for k in which:
        d = datas[k]
        if d is None:
            continue
        u0, u1, v0, v1 = faces[k].ParameterRange
        jet = d.eval_grid(np.linspace(u0, u1, n), np.linspace(v0, v1, n))
        flip = faces[k].Orientation == 'Reversed'
        nrm = q2n_nurbs.unit_normals(jet[1], jet[2], flip)
        H = -q2n_nurbs.mean_curvature(jet, nrm)
        Vs.append(jet[0].reshape(-1, 3))
        Ns.append(nrm.reshape(-1, 3))
        Hs.append(H.ravel())
        Ts.append(tri_local + base)
        tf.append(np.full(len(tri_local), k))
        vf.append(np.full(n * n, k))
        base += n * n
    if not Vs:
        raise ReportError('no face could be evaluated')
    return Tess(np.concatenate(Vs), np.concatenate(Ns), np.concatenate(Hs), np.concatenate(Ts),
                np.concatenate(tf), np.concatenate(vf))


def vertex_valences(shape, edges):
    """Per B-rep vertex: point, number of faces around it, whether it lies on a free edge."""
    faces_at, point, boundary = {}, {}, set()
    for fi, f in enumerate(shape.Faces):
        for v in f.Vertexes:
            k = v.hashCode()
            faces_at.setdefault(k, set()).add(fi)
            point[k] = (v.Point.x, v.Point.y, v.Point.z)
    for e, fl in edges:
        if len(fl) == 1:
            for v in e.Vertexes:
                boundary.add(v.hashCode())
    return [(np.array(point[k]), len(fs), k in boundary, sorted(fs)) for k, fs in faces_at.items()]


def extraordinary_vertices(shape, edges):
    """Interior vertices with other than 4 faces, boundary vertices with more than 2."""
    return [(p, val, bnd, fs) for p, val, bnd, fs in vertex_valences(shape, edges)
            if (not bnd and val != 4) or (bnd and val > 2)]


def ev_variation(evs, tess):
    """Per extraordinary vertex: the mean-curvature range over its faces times their radius around
    it (dimensionless), and that radius: the median over the faces of their farthest point (one long
    face does not blow the close-up up)."""
    out = []
    for p, _, _, fs in evs:
        m = np.isin(tess.vert_face, fs)
        if not m.any():
            out.append((0.0, 0.0))
            continue
        dist = np.linalg.norm(tess.V[m] - p, axis=1)
        far = [dist[tess.vert_face[m] == f].max() for f in fs if (tess.vert_face[m] == f).any()]
        radius = float(np.median(far))
        out.append((float(tess.H[m].max() - tess.H[m].min()) * radius, radius))
    return out


def sample_deviation(datas, ks, us, vs, X, nfaces):
    """Per face: largest distance between the fitted face and the construction's sample points."""
    if ks.min() < 0 or ks.max() >= nfaces:
        raise ReportError('samples name patch %d, the file has %d faces' % (ks.max(), nfaces))
    dev = np.full(nfaces, np.nan)
    order = np.argsort(ks, kind='stable')
    ks, us, vs, X = ks[order], us[order], vs[order], X[order]
    bounds = np.searchsorted(ks, np.arange(nfaces + 1))
    for k in range(nfaces):
        a, b = bounds[k], bounds[k + 1]
        if b > a and datas[k] is not None:
            S = datas[k].eval_points(us[a:b], vs[a:b])[0]
            dev[k] = float(np.linalg.norm(S - X[a:b], axis=1).max())
    return dev


# ---------------------------------------------------------------------------------------------
# Pictures
# ---------------------------------------------------------------------------------------------

def png_uri(fig, dpi=100):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    FigureCanvasAgg(fig)
    buf = io.BytesIO()
    fig.savefig(buf, format='png', dpi=dpi)
    return 'data:image/png;base64,' + base64.b64encode(buf.getvalue()).decode('ascii')


def new_figure(w_in, h_in):
    from matplotlib.figure import Figure
    return Figure(figsize=(w_in, h_in))


class WholeViews:
    """The three whole-part views: camera, frame and raster, computed once and shaded many ways
    (triangles facing away are skipped when the part is closed)."""

    def __init__(self, tess, up_axis, closed):
        self.views = []
        size = VIEW_PX * R.SUPERSAMPLE
        for az, el in VIEWS:
            cam = R.Camera.from_angles(az, el, up_axis)
            frame = R.Frame.fit(cam, tess.V, size, size)
            self.views.append((az, el, cam, frame, R.rasterize(frame, tess.V, tess.T, tess.N if closed else None)))


def draw_panels(panels, title, cbar=None, markers=None):
    """One figure: images side by side at their own pixel size (no resampling), optional colour bar
    (ScalarMappable, label, [(value, text)] lines) and per-panel markers [(x, y, style dict)]."""
    from matplotlib.ticker import NullFormatter
    dpi = 100.0
    ph, pw = panels[0][0].shape[:2]
    gap, top, bottom, right = 8, (46 if title else 24), 22, (110 if cbar else 8)
    W = len(panels) * (pw + gap) + right
    H = ph + top + bottom
    fig = new_figure(W / dpi, H / dpi)
    for i, (img, sub) in enumerate(panels):
        ax = fig.add_axes([(i * (pw + gap) + gap / 2) / W, bottom / H, pw / W, ph / H])
        ax.imshow(img, interpolation='none')
        ax.set_axis_off()
        ax.set_title(sub, fontsize=9, pad=3)
        for x, y, style in (markers[i] if markers else []):
            if len(x):
                ax.plot(x, y, linestyle='none', **style)
        ax.set_xlim(0, img.shape[1])
        ax.set_ylim(img.shape[0], 0)
    if cbar:
        mappable, label, lines = cbar
        cax = fig.add_axes([(len(panels) * (pw + gap) + 10) / W, (bottom + 0.1 * ph) / H, 14 / W, 0.8 * ph / H])
        cb = fig.colorbar(mappable, cax=cax)
        if type(mappable.norm).__name__ == 'LogNorm':
            cb.ax.yaxis.set_major_formatter(decade_formatter())
            cb.ax.yaxis.set_minor_formatter(NullFormatter())
        cb.set_label(label, fontsize=8)
        cb.ax.tick_params(labelsize=7)
        for val, text in lines:
            cb.ax.axhline(val, color='red', lw=1.5)
            cb.ax.text(-0.3, val, text, color='red', fontsize=7, va='center', ha='right',
                       transform=cb.ax.get_yaxis_transform())
    if title:
        fig.text(0.5, 1 - 6 / H, title, fontsize=11, ha='center', va='top')
    return png_uri(fig, dpi)


def view_markers(wv, tess, points_styles):
    """Markers per view for world points that the surface does not hide."""
    out = []
    for _, _, _, frame, ras in wv.views:
        mk = []
        for pts, style in points_styles:
            if len(pts) == 0:
                continue
            vis, x, y = R.visible(frame, ras, pts)
            mk.append((x[vis], y[vis], style))
        out.append(mk)
    return out


def zebra_whole(wv, tess, marks):
    panels = []
    for az, el, cam, frame, ras in wv.views:
        rgb = R.zebra(ras, tess.T, tess.N, cam)
        panels.append((R.compose(ras, rgb, tess.tri_face), 'azimuth %g°, elevation %g°' % (az, el)))
    return draw_panels(panels, 'Zebra (reflection lines), whole part', markers=view_markers(wv, tess, marks))


def curvature_norm(tess):
    from matplotlib.colors import Normalize
    lim = float(np.percentile(np.abs(tess.H), CURV_PERCENTILE)) if len(tess.H) else 0.0
    if not lim > 0:
        lim = 1.0
    return Normalize(-lim, lim), lim


def curvature_whole(wv, tess, marks, units):
    from matplotlib import cm
    norm, lim = curvature_norm(tess)
    cmap = cm.get_cmap('RdBu_r')
    panels = []
    for az, el, cam, frame, ras in wv.views:
        col = cmap(norm(ras.interpolate(tess.T, tess.H)))[:, :3]
        panels.append((R.compose(ras, R.shaded(ras, tess.T, tess.N, cam, col), tess.tri_face),
                       'azimuth %g°, elevation %g°' % (az, el)))
    sm = cm.ScalarMappable(norm=norm, cmap=cmap)
    return draw_panels(panels, 'Mean curvature H (1/%s), limits ±%s (the %gth percentile of |H|)'
                       % (units, fmt(lim, 3), CURV_PERCENTILE),
                       cbar=(sm, 'H (1/%s), > 0 convex' % units, []), markers=view_markers(wv, tess, marks))


def face_value_views(wv, tess, values, title, label, norm, cmap_name, lines):
    """Whole-part views coloured by one value per face (grey where the value is missing)."""
    from matplotlib import cm
    cmap = cm.get_cmap(cmap_name)
    panels = []
    for az, el, cam, frame, ras in wv.views:
        fv = values[tess.tri_face[ras.tri[ras.covered]]]
        col = np.full((len(fv), 3), 0.75)
        ok = np.isfinite(fv)
        col[ok] = cmap(norm(fv[ok]))[:, :3]
        panels.append((R.compose(ras, R.shaded(ras, tess.T, tess.N, cam, col), tess.tri_face),
                       'azimuth %g°, elevation %g°' % (az, el)))
    sm = cm.ScalarMappable(norm=norm, cmap=cmap)
    return draw_panels(panels, title, cbar=(sm, label, lines))


def closeup(faces, datas, tess, center, radius, toward, up_hint, title, line_pts=None, point=None):
    """Zebra close-up: faces with a tessellation point within CLOSEUP_REACH radii of center, finely
    tessellated, seen along toward, stripes crossing up_hint (the screen's vertical)."""
    near = np.unique(tess.vert_face[np.linalg.norm(tess.V - center, axis=1) < CLOSEUP_REACH * radius])
    sub = tessellate(faces, datas, near, CLOSEUP_TESS)
    size = VIEW_PX * R.SUPERSAMPLE
    cam = R.Camera(toward, up_hint)
    frame = R.Frame.around(cam, center, radius, size, size)
    ras = R.rasterize(frame, sub.V, sub.T)
    panels = [(R.compose(ras, R.zebra(ras, sub.T, sub.N, cam, axis=cam.R[0]), sub.tri_face), 'zebra')]
    norm, _ = curvature_norm(tess)
    from matplotlib import cm
    col = cm.get_cmap('RdBu_r')(norm(ras.interpolate(sub.T, sub.H)))[:, :3]
    panels.append((R.compose(ras, R.shaded(ras, sub.T, sub.N, cam, col), sub.tri_face),
                   'mean curvature (colours as below)'))
    marks = []
    for _ in panels:
        mk = []
        if line_pts is not None:
            vis, x, y = R.visible(frame, ras, line_pts)
            mk.append((x[vis], y[vis], dict(marker='.', ms=2.5, color='red')))
        if point is not None:
            vis, x, y = R.visible(frame, ras, np.asarray(point)[None, :])
            mk.append((x[vis], y[vis], dict(marker='o', ms=11, mfc='none', mec='magenta', mew=1.5)))
        marks.append(mk)
    return draw_panels(panels, None, markers=marks), title


def nearest_normal(tess, faces_idx, p):
    m = np.isin(tess.vert_face, faces_idx)
    idx = np.nonzero(m)[0]
    d = np.linalg.norm(tess.V[idx] - p, axis=1)
    near = idx[d <= d.min() * 1.5 + 1e-300]
    return R.unit(tess.N[near].sum(axis=0))


def perpendicular(n):
    a = np.eye(3)[int(np.argmin(np.abs(n)))]
    return R.unit(np.cross(n, a))


def decade_formatter():
    """Tick labels 1e-05 in plain text (matplotlib's 10^x labels go through mathtext: ~1 s)."""
    from matplotlib.ticker import FuncFormatter
    return FuncFormatter(lambda x, _: ('%g' % x) if 1e-3 <= x <= 1e4 else '%.0e' % x)


def histograms(detail, diag, targets):
    """Log-scale histograms of G0 (relative), G1, G2 over the shared edges, targets as lines."""
    from matplotlib.ticker import NullFormatter
    fig = new_figure(14, 3.6)
    series = [('G0 gap / diagonal', np.array([d['g0'] for d in detail]) / (diag if diag > 0 else 1.0), targets[0]),
              ('G1 normal angle (deg)', np.array([d['g1_deg'] for d in detail]), targets[1]),
              ('G2 relative curvature jump', np.array([d['g2_rel'] for d in detail]), targets[2])]
    for i, (label, v, target) in enumerate(series):
        ax = fig.add_axes([0.05 + 0.325 * i, 0.17, 0.27, 0.68])
        pos = v[v > 0]
        top = math.log10(max(pos.max() if len(pos) else 1e-300, target or 1e-300, 1e-300))
        hi = math.ceil(top + 1e-9) if top > -300 else 0
        lo = hi - HIST_DECADES
        floor = 10.0 ** lo
        clipped = np.clip(v, floor, None)
        bins = np.logspace(lo, hi, HIST_BINS + 1)
        ax.hist(clipped, bins=bins, color='#4878a8', edgecolor='white', linewidth=0.3)
        ax.set_xscale('log')
        ax.set_yscale('log')
        ax.set_xlim(bins[0], bins[-1])
        if target is not None:
            ax.axvline(target, color='red', ls='--', lw=1.2)
            over = int((v > target).sum())
            ax.text(0.98, 0.95, 'target %s\n%d of %d edges above' % (fmt(target, 3), over, len(v)),
                    transform=ax.transAxes, ha='right', va='top', fontsize=8, color='red')
        nlow = int((v < floor).sum())
        if nlow:
            ax.text(0.02, 0.95, '%d edges ≤ %s\n(left bin)' % (nlow, fmt(floor, 1)), transform=ax.transAxes,
                    ha='left', va='top', fontsize=7.5, color='#444')
        for axis in (ax.xaxis, ax.yaxis):
            axis.set_major_formatter(decade_formatter())
            axis.set_minor_formatter(NullFormatter())
        ax.set_xlabel(label, fontsize=9)
        ax.set_ylabel('edges', fontsize=8)
        ax.tick_params(labelsize=7)
    fig.suptitle('Per-edge continuity over %d shared edges (largest sample per edge)' % len(detail), fontsize=11)
    return png_uri(fig)


# ---------------------------------------------------------------------------------------------
# HTML
# ---------------------------------------------------------------------------------------------

CSS = """
body{font-family:"DejaVu Sans",Arial,sans-serif;margin:16px 24px;color:#222;max-width:1420px}
h1{font-size:22px;margin:4px 0 2px} h2{font-size:17px;margin:26px 0 6px;border-bottom:1px solid #ccc}
table{border-collapse:collapse;font-size:13px;margin:6px 0 10px}
td,th{border:1px solid #ccc;padding:3px 8px;text-align:left;vertical-align:top}
th{background:#f0f0f0} td.num{text-align:right;font-family:"DejaVu Sans Mono",monospace;white-space:nowrap}
td.ok,td.bad,td.na{white-space:nowrap}
.ok{color:#17772b;font-weight:bold} .bad{color:#b00020;font-weight:bold} .na{color:#888}
.note{color:#555;font-size:13px;max-width:1100px} img{display:block;max-width:100%;margin:6px 0}
.grid{display:flex;gap:28px;flex-wrap:wrap} h3.caption{font-size:14px;font-weight:normal;margin:14px 0 0}
"""


def num_cell(value, src=None, key=None, bad=None):
    attrs = ''
    if src:
        attrs = ' data-src="%s" data-key="%s"' % (esc(src), esc(key))
    cls = 'num' + ('' if bad is None else (' bad' if bad else ''))
    return '<td class="%s"%s>%s</td>' % (cls, attrs, esc(fmt(value)))


def mark(ok):
    if ok is None:
        return '<td class="na">–</td>'
    return '<td class="ok">✔ held</td>' if ok else '<td class="bad">✘ missed</td>'


def held(values, target):
    vals = [v for v in values if v is not None]
    if target is None or not vals:
        return None
    return all(v <= target for v in vals)


def report_get(rep, *keys):
    x = rep
    for k in keys:
        if not isinstance(x, dict) or k not in x:
            return None
        x = x[k]
    return x if not isinstance(x, (dict, list)) else None


def summary_html(a, rep, units, path, extra):
    bb = extra['bbox']
    rows = [('file', esc(os.path.basename(path)) + ' (%s, %.1f MB)' % (a['format'].upper(), extra['size'] / 1e6)),
            ('faces', '%d (%d reversed)' % (a['faces'], a['reversed_faces'])),
            ('shells / solids', '%d / %d' % (a['shells'], a['solids'])),
            ('edges', '%d: %d shared, %d free, %d non-manifold' % (a['edges'], a['shared_edges'], a['free_edges'],
                                                                  a['nonmanifold_edges'])),
            ('valid (OCCT isValid)', '<span class="%s">%s</span>' % ('ok' if a['valid'] else 'bad', fmt(a['valid']))),
            ('largest edge / vertex tolerance', '%s / %s (1e-07: OCCT found no gap)' % (
                fmt(a['max_edge_tolerance'], 3), fmt(a['max_vertex_tolerance'], 3))),
            ('units', '%s as written in the file; FreeCAD imports in mm' % esc(units)),
            ('bounding box (mm)', 'x %s … %s, y %s … %s, z %s … %s; diagonal %s' % tuple(
                fmt(v, 5) for v in (bb[0], bb[3], bb[1], bb[4], bb[2], bb[5], extra['bbox_diag']))),
            ('extraordinary vertices', '<span data-src="topology" data-key="extraordinary_vertices">%d</span> '
             '(interior vertices with other than 4 faces, boundary vertices with more than 2)' % extra['n_ev'])]
    if rep is not None:
        rows.append(("quad2nurbs' report", '%s: %s, %s, continuity %s, tol %s, spans per patch %s…%s' % (
            esc(os.path.basename(extra['json_path'])), esc(rep.get('stage', '')), esc(rep.get('mode', '')),
            esc(rep.get('continuity', '')), fmt(rep.get('tol')), fmt(report_get(rep, 'spans_per_patch', 'min')),
            fmt(report_get(rep, 'spans_per_patch', 'max')))))
        if rep.get('note'):
            rows.append(('report note', esc(rep['note'])))
        if rep.get('faces') is not None and rep.get('faces') != a['faces']:
            rows.append(('WARNING', '<span class="bad">the report has %s faces, the file %d: not the same part?'
                         '</span>' % (esc(rep.get('faces')), a['faces'])))
    body = ''.join('<tr><th>%s</th><td>%s</td></tr>' % (k, v) for k, v in rows)
    return '<table>%s</table>' % body


def targets_html(a, rep, extra):
    g2_on = rep is None or str(rep.get('continuity', 'G2')).upper() != 'G1'
    tol = rep.get('tol') if rep else None
    t_g1, t_g2 = continuity_targets(rep)
    mesh = a.get('mesh')
    rows = []

    def row(name, target, cons, rep_v, imp, rep_key=None, cons_key=None, imp_key=None, why='', judge_imp=True):
        ok = held([cons, rep_v, imp if judge_imp else None], target)
        cells = ['<th>%s</th>' % name, '<td class="num">%s</td>' % ('≤ ' + fmt(target) if target is not None
                                                                  else 'not a target')]
        for v, src, key in ((cons, 'report', cons_key), (rep_v, 'report', rep_key), (imp, 'audit', imp_key)):
            bad = None if (v is None or target is None or (src == 'audit' and not judge_imp)) else v > target
            cells.append(num_cell(v, src if v is not None and key else None, key, bad))
        cells.append(mark(ok))
        cells.append('<td class="note">%s</td>' % why)
        rows.append('<tr>%s</tr>' % ''.join(cells))

    row('G0 gap / diagonal', TARGET_G0_REL, None, report_get(rep, 'g0_max_rel') if rep else None,
        a['g0_max_rel'], 'g0_max_rel', None, 'g0_max_rel', 'watertight: shared edges')
    row('G1 normal angle (deg)', t_g1, report_get(rep, 'construction', 'g1_max_deg') if rep else None,
        report_get(rep, 'g1_max_deg') if rep else None, a['g1_max_deg'], 'g1_max_deg', 'construction.g1_max_deg',
        'g1_max_deg', 'largest over all shared edges')
    row('G2 relative curvature jump', t_g2 if g2_on else None,
        report_get(rep, 'construction', 'g2_max_rel') if rep else None,
        report_get(rep, 'g2_max_rel') if rep else None, a['g2_max_rel'], 'g2_max_rel', 'construction.g2_max_rel',
        'g2_max_rel', 'jump ÷ largest |curvature| (≥ 1/diagonal)' + ('' if g2_on else '; a G1 fit'))
    dev_s = extra.get('samples_dev_rel')
    row('deviation from the construction / diagonal', tol, None, report_get(rep, 'max_dev_rel') if rep else None,
        dev_s, 'max_dev_rel', None, None,
        'report: at its check points' + ('; import: at the samples file\'s points' if dev_s is not None else ''))
    # --limit-points (the default after --subdivide): the surface passes through the limit points, so
    # the given mesh's own vertices are off it by design; shown, not judged
    moved = report_get(rep, 'construction', 'vertices_moved_max_rel') if rep else None
    limit = isinstance(moved, (int, float)) and moved > 0
    row('mesh vertices off the surface / diagonal', TARGET_VERTEX_REL,
        report_get(rep, 'vertex_dev_max_rel') if rep else None, None,
        mesh['max_vertex_dist_rel'] if mesh else None, None, 'vertex_dev_max_rel', 'mesh.max_vertex_dist_rel',
        'construction: patch corners vs vertices' + ('; import: distance of %d vertices' % mesh['vertices']
                                                     if mesh else '; import: give --mesh') +
        ('; the run interpolates Catmull–Clark limit points (--limit-points, the default after --subdivide; '
         'the report\'s vertices_moved_max_rel %s), not the given mesh\'s vertices: the import column is shown, '
         'not judged' % fmt(moved) if limit else ''),
        judge_imp=not limit)
    head = ('<tr><th>measure</th><th>target</th><th>construction<br>(report)</th><th>fitted surface<br>'
            '(quad2nurbs report)</th><th>fitted surface<br>(this import)</th><th>held</th><th>where</th></tr>')
    flags = ''
    if rep is not None:
        flags = '<p class="note">The report\'s own verdicts: %s.</p>' % ', '.join(
            '%s <span data-src="report" data-key="%s" class="%s">%s</span>' % (
                k, k, 'ok' if rep.get(k) else 'bad', fmt(rep.get(k))) for k in ('tol_met', 'g1_met', 'g2_met')
            if k in rep)
    else:
        flags = '<p class="note">No --json report given: construction and report columns are empty.</p>'
    return '<table>%s%s</table>%s' % (head, ''.join(rows), flags)


def worst_tables(detail, diag, rep):
    out = []
    t_g1, t_g2 = continuity_targets(rep)
    cols = (('g0', 'G0 gap / diag', TARGET_G0_REL), ('g1_deg', 'G1 (deg)', t_g1), ('g2_rel', 'G2 rel', t_g2))
    for key, label, target in cols:
        rows = sorted(detail, key=lambda d: -d[key])[:WORST_EDGES]
        trs = []
        for i, d in enumerate(rows):
            at = d['worst_%s_at' % {'g0': 'g0', 'g1_deg': 'g1', 'g2_rel': 'g2'}[key]]
            cells = ['<td>%d</td>' % (i + 1), '<td>%d</td>' % d['edge'], '<td>%s</td>' % ' – '.join(map(str, d['faces']))]
            for k2, _, t2 in cols:
                v = d[k2] / diag if k2 == 'g0' and diag > 0 else d[k2]
                attrs = ' data-src="edge" data-edge="%d" data-key="%s"' % (d['edge'], k2)
                cls = 'num' + (' bad' if v > t2 else '') + (' sorted' if k2 == key else '')
                cells.append('<td class="%s"%s>%s</td>' % (cls, attrs, esc(fmt(v, 4))))
            cells.append('<td class="num">%s</td>' % ('(%s)' % ', '.join(fmt(c, 5) for c in at) if at else '–'))
            trs.append('<tr>%s</tr>' % ''.join(cells))
        out.append('<div><h3 style="font-size:14px">worst %d by %s</h3><table><tr><th>#</th><th>edge</th>'
                   '<th>faces</th><th>G0 gap / diag</th><th>G1 (deg)</th><th>G2 rel</th><th>worst point (x, y, z)'
                   '</th></tr>%s</table></div>' % (len(rows), label, ''.join(trs)))
    return '<div class="grid">%s</div>' % ''.join(out)


# ---------------------------------------------------------------------------------------------
# The report
# ---------------------------------------------------------------------------------------------

class Clock:
    """Wall and CPU seconds per stage (the machine is shared: CPU time is the figure to compare)."""

    def __init__(self):
        self.stages = []
        self.t, self.c = time.time(), time.process_time()

    def lap(self, name):
        t, c = time.time(), time.process_time()
        self.stages.append((name, t - self.t, c - self.c))
        self.t, self.c = t, c

    def text(self):
        return '%.1f s (%.1f s CPU): %s' % (sum(w for _, w, _ in self.stages), sum(c for _, _, c in self.stages),
                                           ', '.join('%s %.1f / %.1f' % s for s in self.stages))


def read_part(args, Part):
    """The inputs: (shape, report JSON or None, samples or None); ReportError names a bad one."""
    path = args.file
    if not os.path.exists(path):
        raise ReportError('%s: no such file' % path)
    rep = read_json(args.json) if args.json else None
    if args.mesh and not os.path.exists(args.mesh):
        raise ReportError('%s: no such file' % args.mesh)
    samples = read_samples(args.samples) if args.samples else None
    try:
        shape = Part.read(path)
    except Exception as ex:
        raise ReportError('%s: %s' % (path, str(ex).strip() or 'FreeCAD cannot read it'))
    if not shape.Faces:
        raise ReportError('%s: no faces imported' % path)
    return shape, rep, samples


def closeup_worst_g1(faces, datas, tess, edges, worst, diag):
    """Close-up of the worst G1 sample's edge, looking along the normal there tilted along the edge,
    stripes across the edge; None when no edge is shared."""
    if worst['edge'] is None or worst['point'] is None:
        return None
    e, fl = edges[worst['edge']]
    p = np.array(worst['point'])
    t0, t1 = e.ParameterRange
    tan = R.unit(np.asarray(q2n_audit.vec(e.tangentAt(0.5 * (t0 + t1)))))
    toward = R.unit(nearest_normal(tess, fl, p) + 0.45 * tan)
    line = np.array([(v.x, v.y, v.z) for v in e.discretize(Number=80)])
    title = 'Close-up: worst G1 edge %d (faces %s), %s° at the circle' % (
        worst['edge'], ' – '.join(map(str, fl)), fmt(worst['value'], 3))
    return closeup(faces, datas, tess, p, CLOSEUP_RADIUS * max(e.Length, 1e-9 * diag), toward, tan, title,
                   line_pts=line, point=p)


def closeup_ev(faces, datas, tess, evs):
    """Close-up of the extraordinary vertex whose faces span the largest mean-curvature range."""
    var = ev_variation(evs, tess)
    i = int(np.argmax([v for v, _ in var]))
    p, val, bnd, fs = evs[i]
    nrm = nearest_normal(tess, fs, p)
    side = perpendicular(nrm)
    title = 'Close-up: extraordinary vertex of valence %d%s at (%s), mean-curvature variation %s' % (
        val, ' (boundary)' if bnd else '', ', '.join(fmt(c, 4) for c in p), fmt(var[i][0], 3))
    return closeup(faces, datas, tess, p, CLOSEUP_RADIUS * var[i][1], R.unit(nrm + 0.45 * side), side, title,
                   point=p)


def poles_views(wv, tess, datas):
    """Control points per face; the title also gives the knot spans (u spans x v spans) per face."""
    from matplotlib.colors import LogNorm, Normalize
    poles = np.array([d.pole_count if d is not None else np.nan for d in datas], dtype=float)
    spans = np.array([d.span_count if d is not None else np.nan for d in datas], dtype=float)
    pmin, pmax = np.nanmin(poles), np.nanmax(poles)
    norm = LogNorm(pmin, pmax) if pmax > 4 * pmin else Normalize(pmin - 0.5, pmax + 0.5)
    return face_value_views(wv, tess, poles, 'Control points per face: %d…%d, median %d, %d in all; knot spans per '
                            'face %d…%d, median %d' % (pmin, pmax, np.nanmedian(poles), np.nansum(poles),
                                                       np.nanmin(spans), np.nanmax(spans), np.nanmedian(spans)),
                            'control points', norm, 'viridis', [])


def deviation_views(wv, tess, dev, diag, tol):
    from matplotlib.colors import LogNorm
    rel = dev / diag if diag > 0 else dev
    pos = rel[np.isfinite(rel) & (rel > 0)]
    lo = max(pos.min() if len(pos) else 1e-16, 1e-16)
    hi = max(pos.max() if len(pos) else 1e-15, tol or 0, lo * 10)
    return face_value_views(wv, tess, np.clip(rel, lo, None), 'Deviation from the construction per face (largest '
                            'over the samples file\'s points) / diagonal', 'deviation / diagonal', LogNorm(lo, hi),
                            'magma', [(tol, 'tol')] if tol else [])


def build(args):
    """Everything but writing: returns (html text, audit dict, Clock)."""
    clock = Clock()
    Part = q2n_audit.load_freecad()
    shape, rep, samples = read_part(args, Part)
    faces = shape.Faces
    clock.lap('read')
    datas = face_datas(faces)
    evals = [q2n_nurbs.NumpyFaceEval(f, d if type(f.Surface).__name__ == 'BSplineSurface' else None)
             for f, d in zip(faces, datas)]
    edges = q2n_audit.edge_faces(shape)
    rep_diag = report_get(rep, 'bbox_diag') if rep else None   # the report's diagonal: its G2 floor and ratios
    a = q2n_audit.audit_shape(Part, shape, args.file, args.mesh, 0, 100.0, True, False, evals, edges, mass=False,
                              diag=rep_diag if isinstance(rep_diag, (int, float)) and rep_diag > 0 else None)
    diag = a['bbox_diag']
    clock.lap('audit')
    n = int(np.clip(int(math.sqrt(TESS_TRIANGLES / (2.0 * len(faces)))) + 1, TESS_MIN, TESS_MAX))
    tess = tessellate(faces, datas, range(len(faces)), n)
    evs = extraordinary_vertices(shape, edges)
    bb = shape.BoundBox
    extra = {'bbox': (bb.XMin, bb.YMin, bb.ZMin, bb.XMax, bb.YMax, bb.ZMax), 'bbox_diag': diag,
             'size': os.path.getsize(args.file), 'n_ev': len(evs), 'json_path': args.json or ''}
    dev = sample_deviation(datas, *samples, len(faces)) if samples is not None else None
    if dev is not None:
        extra['samples_dev_rel'] = float(np.nanmax(dev)) / (diag if diag > 0 else 1.0)
    clock.lap('tessellation')
    wv = WholeViews(tess, 'xyz'.index(args.up), a['free_edges'] == 0 and a['nonmanifold_edges'] == 0)
    worst_g1 = a['worst']['g1_deg']
    marks = [(np.array([p for p, _, _, _ in evs]).reshape(-1, 3), dict(marker='o', ms=4, mfc='magenta', mec='white',
                                                                         mew=0.5)),
             (np.array(worst_g1['point'] or np.zeros((0, 3))).reshape(-1, 3), dict(marker='x', ms=9, mew=2,
                                                                                    color='red'))]
    imgs = {'zebra': zebra_whole(wv, tess, marks), 'curv': curvature_whole(wv, tess, marks, 'mm')}
    imgs['closeups'] = [c for c in (closeup_worst_g1(faces, datas, tess, edges, worst_g1, diag),
                                    closeup_ev(faces, datas, tess, evs) if evs else None) if c]
    ev_note = ('%d extraordinary %s; the close-up shows the one whose faces span the largest range of mean '
               'curvature (times their radius around it).' % (len(evs), 'vertex' if len(evs) == 1 else 'vertices')
               if evs else 'The part has no extraordinary vertex.')
    imgs['hist'] = (histograms(a['edge_detail'], diag, (TARGET_G0_REL,) + continuity_targets(rep))
                    if a['edge_detail'] else None)
    imgs['poles'] = poles_views(wv, tess, datas)
    if dev is not None:
        imgs['dev'] = deviation_views(wv, tess, dev, diag, (rep or {}).get('tol'))
    clock.lap('pictures')
    page = page_html(args.file, a, rep, file_units(args.file), extra, imgs, ev_note, clock, args)
    return page, a, clock


LEGEND_ZEBRA = ('Stripes are the view direction reflected in the surface, looking up black and white stripes on a '
                'cylinder around the part (Rhino\'s zebra).  A stripe that breaks across an edge is a G1 jump (a '
                'crease), one that kinks there is a G2 jump (a curvature jump); smooth stripes across every edge '
                'are what G2 looks like.  Thin lines: patch edges.  Magenta dots: extraordinary vertices; red '
                'cross: the worst G1 sample.  Blue tint: back sides of an open surface.')
LEGEND_CLOSEUP = ('Close-ups: the faces around the spot, seen from slightly above its normal; stripes run across '
                  'the edge.  Red dots: the edge; magenta circle: the worst sample or the vertex.')
LEGEND_CURV = ('Mean curvature H = (k1 + k2)/2 at every pixel, from the faces\' exact second derivatives: red '
               'convex, blue concave, with respect to the face normals (outwards on a solid); colours clipped at '
               'the limits.  A G2 surface has no colour step across edges.')
LEGEND_HIST = ('Largest value per shared edge at the fit\'s check points (4 per knot span of the edge curve, between its '
               'collocation points), evaluated on the imported faces.  Dashed red: target.  G2: |k_A - k_B| over '
               'three directions divided by the largest |k| (at least 1/diagonal), the measure of quad2nurbs\' '
               'report.')
LEGEND_POLES = ('Control points per face, where the file is heavy: the fit adds knot spans where the '
                'construction needs them to meet the tolerance and the continuity targets.')
LEGEND_DEV = ('Largest distance per face between the imported face and the construction\'s points from '
              '<code>quad2nurbs sample</code> (same mesh and options), divided by the diagonal.  Red line on '
              'the colour bar: the fit tolerance.')


def page_html(path, a, rep, units, extra, imgs, ev_note, clock, args):
    def img(uri, alt):
        return '<img src="%s" alt="%s">' % (uri, esc(alt))

    def note(text):
        return '<p class="note">%s</p>' % text
    parts = ['<!DOCTYPE html><html lang="en"><head><meta charset="utf-8">',
             '<title>Continuity report: %s</title><style>%s</style></head><body>' % (esc(os.path.basename(path)), CSS),
             '<h1>Continuity audit: %s</h1>' % esc(os.path.basename(path)),
             note('Imported with FreeCAD %s (OpenCASCADE), an importer independent of quad2nurbs; continuity '
                  'sampled between the fit\'s collocation points of every shared edge (tools/q2n_audit.py), '
                  'faces evaluated with numpy from the imported poles and knots.' % esc(freecad_version())),
             '<h2 id="summary">1. Summary</h2>', summary_html(a, rep, units, path, extra),
             targets_html(a, rep, extra),
             '<h2 id="zebra">2. Zebra (reflection lines)</h2>', img(imgs['zebra'], 'zebra views'),
             note(LEGEND_ZEBRA), note(esc(ev_note))]
    for uri, title in imgs['closeups']:
        parts += ['<h3 class="caption">%s</h3>' % esc(title), img(uri, title)]
    if imgs['closeups']:
        parts.append(note(LEGEND_CLOSEUP))
    parts += ['<h2 id="curvature">3. Mean curvature</h2>', img(imgs['curv'], 'mean curvature views'),
              note(LEGEND_CURV),
              '<h2 id="edges">4. Per-edge continuity</h2>']
    if imgs['hist']:
        parts += [img(imgs['hist'], 'per-edge histograms'), note(LEGEND_HIST),
                  worst_tables(a['edge_detail'], a['bbox_diag'], rep)]
    else:
        parts.append(note('The part has no edge shared by two faces.'))
    parts += ['<h2 id="deviation">5. Deviation from the construction and weight of the file</h2>']
    if 'dev' in imgs:
        parts += [img(imgs['dev'], 'deviation per face'), note(LEGEND_DEV)]
    else:
        parts.append(note('No per-face deviation: give <code>--samples</code> with the output of '
                          '<code>quad2nurbs sample MESH.obj</code> (same options as the fit).%s' % (
                              ' The report gives max_dev_rel <span data-src="report" data-key="max_dev_rel">%s'
                              '</span> and rms_dev_rel <span data-src="report" data-key="rms_dev_rel">%s</span> '
                              'over its check points.' % (fmt(rep.get('max_dev_rel')), fmt(rep.get('rms_dev_rel')))
                              if rep and 'max_dev_rel' in rep else '')))
    parts += [img(imgs['poles'], 'control points per face'), note(LEGEND_POLES)]
    parts.append(note('Made by tools/q2n_report.py in %s (wall / CPU seconds per stage, HTML writing not '
                      'included); command: <code>%s</code>' % (clock.text(), esc(' '.join(['q2n_report.py'] + [
                          os.path.basename(x) if os.sep in x else x for x in args.argv])))))
    parts.append('</body></html>\n')
    return '\n'.join(parts)


def freecad_version():
    try:
        import FreeCAD
        return '.'.join(FreeCAD.Version()[:3])
    except Exception:
        return '?'


def make_parser():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('file', help='.step/.stp or .igs/.iges file')
    ap.add_argument('-o', '--output', required=True, help='the HTML file to write')
    ap.add_argument('--mesh', help='the quad mesh (.obj) the part interpolates: distance of its vertices')
    ap.add_argument('--json', help="quad2nurbs' report (-o REPORT.json) of the same run")
    ap.add_argument('--samples', help='output of `quad2nurbs sample` for the same mesh and options: '
                                      'deviation per face')
    ap.add_argument('--up', choices='xyz', default='z', help='the part\'s up axis for the views (default z)')
    ap.add_argument('--audit-json', help='also write the audit (q2n_audit.py fields, no area/volume) here')
    return ap


def write_atomic(path, text):
    tmp = path + '.tmp.%d' % os.getpid()
    try:
        with open(tmp, 'w', encoding='utf-8') as f:
            f.write(text)
        os.replace(tmp, path)
    except OSError:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    args = make_parser().parse_args(argv)
    args.argv = argv
    if q2n_audit.load_freecad() is None:
        sys.stderr.write('q2n_report: FreeCAD is not installed (apt-get install freecad-python3)\n')
        return 2
    if np is None:
        sys.stderr.write('q2n_report: numpy is not installed (apt-get install python3-numpy)\n')
        return 2
    try:
        import matplotlib
        matplotlib.use('Agg')
    except ImportError:
        sys.stderr.write('q2n_report: matplotlib is not installed (apt-get install python3-matplotlib)\n')
        return 2
    t0, c0 = time.time(), time.process_time()
    try:
        page, a, clock = build(args)
        write_atomic(args.output, page)
        if args.audit_json:
            write_atomic(args.audit_json, json.dumps(a, indent=1, sort_keys=True) + '\n')
    except ReportError as ex:
        sys.stderr.write('q2n_report: %s\n' % ex)
        return 1
    except OSError as ex:
        sys.stderr.write('q2n_report: %s\n' % ex)
        return 1
    sys.stderr.write('q2n_report: wrote %s (%d faces, %d shared edges) in %.1f s, %.1f s CPU; %s\n' % (
        args.output, a['faces'], a['shared_edges'], time.time() - t0, time.process_time() - c0, clock.text()))
    return 0


if __name__ == '__main__':
    sys.exit(main())
