#!/usr/bin/python3
"""q2n_compare.py — compare the FreeCAD import audit (tools/q2n_audit.py JSON) with quad2nurbs'
own report JSON and fail on disagreement.

Fields compared (names fixed by the fit issue's report): faces (exactly), g0_max_rel, g1_max_deg,
g2_max_rel, and the rim's largest turn and curvature jump where boundary edges of two faces meet
(rim.max_turn_deg, rim.curvature_jump_rel in both).  Two maxima sampled at possibly different points agree when
    |audit - report| <= max(ABS, REL * max(|audit|, |report|))
with ABS/REL per field (defaults: g0 1e-9 / 0.01, g1 1e-4 deg / 0.01, g2 1e-4 / 0.01, rim 1e-4 deg /
0.01, rimk 1e-4 / 0.01; override with --tol-g0 ABS,REL etc.).  Optional targets
(--target-g0/-g1/-g2/-rim/-rimk) are upper bounds the audit's figures must also meet.  The report's fields are looked up at its top level, then in nested
objects (first match).  A field missing from the report is listed and skipped unless --strict.
The audit samples the report's own points by default (4 per knot span of each edge), where the two agree
to ~1e-6 relative (the report prints 6 digits): hence the tight defaults.  Audits run with other
--samples need looser --tol-* values.
The two must use one diagonal (bbox_diag) for their relative figures: a difference is reported as a
disagreement of its own (run the audit with --report REPORT.json, which takes the report's).
Prints one line per field; exit 0 = agree, 1 = disagreement or target missed, 2 = bad input.
"""
import argparse
import json
import sys

FIELDS = [('g0_max_rel', (1e-9, 0.01)), ('g1_max_deg', (1e-4, 0.01)), ('g2_max_rel', (1e-4, 0.01)),
          ('max_turn_deg', (1e-4, 0.01)), ('curvature_jump_rel', (1e-4, 0.01))]
OPTION = {'g0_max_rel': 'g0', 'g1_max_deg': 'g1', 'g2_max_rel': 'g2', 'max_turn_deg': 'rim',
          'curvature_jump_rel': 'rimk'}


def find_field(obj, name):
    if isinstance(obj, dict):
        if name in obj and not isinstance(obj[name], (dict, list)):
            return obj[name]
        for v in obj.values():
            r = find_field(v, name)
            if r is not None:
                return r
    elif isinstance(obj, list):
        for v in obj:
            r = find_field(v, name)
            if r is not None:
                return r
    return None


def parse_pair(s):
    a, r = s.split(',')
    return float(a), float(r)


def compare(audit, report, tols, targets, strict):
    """Returns (ok, lines)."""
    ok, lines = True, []
    fa, fr = find_field(audit, 'faces'), find_field(report, 'faces')
    if fr is None:
        lines.append('faces: audit %s, report missing' % fa)
        ok = ok and not strict
    elif fa != fr:
        lines.append('faces: audit %s != report %s  DISAGREE' % (fa, fr))
        ok = False
    else:
        lines.append('faces: %s  ok' % fa)
    da, dr = find_field(audit, 'bbox_diag'), find_field(report, 'bbox_diag')
    if da is not None and dr is not None and abs(da - dr) > 1e-9 * max(abs(da), abs(dr)):
        lines.append('bbox_diag: audit %.9g (%s) != report %.9g: the relative figures divide by different '
                     'diagonals (after --subdivide or --scale the model\'s mesh is not the file given to the '
                     'audit); audit with --report REPORT.json  DISAGREE' % (da, audit.get('diag_source', '?'), dr))
        ok = False
    for name, _ in FIELDS:
        a, r = find_field(audit, name), find_field(report, name)
        ab, rel = tols[name]
        if a is None:
            lines.append('%s: missing from the audit  FAIL' % name)
            ok = False
            continue
        if r is None:
            lines.append('%s: audit %.6g, report missing%s' % (name, a, '  FAIL' if strict else ''))
            ok = ok and not strict
        else:
            tol = max(ab, rel * max(abs(a), abs(r)))
            agree = abs(a - r) <= tol
            lines.append('%s: audit %.6g report %.6g |diff| %.3g tol %.3g  %s' %
                         (name, a, r, abs(a - r), tol, 'ok' if agree else 'DISAGREE'))
            ok = ok and agree
        t = targets.get(name)
        if t is not None:
            meets = a <= t
            lines.append('%s: audit %.6g target %.6g  %s' % (name, a, t, 'met' if meets else 'MISSED'))
            ok = ok and meets
    return ok, lines


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('audit', help='JSON from tools/q2n_audit.py')
    ap.add_argument('report', help="quad2nurbs' report JSON")
    for name, (ab, rel) in FIELDS:
        key = OPTION[name]
        ap.add_argument('--tol-' + key, type=parse_pair, default=(ab, rel), metavar='ABS,REL',
                        help='agreement tolerance for %s (default %g,%g)' % (name, ab, rel))
        ap.add_argument('--target-' + key, type=float, default=None, metavar='MAX',
                        help='upper bound the audit\'s %s must meet' % name)
    ap.add_argument('--strict', action='store_true', help='a field missing from the report fails')
    a = ap.parse_args()
    try:
        with open(a.audit) as f:
            audit = json.load(f)
        with open(a.report) as f:
            report = json.load(f)
    except (OSError, ValueError) as ex:
        sys.stderr.write('q2n_compare: %s\n' % ex)
        return 2
    tols = {name: getattr(a, 'tol_' + OPTION[name]) for name, _ in FIELDS}
    targets = {name: getattr(a, 'target_' + OPTION[name]) for name, _ in FIELDS}
    ok, lines = compare(audit, report, tols, targets, a.strict)
    print('\n'.join(lines))
    print('agree' if ok else 'DISAGREE')
    return 0 if ok else 1


if __name__ == '__main__':
    sys.exit(main())
