#!/usr/bin/python3
"""q2n_audit_table.py — run the whole export audit over many meshes and print a Markdown table.

For every mesh x surface method: quad2nurbs writes STEP, IGES and its JSON report in one run,
tools/q2n_audit.py imports each CAD file with FreeCAD, tools/q2n_compare.py compares the audit
with the report.  One row per mesh x method x format: faces, isValid, shells/solids, free edges
(and the mesh boundary they should equal), G0 / G1 / G2 from the import (the report's figure in
parentheses), the compare verdict and the import + audit time.  A run the executable refuses
(e.g. a construction that does not cover a mesh yet) is listed with its message.

The augmented construction needs an all-quad mesh: for a mesh with non-quad faces it runs with
`--subdivide N` (N = --nonquad-subdivide, default 1; 0 passes the mesh as it is, which quad2nurbs
refuses) and the row says "(subdivided)" after the mesh name; its free edges are compared with the
mesh boundary x 2^N.  The Catmull-Clark methods (acc3, acc-g1) handle non-quads themselves and get
the mesh as it is.

usage: tools/q2n_audit_table.py [--exe build/quad2nurbs] [--meshes-dir $Q2N_SHARED_MESHES or ../shared/meshes]
                                [--methods augmented,acc3,acc-g1] [--out build/audit]
                                [--nonquad-subdivide 1] [--threads N] [--timeout S] [MESH.obj ...]
"""
import argparse
import glob
import json
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))


def mesh_counts(path):
    """faces, boundary edges, connected components, all faces quads? of a polygon OBJ."""
    faces = []
    with open(path) as f:
        for line in f:
            if line.startswith('f '):
                faces.append([int(t.split('/')[0]) for t in line.split()[1:]])
    nv = 0
    with open(path) as f:
        nv = sum(1 for line in f if line.startswith('v '))
    faces = [[i - 1 if i > 0 else nv + i for i in fc] for fc in faces]
    edges = {}
    for k, fc in enumerate(faces):
        for i in range(len(fc)):
            a, b = fc[i], fc[(i + 1) % len(fc)]
            edges.setdefault((min(a, b), max(a, b)), []).append(k)
    parent = list(range(len(faces)))

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x
    for fl in edges.values():
        for g in fl[1:]:
            parent[find(g)] = find(fl[0])
    comps = len({find(k) for k in range(len(faces))})
    return (len(faces), sum(1 for fl in edges.values() if len(fl) == 1), comps,
            all(len(fc) == 4 for fc in faces))


