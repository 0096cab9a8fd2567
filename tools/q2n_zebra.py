#!/usr/bin/python3
"""q2n_zebra.py — zebra stripes and mean curvature of a CAD file around one point, as a PNG.

    /usr/bin/python3 tools/q2n_zebra.py PART.step|PART.igs --at X Y Z [--radius R] [--toward X Y Z]
                                       [--up X Y Z] [--title T] -o OUT.png

The same independent import (FreeCAD) and the same pictures as the HTML report's close-ups
(tools/q2n_report.py, docs/report.md): the faces near the point, finely tessellated from their own
B-spline data, zebra stripes (reflection lines) on the left and the mean curvature on the right.
--toward is the direction from the point towards the viewer (default: the surface normal there),
--up the screen's vertical (the stripes cross it).  Used for the before/after pictures of
docs/extraordinary.md.  Exit status: 0 written, 1 an input cannot be read, 2 usage or FreeCAD,
numpy or matplotlib missing.
"""
import argparse
import base64
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import q2n_audit  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('file')
    ap.add_argument('--at', type=float, nargs=3, required=True, help='the point to look at')
    ap.add_argument('--radius', type=float, help='half-width of the view (default: a tenth of the part)')
    ap.add_argument('--toward', type=float, nargs=3, help='direction towards the viewer (default: the normal)')
    ap.add_argument('--up', type=float, nargs=3, default=(0.0, 0.0, 1.0), help='screen vertical')
    ap.add_argument('--title', default='')
    ap.add_argument('-o', '--output', required=True)
    a = ap.parse_args(argv)
    Part = q2n_audit.load_freecad()
    if Part is None:
        print('q2n_zebra: FreeCAD is missing (Debian freecad-python3)', file=sys.stderr)
        return 2
    try:
        import q2n_report as Q
    except ImportError as ex:
        print('q2n_zebra: %s' % ex, file=sys.stderr)
        return 2
    if not os.path.exists(a.file):
        print('q2n_zebra: %s: no such file' % a.file, file=sys.stderr)
        return 1
    try:
        shape = Part.read(a.file)
    except Exception as ex:
        print('q2n_zebra: %s: %s' % (a.file, str(ex).strip() or 'FreeCAD cannot read it'), file=sys.stderr)
        return 1
    faces = list(shape.Faces)
    datas = Q.face_datas(faces)
    tess = Q.tessellate(faces, datas, range(len(faces)), 6)
    center = np.asarray(a.at, dtype=float)
    bb = shape.BoundBox
    radius = a.radius or 0.1 * (bb.XLength ** 2 + bb.YLength ** 2 + bb.ZLength ** 2) ** 0.5
    near = np.unique(tess.vert_face[np.linalg.norm(tess.V - center, axis=1) < 2 * radius])
    toward = np.asarray(a.toward, dtype=float) if a.toward else Q.nearest_normal(tess, near, center)
    uri, _ = Q.closeup(faces, datas, tess, center, radius, toward, np.asarray(a.up, dtype=float), a.title)
    png = base64.b64decode(uri.split(',', 1)[1])
    tmp = a.output + '.tmp'
    with open(tmp, 'wb') as f:
        f.write(png)
    os.replace(tmp, a.output)
    return 0


if __name__ == '__main__':
    sys.exit(main())
