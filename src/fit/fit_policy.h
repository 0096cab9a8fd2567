/* fit_policy.h — every threshold and cap of the fit stage, each with why it has its value.  The
 * mathematics (degree, basis, gluing relations) lives in the .c files; the measured figures that
 * led to these values are in docs/fit.md, not here. */
#ifndef Q2N_FIT_POLICY_H
#define Q2N_FIT_POLICY_H

/* ---- defaults of q2n_fit_options ---- */
/* A measured normal jump at most this is rounding (issue 12's "exact up to rounding"): the report counts
 * such edges (g1_edges.within_rounding), whatever glued them — constraints, or both sides reproducing
 * polynomial patches (1e-13-1e-9 degrees measured there; least-squares gluing leaves 1e-4 and more). */
#define Q2N_FIT_G1_ROUNDING_DEG 1e-6
#define Q2N_FIT_TOL_DEFAULT 1e-5        /* relative to the bounding-box diagonal: CAD import tolerances are ~1e-6..1e-4 of a part */
#define Q2N_FIT_MAX_SPANS_DEFAULT 64    /* knot spans per patch direction: 69 x 69 control points is already heavy for CAD */
#define Q2N_FIT_MAX_ROUNDS_DEFAULT 12   /* bisection halves a span per round: 2^11 spans of refinement is far beyond the span cap */
/* ... and, unless the caller sets max_rounds, as many rounds again as the mesh's largest valence:
 * around a vertex of high valence continuity refinement travels one spoke per round (a spoke's new
 * knots change the patch between it and the next, whose refitted rows then miss the G2 aim in turn):
 * a UV sphere with 24-gon poles, subdivided, needed 26 rounds and missed the curvature target
 * (3.0 %) when stopped at 12; such late rounds refit a few patches each (0.93 s in all, the same as
 * with 12).  The 25 shared meshes stop after at most 7 rounds, so their files do not change. */
#define Q2N_FIT_G1_TARGET_DEFAULT 0.01  /* degrees of normal jump a CAD kernel still calls tangent-continuous (OCCT's angular tolerance is 0.01 rad; we stay far below) */
#define Q2N_FIT_G2_TARGET_DEFAULT 0.01  /* relative curvature jump: 1 % is invisible in zebra stripes and curvature combs */
/* The two defaults above hold at tol <= Q2N_FIT_TOL_DEFAULT; a looser tol loosens them in proportion
 * (tol / Q2N_FIT_TOL_DEFAULT), up to the caps: a normal jump θ moves the surface by ~θ·h at distance h
 * from the edge and a relative curvature jump ε by ~ε·κ·h²/2, both linear in the jump, so targets held
 * fixed while the tolerance grows buy precision the user did not ask for (at --tol 1e-4 they set most
 * of the spans on meshes with extraordinary vertices: docs/fit.md).  --angle-tol / --curvature-tol
 * override. */
#define Q2N_FIT_G1_TARGET_CAP 0.5       /* degrees: below OCCT's angular tolerance (0.01 rad = 0.57 deg), so edges still import as tangent */
#define Q2N_FIT_G2_TARGET_CAP 0.1       /* a 10 % curvature jump starts to show in curvature combs: beyond it the surface is not G2 in any useful sense */
#define Q2N_FIT_G1_WEIGHT_DEFAULT 3.0   /* least-squares gluing rows against fidelity rows: a row with one free point cannot satisfy both; over 64 meshes in G2 mode (docs/fit.md, "The weight of least-squares gluing rows") 1-5 give files alike, 10 0.7 % and 30 2.3 % heavier, every target met at each */