def run(cmd, timeout=None):
    try:
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, universal_newlines=True,
                           timeout=timeout)
    except subprocess.TimeoutExpired:
        return None, '', 'timed out after %g s' % timeout
    return p.returncode, p.stdout, p.stderr


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('meshes', nargs='*', help='OBJ files (default: every *.obj in --meshes-dir)')
    ap.add_argument('--exe', default='build/quad2nurbs')
    ap.add_argument('--meshes-dir', default=os.environ.get('Q2N_SHARED_MESHES') or '../shared/meshes')
    ap.add_argument('--methods', default='augmented,acc3,acc-g1')
    ap.add_argument('--formats', default='step,igs')
    ap.add_argument('--out', default='build/audit')
    ap.add_argument('--nonquad-subdivide', type=int, default=1, metavar='N',
                    help='augmented on a mesh with non-quad faces: --subdivide N first (default 1; 0: off)')
    ap.add_argument('--threads', type=int, default=0, help='passed to quad2nurbs --threads (0: not passed)')
    ap.add_argument('--timeout', type=float, default=None,
                    help='seconds one quad2nurbs run may take (default: no limit); a timed-out run is listed')
    a = ap.parse_args()
    meshes = a.meshes or sorted(glob.glob(os.path.join(a.meshes_dir, '*.obj')))
    if not meshes:
        sys.exit('q2n_audit_table.py: no *.obj in %s (name meshes or --meshes-dir)' % a.meshes_dir)
    fmts = a.formats.split(',')
    os.makedirs(a.out, exist_ok=True)
    # 1. every model (quad2nurbs writes all formats and its report in one run)
    rows, batch = [], []
    for mesh in meshes:
        mname = os.path.splitext(os.path.basename(mesh))[0]
        counts = mesh_counts(mesh)
        for method in a.methods.split(','):
            base = os.path.join(a.out, '%s_%s' % (mname, method))
            cmd = [a.exe, '-q', '--surface', method, mesh] + sum([['-o', base + '.' + f] for f in fmts], [])
            label, nsub = mname, 0
            if method == 'augmented' and not counts[3] and a.nonquad_subdivide > 0:
                nsub = a.nonquad_subdivide
                cmd += ['--subdivide', str(nsub)]
                label = '%s (subdivided%s)' % (mname, '' if nsub == 1 else ' %d' % nsub)
            if a.threads > 0:
                cmd += ['--threads', str(a.threads)]
            t0 = time.time()
            rc, _, err = run(cmd + ['-o', base + '.json'], a.timeout)
            msg = None
            if rc != 0:
                msg = err.strip().splitlines()[-1] if err.strip() else 'exit %d' % rc
            sys.stderr.write('%s %s: %s (%.1f s)\n' % (label, method, 'built' if msg is None else msg,
                                                     time.time() - t0))
            sys.stderr.flush()
            rows.append((mesh, label, counts, method, base, msg, nsub))
            if msg is None:
                for fmt in fmts:
                    aj = '%s.%s.audit.json' % (base, fmt)
                    if os.path.exists(aj):
                        os.remove(aj)
                    # the report's diagonal: after --subdivide the model's mesh is not the input
                    batch.append('%s.%s --no-edges --mesh %s --report %s.json --json %s' % (base, fmt, mesh, base, aj))
    # 2. one FreeCAD process audits them all
    lst = os.path.join(a.out, 'batch.txt')
    with open(lst, 'w') as f:
        f.write('\n'.join(batch) + '\n')
    t0 = time.time()
    run([sys.executable, os.path.join(HERE, 'q2n_audit.py'), '--batch', lst])
    sys.stderr.write('FreeCAD audit of %d files: %.1f s\n' % (len(batch), time.time() - t0))
    # 3. the table
    print('| mesh | method | format | faces | valid | shells/solids | free edges (mesh bnd) | G0 gap/diag '
          '| G1 deg (report) | G2 rel (report) | compare | import+audit s |')
    print('|---|---|---|---|---|---|---|---|---|---|---|---|')
    for mesh, mname, (nf, nbnd, _, _), method, base, msg, nsub in rows:
        if msg is not None:
            print('| %s | %s | – | – | – | – | – | – | – | – | not built: %s | – |' %
                  (mname, method, msg.replace('|', '/')[:90]))
            continue
        with open(base + '.json') as f:
            rep = json.load(f)
        scale = 1
        if nsub > 0:        # subdivided here: boundary edges x 2 per step
            scale = 2 ** nsub
        else:               # the CLI may subdivide itself (acc-g1 at EVs, ACC on non-quads)
            while nf * scale * scale < rep.get('faces', nf):
                scale *= 2
        for fmt in fmts:
            aj = '%s.%s.audit.json' % (base, fmt)
            if not os.path.exists(aj):
                print('| %s | %s | %s | import failed | | | | | | | | |' % (mname, method, fmt))
                continue
            with open(aj) as f:
                d = json.load(f)
            rc, _, _ = run([sys.executable, os.path.join(HERE, 'q2n_compare.py'), aj, base + '.json'])
            print('| %s | %s | %s | %d | %s | %d/%d | %d (%d) | %.1e | %.3g (%.3g) | %.3g (%.3g) | %s | %.1f |' % (
                mname, method, fmt, d['faces'], 'yes' if d['valid'] else 'NO', d['shells'], d['solids'],
                d['free_edges'], nbnd * scale, d['g0_max_rel'], d['g1_max_deg'], rep.get('g1_max_deg', -1),
                d['g2_max_rel'], rep.get('g2_max_rel', -1), 'agree' if rc == 0 else 'DISAGREE',
                d['seconds_read'] + d['seconds_audit']))
    return 0


if __name__ == '__main__':
    sys.exit(main())
