"""q2n_render.py — a small z-buffer renderer in numpy for tools/q2n_report.py.

matplotlib's 3-D axes sort whole polygons (no depth buffer) and slow down past ~10^4 polygons; a
report shows parts of 3000 faces with ~10^5 triangles, and zebra stripes need the normal per pixel.
So the report rasterises its tessellation itself: orthographic camera, triangles scan-converted
all at once (one candidate per triangle and bounding-box pixel), nearest candidate per pixel,
barycentric interpolation of vertex attributes (normals, curvature, face values), supersampling for
anti-aliasing; matplotlib only frames the finished RGB images.

Face normals are never averaged across faces: each face's vertices carry that face's own normals,
so a tangent-plane jump across an edge shows as a jump of the reflection lines.
"""
import numpy as np

# Policy (render): the numbers that shape the pictures, with why.
SUPERSAMPLE = 2            # 2 x 2 samples per pixel: stripes and edges without staircase aliasing
MAX_CANDIDATES = 1500000   # pixel candidates per rasterisation batch: ~200 MB of temporaries at most
INSIDE_EPS = 1e-7          # barycentric slack: no cracks between triangles that share an edge
ZEBRA_STRIPES = 12         # black/white pairs around the environment cylinder (Rhino's zebra looks alike)
EDGE_DARKEN = 0.35         # brightness left on a patch-edge pixel
EDGE_FAINT_AREA = 60.0     # mean face area in (supersampled) pixels under which edges are drawn faint
BACK_TINT = (0.80, 0.85, 1.0)   # back sides of open surfaces are tinted blue


def unit(v):
    v = np.asarray(v, dtype=float)
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    return v / np.where(n > 0, n, 1.0)


class Camera:
    """Orthographic camera: rows of R are screen right, screen up and the direction towards the
    viewer (world coordinates)."""

    def __init__(self, toward_viewer, up_hint=(0.0, 0.0, 1.0)):
        e = unit(toward_viewer)
        up = np.asarray(up_hint, dtype=float)
        if abs(np.dot(unit(up), e)) > 0.99:            # looking along the up axis: any other up
            up = np.roll(up, 1)
        right = unit(np.cross(-e, up))
        self.R = np.stack([right, np.cross(right, -e), e])

    @classmethod
    def from_angles(cls, azimuth_deg, elevation_deg, up_axis=2):
        """Azimuth about the up axis and elevation above the plane normal to it, in degrees."""
        a, el = np.radians(azimuth_deg), np.radians(elevation_deg)
        local = np.array([np.cos(el) * np.cos(a), np.cos(el) * np.sin(a), np.sin(el)])
        perm = {2: [0, 1, 2], 1: [2, 0, 1], 0: [1, 2, 0]}[up_axis]   # (x, y, up) -> world axes
        e = np.zeros(3)
        e[perm] = local
        up = np.zeros(3)
        up[up_axis] = 1.0
        return cls(e, up)

    def to_camera(self, P):
        return np.asarray(P, dtype=float) @ self.R.T


class Frame:
    """Camera + pixel mapping of a W x H image (supersampled size)."""

    def __init__(self, cam, center_xy, scale, W, H):
        self.cam, self.c, self.s, self.W, self.H = cam, np.asarray(center_xy, dtype=float), scale, W, H

    @classmethod
    def fit(cls, cam, points, W, H, margin=0.04):
        q = cam.to_camera(points)
        lo, hi = q[:, :2].min(axis=0), q[:, :2].max(axis=0)
        ext = np.maximum(hi - lo, 1e-300)
        s = min(W * (1 - 2 * margin) / ext[0], H * (1 - 2 * margin) / ext[1])
        return cls(cam, (lo + hi) / 2, s, W, H)

    @classmethod
    def around(cls, cam, center, radius, W, H):
        q = cam.to_camera(np.asarray(center, dtype=float)[None, :])[0]
        return cls(cam, q[:2], min(W, H) / (2.0 * radius), W, H)

    def project(self, P):
        """Pixel x, pixel y (row, downwards) and depth (larger = nearer) of world points."""
        q = self.cam.to_camera(P)
        return (self.W / 2 + (q[:, 0] - self.c[0]) * self.s,
                self.H / 2 - (q[:, 1] - self.c[1]) * self.s, q[:, 2])


class Raster:
    """Per pixel (flattened, row-major): triangle index (-1 = background), barycentric weights of
    the triangle's second and third vertex, depth."""

    def __init__(self, W, H):
        self.W, self.H = W, H
        self.tri = np.full(W * H, -1, dtype=np.int64)
        self.l1 = np.zeros(W * H)
        self.l2 = np.zeros(W * H)
        self.depth = np.full(W * H, -np.inf)
        self.cache = {}           # per-pixel quantities shared by several shadings of one view

    @property
    def covered(self):
        return self.tri >= 0

    def interpolate(self, tris, values):
        """Vertex values (n,) or (n, k) interpolated at every covered pixel (rows in pixel order)."""
        idx = self.tri[self.covered]
        t = tris[idx]
        l1, l2 = self.l1[self.covered], self.l2[self.covered]
        v = np.asarray(values)
        if v.ndim == 1:
            return (1 - l1 - l2) * v[t[:, 0]] + l1 * v[t[:, 1]] + l2 * v[t[:, 2]]
        return ((1 - l1 - l2)[:, None] * v[t[:, 0]] + l1[:, None] * v[t[:, 1]] + l2[:, None] * v[t[:, 2]])