/* ---- refinement ---- */
#define Q2N_FIT_SAMPLES_PER_SPAN 4      /* fit samples per knot span and direction: 4 per new unknown keeps every block well overdetermined */
#define Q2N_FIT_REFINE_AIM 0.9          /* continuity refinement aims at this fraction of the acceptance target, judged on the jumps at the check points and the dense jump samples between them: those see the true maxima to ~1 % (256 points per edge on the shared meshes: 0.904 % where the fit held 0.9 %); the rest is margin for an importer's own evaluation.  At 0.5 on the check points alone (4 per span, which miss the maxima by up to 1.46x) the files were 6 % heavier (docs/fit.md) */
#define Q2N_FIT_JUMP_SAMPLES 4          /* jump samples per span of an edge's union knots at least, at the knots and halfway between the check points (4 per span, the odd eighths): with them 8 evenly spaced per span */
#define Q2N_FIT_JUMP_SAMPLES_EDGE 64    /* and at least this many per edge: the relative curvature jump peaks narrowly where the surface is nearly flat (|kappa| near its 1/diag floor) — on a coarse edge 8 per span missed a peak 1/16 of a span wide at 3.1x the check points' figure (docs/fit.md) */
#define Q2N_FIT_JUMP_DENSE_FROM 0.25   /* an edge is sampled between its check points once its jumps there reach this fraction of the aim: the maxima between them were up to 3.2x the check points' (a narrow peak on a coarse edge, docs/fit.md), so below a quarter the aim is out of reach */
#define Q2N_FIT_JUMP_MIN_SIN 1e-3      /* a jump sample where a side's tangents are closer than this (sine of their angle) is not counted: near a singular point (a collapsed side of a degenerate face) normals and curvatures are rounding, as at the singular point itself, which measures nothing (fit_measure.c) */
#define Q2N_FIT_EDGE_SHARE 0.9          /* share of the tolerance an edge curve may use on its own: its error shows in the cells beside it, which split it further where they fail (Q2N_FIT_EDGE_ASSIST); at 0.5 every edge was refined for a margin its patches seldom needed (docs/fit.md) */
#define Q2N_FIT_EDGE_ASSIST 0.25        /* a failing cell beside a side splits that span of the side's edge when the curve uses more than this share there: the patch's own knots cannot remove its boundary's error (without it an edge at 0.9 of the tolerance left a patch failing at the last round) */
#define Q2N_FIT_ROW_SHARE 0.25          /* share of the tolerance a cross-derivative row may cost in position terms */
#define Q2N_FIT_SPLIT_LEVELS 3         /* a span is split into at most 2^3 parts per round: the error model (h^6, h^5, h^4) is only asymptotic */
#define Q2N_FIT_SPLIT_MARGIN 2.0       /* a second (third) level of splitting only when the h^p model asks for twice the first's reduction */
#define Q2N_FIT_DIR_SHARE 0.25          /* a direction whose 6th-difference share of a cell's error is below this is not refined */
#define Q2N_FIT_STALL_SPANS 8          /* stalling is judged from this many edge spans on: coarser rows may not yet resolve the construction */
#define Q2N_FIT_CONT_LOCAL 2.0         /* a least-squares relation missing its aim by less than this splits only its spans that miss (one bisection's worth there: the jumps fall 16-32x); larger misses split every span, which converges, where grading towards the misses did not next to extraordinary corners (G2 files up to +15 % at 4, fits that never met the curvature target without a cap: docs/fit.md) */
#define Q2N_FIT_CONT_LOCAL_ROOM 2.0    /* ... and only while its knots, evened out at the level a local round reaches, could be bisected once more within --max-spans: near the cap graded knots spend the patches' span budget where uniform ones met the tolerance (at --max-spans 8, 4 of the 30 of 53 runs that met their targets missed them with local splits up to the cap, none with this; the default cap of 64 never binds it on the 48 + 5 meshes of docs/fit.md) */
#define Q2N_FIT_STALL_GAIN 1.2          /* a continuity edge refined twice in a row that improved by less than this each time stops driving refinement */