def rasterize(frame, V, tris, normals=None):
    """Scan-convert triangles (vertex indices into V, world coordinates) with a depth buffer.
    normals (per vertex), when given, cull triangles facing away at all three vertices: for a closed
    surface seen from outside they are hidden anyway."""
    W, H = frame.W, frame.H
    x, y, z = frame.project(V)
    ids = np.arange(len(tris))                    # Raster.tri holds indices into the given tris
    if normals is not None:
        facing = normals @ frame.cam.R[2] >= 0
        ids = np.nonzero(facing[tris].any(axis=1))[0]
        tris = tris[ids]
    ax, bx, cx = x[tris[:, 0]], x[tris[:, 1]], x[tris[:, 2]]
    ay, by, cy = y[tris[:, 0]], y[tris[:, 1]], y[tris[:, 2]]
    det = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
    x0 = np.clip(np.ceil(np.minimum(np.minimum(ax, bx), cx) - 0.5), 0, W).astype(np.int64)
    x1 = np.clip(np.floor(np.maximum(np.maximum(ax, bx), cx) - 0.5), -1, W - 1).astype(np.int64)
    y0 = np.clip(np.ceil(np.minimum(np.minimum(ay, by), cy) - 0.5), 0, H).astype(np.int64)
    y1 = np.clip(np.floor(np.maximum(np.maximum(ay, by), cy) - 0.5), -1, H - 1).astype(np.int64)
    keep = np.nonzero((x1 >= x0) & (y1 >= y0) & (np.abs(det) > 1e-12))[0]
    # barycentric weights of the 2nd and 3rd vertex and the depth are affine in the pixel centre:
    # l = A x + B y + C per triangle (edge functions, e.g. Pineda 1988)
    d = det[keep]
    ax, ay, bx, by, cx, cy = ax[keep], ay[keep], bx[keep], by[keep], cx[keep], cy[keep]
    A1, B1 = (cy - ay) / d, -(cx - ax) / d
    A2, B2 = -(by - ay) / d, (bx - ax) / d
    C1, C2 = -(A1 * ax + B1 * ay), -(A2 * ax + B2 * ay)
    tz = z[tris[keep]]
    dz1, dz2 = tz[:, 1] - tz[:, 0], tz[:, 2] - tz[:, 0]
    coef = (A1, B1, C1, A2, B2, C2, A1 * dz1 + A2 * dz2, B1 * dz1 + B2 * dz2, tz[:, 0] + C1 * dz1 + C2 * dz2)
    x0, y0 = x0[keep], y0[keep]
    bw = x1[keep] - x0 + 1
    counts = bw * (y1[keep] - y0 + 1)
    ras = Raster(W, H)
    keep_ids = ids[keep]
    cum = np.cumsum(counts)
    start = 0
    while start < len(keep):
        base = cum[start - 1] if start else 0
        stop = max(start + 1, int(np.searchsorted(cum, base + MAX_CANDIDATES, side='right')))
        sl = slice(start, stop)
        _raster_batch(ras, keep_ids[sl], counts[sl], bw[sl], x0[sl], y0[sl], tuple(c[sl] for c in coef))
        start = stop
    return ras


def _raster_batch(ras, tid, counts, bw, x0, y0, coef):
    total = int(counts.sum())
    rep = np.repeat(np.arange(len(tid)), counts)
    local = np.arange(total) - np.repeat(np.cumsum(counts) - counts, counts)
    w = bw[rep]
    py = local // w
    px = x0[rep] + (local - py * w)
    py += y0[rep]
    fx, fy = px + 0.5, py + 0.5
    l1 = coef[0][rep] * fx + coef[1][rep] * fy + coef[2][rep]
    l2 = coef[3][rep] * fx + coef[4][rep] * fy + coef[5][rep]
    ins = np.nonzero((l1 >= -INSIDE_EPS) & (l2 >= -INSIDE_EPS) & (1 - l1 - l2 >= -INSIDE_EPS))[0]
    l1, l2, rep, fx, fy = l1[ins], l2[ins], rep[ins], fx[ins], fy[ins]
    pix = py[ins] * ras.W + px[ins]
    depth = coef[6][rep] * fx + coef[7][rep] * fy + coef[8][rep]
    if len(pix) == 0:
        return
    # nearest candidate per pixel: one sort of the key (pixel, quantised depth, nearest first)
    pbits = max(1, int(ras.W * ras.H - 1).bit_length())
    dbits = 62 - pbits
    lo, hi = depth.min(), depth.max()
    q = ((hi - depth) * ((2 ** dbits - 1) / (hi - lo if hi > lo else 1.0))).astype(np.int64)
    order = np.argsort((pix << dbits) | q)
    ps = pix[order]
    first = order[np.r_[True, ps[1:] != ps[:-1]]]
    sel = first[depth[first] > ras.depth[pix[first]]]
    p = pix[sel]
    ras.depth[p], ras.tri[p], ras.l1[p], ras.l2[p] = depth[sel], tid[rep[sel]], l1[sel], l2[sel]