/* ---- gluing data (exact G1 constraints) ---- */
#define Q2N_FIT_GLUE_SAMPLES 9          /* construction samples per edge that decide the gluing polynomial: 9 dyadic points, reused by the row fits */
#define Q2N_FIT_GLUE_EXACT 1e-11        /* relative residual below which the construction's gluing is a polynomial of the tested degree (rounding of the 2x2 solve is ~1e-14) */
#define Q2N_FIT_GLUE_FLAT 1e-9         /* alpha' at an edge end below this (relative) is zero: second derivatives carry ~1e-13 rounding */
#define Q2N_FIT_SPEED_ITER 4000        /* CGLS iterations of the speed system: its graph-Laplacian-like condition needs ~mesh diameter x 30 */
#define Q2N_FIT_SPEED_RESID 1e-12       /* an edge whose speed equation (fit_target.c) is missed by more keeps least-squares gluing */
#define Q2N_FIT_SPEED_STOP 1e-14        /* CGLS stops once every speed equation is met this well, 100x below the acceptance above (a 10 000-face torus: 1 150 iterations instead of 2 590, where the residual's rounding floor is 3e-15) */
#define Q2N_FIT_CONSTRAINT_RCOND 1e-11  /* singular values of a constraint block below this (relative) are dependent rows, not conditions */
#define Q2N_FIT_CONSTRAINT_RESID 1e-9   /* a constraint block whose best solution misses by more (relative) is inconsistent: fall back to least squares */

/* ---- construction caches ---- */
#ifndef Q2N_FIT_ALPHA_CACHE_BYTES
#define Q2N_FIT_ALPHA_CACHE_BYTES 16e6  /* the reparametrized edges' alpha values (24 bytes per parameter) are kept up to this total, apart from the construction caches: large models fill those with samples, and every sample grid of a reparametrized patch asks for alpha again (a 2 400-face torus keeps ~1.5 MB) */
#endif
#ifndef Q2N_FIT_CACHE_BYTES
#define Q2N_FIT_CACHE_BYTES 64e6        /* construction values (side and grid caches together) are kept for reuse by the later stages and rounds up to this total; beyond it they are evaluated when needed: large models stay near 3.7 KB per face plus this, small ones keep every value */
#endif

#ifndef Q2N_FIT_PINV_CACHE_BYTES
#define Q2N_FIT_PINV_CACHE_BYTES 16e6   /* the interior stage's basis matrices and pseudo-inverses are kept for the later rounds up to this total: patches on the same knots share one (20 distinct over the 6 rounds of the subdivided 732-face spot, a few KB each), the largest (64 spans, 257 x 63) takes 260 KB */
#endif

/* ---- corners ---- */
#define Q2N_FIT_JET_SPREAD 0.1          /* two corner estimates disagreeing by more than this fraction of tol (control-point terms) are a Gregory-type corner */
#define Q2N_FIT_JET_H 0.002             /* step of the one-sided 6-point corner differences: rounding ~eps/h^2 stays below 1e-10 relative */

/* ---- construction scan (explains failures) ---- */
#define Q2N_FIT_SCAN_N 513              /* grid of the final scan: resolves features 1/500 of a face wide */
#define Q2N_FIT_SCAN_N_QUICK 257        /* grid of the scan during refinement: half the cost, still far below any knot spacing */
#define Q2N_FIT_SPIKE_RATIO 10.0        /* |dS| above 10x its median on a face is a spike narrower than any knot spacing (smooth faces stay below ~3) */
#define Q2N_FIT_SCAN_SPANS 16           /* a failing patch is scanned once before it gets this many spans in a direction */

/* ---- solves and corner points ---- */
#define Q2N_FIT_LS_RCOND 1e-13          /* a direct-solver block with a singular value below this (relative) is rank deficient, an error: the blocks are well overdetermined, only a broken one comes near */
#define Q2N_FIT_FOOT_STEPS 8           /* Gauss-Newton steps of a foot-point distance: it starts at the parametric foot, a few steps converge, the cap bounds the cost */
#define Q2N_FIT_INTERP_REL 1e-9         /* a construction whose corner lies this close (relative) to the vertex interpolates it and the vertex is kept exactly; farther (ACC) its corner is */

/* ---- exact Bézier conversion ---- */
#define Q2N_FIT_BEZIER_AGREE 1e-9       /* shared Bézier boundaries must agree to this (relative) before they are unified */

#endif