def pixel_normals(ras, tris, normals, cam):
    """Unit normals at covered pixels, turned towards the viewer, and the back-facing mask
    (cached on the raster: every shading of a view needs them)."""
    key = ('normals', id(normals))
    if key not in ras.cache:
        n = unit(ras.interpolate(tris, normals))
        back = n @ cam.R[2] < 0
        n[back] = -n[back]
        ras.cache[key] = (n, back)
    return ras.cache[key]


def zebra(ras, tris, normals, cam, axis=None, stripes=ZEBRA_STRIPES):
    """Reflection lines: the view direction reflected in the surface, r = 2 (n.e) n - e, looks up an
    environment of black and white stripes on an infinite cylinder around axis (default: screen
    up); the stripe is the parity of the angle of r about the axis.  Returns RGB per covered pixel."""
    n, back = pixel_normals(ras, tris, normals, cam)
    e = cam.R[2]
    ne = n @ e
    r = 2 * ne[:, None] * n - e[None, :]
    a = unit(cam.R[1] if axis is None else axis)
    b1 = unit(np.cross(a, e) if abs(np.dot(a, e)) < 0.99 else np.cross(a, cam.R[0]))
    b2 = np.cross(a, b1)
    phi = np.arctan2(r @ b2, r @ b1)
    stripe = np.floor((phi + np.pi) / (2 * np.pi) * 2 * stripes).astype(np.int64) % 2
    light = 0.72 + 0.28 * np.clip(ne, 0, 1)
    rgb = np.repeat((stripe * 0.97 * light)[:, None], 3, axis=1) + 0.03
    rgb[back] *= BACK_TINT
    return rgb


def shaded(ras, tris, normals, cam, colors):
    """Per-pixel colours (covered pixels, RGB) lit by a head light, back sides tinted."""
    n, back = pixel_normals(ras, tris, normals, cam)
    light = 0.55 + 0.45 * np.clip(n @ cam.R[2], 0, 1)
    rgb = colors * light[:, None]
    rgb[back] *= BACK_TINT
    return rgb


def edge_pixels(ras, tri_face):
    """Pixels whose right or lower neighbour shows another face or the background, and how strong
    edges are drawn: faint when faces are only a few pixels wide (cached on the raster)."""
    key = ('edges', id(tri_face))
    if key not in ras.cache:
        W, H = ras.W, ras.H
        face = np.full(W * H, -1, dtype=np.int64)
        face[ras.covered] = tri_face[ras.tri[ras.covered]]
        f2 = face.reshape(H, W)
        edge = np.zeros((H, W), dtype=bool)
        edge[:, :-1] |= f2[:, :-1] != f2[:, 1:]
        edge[:-1, :] |= f2[:-1, :] != f2[1:, :]
        edge &= f2 >= 0
        seen = np.zeros(int(tri_face.max()) + 1 if len(tri_face) else 1, dtype=bool)
        seen[face[face >= 0]] = True
        mean_area = ras.covered.sum() / max(1, int(seen.sum()))
        k = EDGE_DARKEN if mean_area >= EDGE_FAINT_AREA else 1 - (1 - EDGE_DARKEN) * 0.4
        ras.cache[key] = (edge.ravel(), k)
    return ras.cache[key]


def compose(ras, rgb, tri_face, edges=True):
    """Full image (H/SS, W/SS, 3) from covered-pixel colours on white, patch edges darkened,
    averaged down by SUPERSAMPLE."""
    W, H = ras.W, ras.H
    img = np.ones((W * H, 3))
    img[ras.covered] = np.clip(rgb, 0, 1)
    if edges:
        edge, k = edge_pixels(ras, tri_face)
        img[edge] *= k
    ss = SUPERSAMPLE
    return img.reshape(H // ss, ss, W // ss, ss, 3).mean(axis=(1, 3))


def visible(frame, ras, P, tol_px=3.0):
    """Which world points are visible (not hidden by the rendered surface), with pixel positions
    in the downsampled image."""
    x, y, z = frame.project(P)
    ix = np.clip(np.floor(x).astype(np.int64), 0, frame.W - 1)
    iy = np.clip(np.floor(y).astype(np.int64), 0, frame.H - 1)
    inside = (x >= 0) & (x < frame.W) & (y >= 0) & (y < frame.H)
    zb = ras.depth[iy * frame.W + ix]
    vis = inside & (z >= zb - tol_px / frame.s)
    return vis, x / SUPERSAMPLE, y / SUPERSAMPLE
