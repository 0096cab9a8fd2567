/* ev_policy.h — tuning constants of the extraordinary-vertex constructions, each with its why.
 * The files that implement the papers' formulas hold none of these. */
#ifndef Q2N_PATCH_EV_POLICY_H
#define Q2N_PATCH_EV_POLICY_H

#include "core/vec3.h"

/* Gauss–Legendre points per direction for the fairness energy of a patch.  G1 patches have degree
 * <= 7 along a side, so 8 points integrate their energy integrands (degree <= 10) exactly.  G2
 * patches reach degree ~17 (integrands up to degree 30): 12 points give the same surfaces as 16 to
 * every digit of the fairness figures measured, 8 did not (docs/extraordinary.md, "Why the policy
 * values"). */
#ifndef EV_FAIR_GAUSS_G1
#define EV_FAIR_GAUSS_G1 8
#endif
#ifndef EV_FAIR_GAUSS_G2
#define EV_FAIR_GAUSS_G2 12
#endif
#define EV_FAIR_GAUSS_MAX (EV_FAIR_GAUSS_G1 > EV_FAIR_GAUSS_G2 ? EV_FAIR_GAUSS_G1 : EV_FAIR_GAUSS_G2)

/* Weight of the curvature-variation term against bending (both dimensionless per face): it is
 * what removes the ripples (bending alone ranks a wavy and a smooth cap alike); larger values
 * trade bending for monotone curvature, and sharp features get rougher (0.05-0.4 swept: 0.1 keeps
 * the most ripple targets met, docs/extraordinary.md "Why the policy values"). */
#ifndef EV_FAIR_W3
#define EV_FAIR_W3 0.1
#endif

/* A face whose variation after the bending-only pass exceeds this many times the median face's
 * gets its variation weight scaled down to that level: thin features (a rim of a few percent of
 * the model) must change curvature fast, and unweighted they would dictate the shape elsewhere. */
#define EV_FAIR_VAR_OUTLIER 4.0

/* Ridge towards the local estimates (q2n_ev_vertex_jets), relative to each unknown's own energy
 * diagonal.  First and second order: keeps tangent planes and curvatures near the mesh's local
 * shape where the energy is indifferent (weaker values smooth strongly anisotropic fans but cost the
 * fitted files spans at box-like corners: docs/extraordinary.md "Why the policy values");
 * third/fourth order and bubbles: only makes the system definite (the energy decides). */
#define EV_FAIR_RIDGE_LOW 1e-3
#define EV_FAIR_RIDGE_HIGH 1e-6

/* At a corner of the mesh's boundary (a vertex of one face) the jet's second order is
 * held towards its local estimate by EV_FAIR_RIDGE_CORNER, and its orders 3 and 4 at zero (the
 * fold guard's EV_FOLD_HOLD).  Only that face's corner sees them, and with the ridges above the
 * energy bought a smoother face with a curvature spike at the corner (|H| x diagonal up to 78
 * on a shared mesh whose boundary apices have fans of 3-6 faces; G1 patches there: 19;
 * docs/extraordinary.md).  Swept at stop 39 over 57 open meshes (G2,
 * fitted; geometric means against 1e-3, the rest of the ridge as above): 0.1 ripple 0.86 x
 * (better on 16, worse on 8: three-sided pyramids), Jacobian ratio 1.12 x, energy 1.00 x, largest
 * |H| 0.92 x; 1 and 100: ripple 0.90 / 0.92 x, energy 1.02 / 1.06 x (a flat star's 4 x at 100);
 * orders 3 and 4 alone: ripple 0.96 x but the spike stronger (121).  G1 patches kept the ridges
 * above until stop 52 (0.1 there: that mesh's ripple 0.50 -> 0.88).  Since the rim runs smoothly
 * through vertices of two faces (ev_derivatives.c fan_span) the corners between them take the rim's
 * turn, and G1 patches hold them too: 45 pyramids and shared open meshes in G1 mode 0.80 x the
 * ripple (better on 32, worse on 10; one shared mesh 1.75 -> 0.98, another 0.49 -> 0.63). */
#define EV_FAIR_RIDGE_CORNER 0.1

/* --keep-flat (ev_fair.c fan_flat): a vertex whose fan — every corner of every face around it, two
 * faces at least — lies within this fraction of the fan's radius of one plane is flat, and its jet
 * stays in that plane (without it the energy spreads neighbouring bends into flat panels: up to
 * 2 % of the diagonal on box-like meshes).  1e-5 covers coordinates written with 6-7 significant
 * digits (float exports); a fan that flat curves with a radius beyond 5e4 fan radii
 * (docs/extraordinary.md, "Flat fans"). */
#define EV_FLAT_REL 1e-5
/* Stiffness of a flat fan's jet terms normal to its plane, against the scaled energy's diagonal of
 * 1, in the first of the two solves: large enough that the in-plane terms are those of the
 * constrained optimum (to ~1e-4), small enough to keep the factorisation well conditioned; the
 * second solve makes the plane exact. */
#define EV_FLAT_PENALTY 1e4

/* Fold guard of the fair solve (ev_fair_solve.c, q2n_ev_fair_solve).  EV_FOLD_GRID points per direction judge
 * whether a patch folds: two neighbouring normals more than 90 degrees apart (a smooth patch turns
 * its normal by a few degrees per step of a 17-point grid, even around a thin plate's rim, while a
 * fold turns it over within one step).  Not the model scan's test (a normal against the face's
 * vector area): next to the corners of strongly warped faces the vertex normal may oppose it
 * without any fold, and holding those corners only roughened such surfaces.  EV_FOLD_HOLD is the
 * ridge, relative to each unknown's energy diagonal, that holds a folded face's corner jets (orders
 * 1, 2) at the local estimates: at 100 the estimates decide (1 left no fold either but a rougher
 * spike, 1e4 gave the surface of 100 to 3 digits: docs/extraordinary.md); EV_FOLD_PASSES bounds
 * the repeats, each holding the corners of the faces still folded. */
#define EV_FOLD_GRID 17
#define EV_FOLD_HOLD 1e2
#define EV_FOLD_PASSES 3
/* Where the held local estimates fold too (a corner pulled out 7 x: their tangents are too long for
 * the turn the tip faces must make), the guard shrinks the held jets by this factor per step (order
 * 1; order 2 by its square), halving as a backtracking search does, at most EV_FOLD_SHRINKS times:
 * the 7 x corner unfolds at the first halving (G2 osc 455 -> 15, E_ev 19 000 -> 1 142 on the fitted
 * file), a 10 x corner goes from 3 folded faces to 1 at the second; shorter tangents than a quarter
 * leave the tip's parametrisation nearly degenerate (Jacobian ratio ~0.005 there already). */
#define EV_FOLD_SHRINK 0.5
#define EV_FOLD_SHRINKS 2

/* Polynomial gluing of G1 patches (ev_fair_gluing.c).  The corner equations are solved as
 * constraints by a quadratic penalty of this weight against the least-change objective (unit
 * weight), refined EV_POLY_REFINE times: each refinement multiplies the rows' residual by about
 * (1/weight)² relative to their scale, so three reach rounding (1e-16 measured; the fifth and on
 * change nothing).  A component keeps the gluing when every row holds to EV_POLY_RESIDUAL (chart
 * units of order one: what the refinement leaves is 1e-16 where the equations are consistent,
 * 1e-4 and more where they are not) and every quadratic α's middle Bernstein coefficient has the
 * sign of its ends: then |α| stays above half the smaller end along the edge (ev_fair_gluing.c
 * q_keeps_sign; no constant), where an α through zero folds the derived face over (measured: a
 * shared box-like mesh's q of the wrong sign, |α| 0.03). */
#define EV_POLY_PENALTY 1e5
#define EV_POLY_REFINE 4
#define EV_POLY_RESIDUAL 1e-12
/* Passes of the gluing solve: an edge whose q misses its ends' sign keeps a cubic α, β with free end
 * slopes (least squares in the fit) and its component is solved again; the shared meshes need at most
 * three. */
#define EV_POLY_PASSES 6
/* A boundary vertex of fewer faces than this takes no twist corrections (its corners form an open
 * chain, not tied around the vertex): least-change corrections there bent the rims of open fans (G1
 * mode, fitted: open pyramids of five to eight sides 1.3-2.6 x the oscillation per EV diagonal, a
 * shared fan of boundary corners 0.87 -> 1.41).  Instead, at a vertex of two faces the edge between
 * them has α and β flat there and a quartic γ (value and slope only at that end), and the derived
 * face's side along the boundary takes the corner's twist from it (ev_fair_gluing.c): the 22
 * generated open pyramids are then exactly G1 in 21 cases, their oscillation 1.02 x on the geometric
 * mean (straight and convex rims 0.48-0.95 x, steep reflex rims 1.09-1.57 x, star-shaped ones 1.02-3.2 x).
 * Where a component's equations then fail, those edges keep a free q (the rim side takes the twist it
 * gives) before the vertices are pinned: open two-ring regions need it (exact then; one shared fan of
 * boundary corners ripples 1.6 x more, docs/extraordinary.md).  A one-face corner has no edge between
 * two faces. */
#define EV_POLY_BOUNDARY_FACES 3
/* Rounds of the gluing solve in which a component whose equations still fail gets the vertex of its
 * largest residual pinned (its corners keep their jets' twists, its edges cubics with free slopes at
 * the other end: least squares in the fit).  The corner equations of vertices of even valence can
 * be inconsistent around the handles of a closed surface (a torus of valence-4 vertices: residual
 * 1e-3), and one such vertex pinned opens the cycle. */
#define EV_POLY_PIN_ROUNDS 8
/* The gluing's near-fold guard (ev_fair.c): a face whose smallest Jacobian ratio (|S_u x S_v| over
 * its median, EV_FOLD_GRID points) the polynomial gluing takes below this fraction of the
 * smoothsteps' with the same jets has its corners kept out of the gluing.  Halving it is no rounding
 * or shape effect: the twist corrections of a nearly inconsistent component then shear the face
 * toward a fold (measured: 0.031 against the smoothsteps' 0.097 on a trapezoid between two valence-3
 * and two valence-5 corners, its bending energy 380 x; the other faces there keep 0.52 of theirs and more). */
#define EV_POLY_JAC_REL 0.5
/* G2 patches glued by polynomials: a face the gluing takes below this Jacobian ratio where the
 * smoothsteps keep it above is nearly folded by the gluing too.  It is issue 11's fold target ("min
 * jac >= 0.1 on every face"): the twist corrections of the G2 gluing sheared a cube's spike tip face to
 * 0.081 (the smoothsteps: 0.107), not by half. */
#define EV_POLY2_JAC_FLOOR 0.1
/* Neighbourhoods of sheared faces the border guard tries before it drops every flat border edge
 * (ev_fair.c border_shear): a cost bound, each ring is one more construction (the shared meshes that
 * keep flat edges need the first; the guard also stops when a ring does not reduce the shear). */
#define EV_POLY_GUARD_RINGS 3
/* A side from a cross-charted free vertex to a regular patch's corner is glued flat at the corner,
 * and a side between two cross-charted vertices may take a bump in β (ev_fair_gluing.c border_end,
 * bump_ok), where its β at those ends is within this of zero (chart ratios of order one: both are
 * zero by construction, up to rounding). */
#define EV_POLY_BETA_SAME 1e-12
/* Rounds in which components whose equations fail take, one per round, a bump in β and then give a
 * side flat at a regular corner its free slopes back (least squares in the fit), before any vertex is
 * pinned; and bumps per component.  Both are cost bounds, not tuning: each round solves the gluing
 * again.  The regions measured at stop 46 (docs/extraordinary.md, "Exact at the border": two rings
 * around vertices of valence 3-12, the shared meshes) that became exact needed at most 16 bumps, one
 * per round; a subdivided shared mesh with many regions went on failing for 60 rounds, and the border
 * guard (ev_fair.c) then kept the old gluing there anyway. */
#define EV_POLY_REVERT_ROUNDS 24
#define EV_POLY_BUMPS 24
/* Of those rounds, the first ones in which an edge whose q misses the sign of α's ends takes a bump in
 * its component (placed at that edge) instead of becoming a cubic with free slopes (least squares in
 * the fit).  A cost bound that also keeps rounds for failing equations: the rounds are counted over
 * all components at once, and when sign bumps could take all 24, a 732-face subdivided shared mesh
 * kept 53 edges more in least squares (stop 52: with half of them, 3; a shared torus with a hole
 * exact again, a subdivided one 21 edges more). */
#define EV_POLY_SIGN_ROUNDS 12

/* Polynomial gluing of G2 patches, the orders above the twist (ev_fair_gluing2.c): per vertex the
 * minimum-norm solution of its corner equations by LAPACK's rank-revealing least squares, columns
 * below EV_POLY2_RCOND of the largest counted dependent (rounding: the equations always have a
 * solution, ev_fair_gluing2.c's header), and the vertex keeps it when every equation holds to
 * EV_POLY2_RESIDUAL of the size of its terms (the edge vectors, the terms the tangential ones cancel,
 * the unknowns: those reach 60 times the edge vectors, and measured against the edge vectors alone
 * rounding, 1e-13 to 7e-11, failed vertices of two shared meshes and three generated ones). */
#define EV_POLY2_RCOND 1e-12
#define EV_POLY2_RESIDUAL 1e-10
/* G2 patches solve the twists' equations exactly, through the rows' normal equations (ev_fair_gluing.c
 * pg_solve_exact): EV_POLY_DUAL_REG of the largest diagonal entry added to the diagonal keeps rows that
 * depend on each other (consistent ones, at even valence) from a zero pivot without moving the
 * solution by more than rounding; EV_POLY_DUAL_REFINE solves in all, the first one and refinements
 * (the second leaves the rows at rounding, the third changes nothing measurable). */
#define EV_POLY_DUAL_REG 1e-14
#define EV_POLY_DUAL_REFINE 3
/* Rounds in which the vertices whose G2 equations failed are pinned and the gluing is solved again (a
 * cost bound: each round is one more gluing solve). */
#define EV_POLY2_PIN_ROUNDS 4

/* Two sides of a corner "agree" when their mixed derivatives differ by less than this fraction of
 * the corner's first- and mixed-derivative scale (rounding of the regular patches' jets); beyond
 * it the corner keeps a Gregory blend. */
#define EV_FAIR_COMPAT_REL 1e-9

/* Worker threads of the fair solve's per-face forms: more gain nothing on the machines we target
 * and each costs a stack. */
#define Q2N_EV_MAX_THREADS 64

/* Relative difference of two faces' transversality below which an edge's base face is its owner
 * face instead of the more transversal one (both constructions: ev_fair.c, curve_network.c):
 * differences that small are rounding (a symmetric mesh computed in floating point), and without
 * the margin one ulp of input could flip the choice and move the surface visibly.  Genuine
 * differences are far larger. */
#define EV_BASE_TIE 1e-9

/* ---- vertex jets from the mesh (ev_derivatives.c) ---- */

/* Largest end speed of an edge, in the jet's tangent map, over the edge's chord: a least-squares
 * tangent map cannot match every edge of a fan whose edge lengths differ widely, and a short edge
 * given several times its chord as end speed makes its quintic curve nearly stop before the other
 * end.  Capping it rescales that edge's local variable (the data stay one surface's derivatives);
 * a lower bound as well only made curvature extremes worse. */
#define EV_SPEED_MAX 1.5

/* Ridge of the fit of the tangential second-order part (the accelerations along the edges),
 * relative to its mean diagonal: the fan determines them weakly, and the ridge keeps them small
 * where it does not, without moving what it determines. */
#define EV_JET_ACCEL_RIDGE 1e-3

/* Ridge of the fit of the normal second-order part, relative to its trace: fans whose edges lie
 * on two lines leave the twist term free; far below the data's weight, it fixes it at zero. */
#define EV_JET_NORMAL_RIDGE 1e-9

/* Chart of a vertex's fan (fan_angles): a sector narrower than EV_CHART_MIN_ANGLE radians counts
 * as that wide (the others shrink in proportion), and no sector is wider than EV_CHART_MAX_ANGLE
 * unless its face's own shape keeps the wider corner regular (sector_cap, up to EV_CHART_WIDE_MAX)
 * (else the two faces at an edge would not lie on its two sides; the excess goes to the sectors
 * below their caps, in proportion).  Why 0.05: a sector of 3 degrees has hardly a usable direction
 * pair; on split triangulated lips with 1.3-2.8-degree needle corners a floor of 0.05 came out as
 * smooth as one of 0.01 or 0.001 or smoother (oscillation 3.5 against 4.2 on one;
 * docs/extraordinary.md, "Charts"), while calling such fans folded, as until stop 35, charted them
 * uniformly and folded the surface.  Why 0.75π (a margin of 45 degrees to the straight angle): a
 * face nearly a triangle at the vertex gets a patch corner that stays regular; swept 0.6π-0.97π
 * (docs/extraordinary.md "Why the policy values"), wider caps give such corners near-degenerate
 * Jacobians and ripples, narrower ones distort the other sectors (0.7π and below: fitted files miss
 * their tolerance, fans of nearly straight sectors ripple). */
#define EV_CHART_MIN_ANGLE 0.05
#define EV_CHART_MAX_ANGLE (0.75 * Q2N_PI)

/* Widest sector a fan's chart gives a face whose own shape allows a wide corner (a parallelogram
 * keeps its angle: sector_cap in ev_derivatives.c): 9 degrees short of the straight angle, so
 * that the two faces at an edge stay on its two sides with a margin.  Only needle corners of
 * split sliver triangles reach it; 0.9π was no better there (docs/extraordinary.md, "Why the
 * policy values"). */
#define EV_CHART_WIDE_MAX (0.95 * Q2N_PI)

/* ---- the paper's harmonisation of corner data (ev_harmonize.c) ---- */

/* Weight of the edge curves' change against the data's change in the surface-aware cost,
 * relative to their traces: small, so the patches' change decides, but enough to keep the
 * system definite along the edges. */
#define EV_HZ_EDGE_WEIGHT 1e-3

/* Gauss–Newton steps at most where the mismatches are not affine (slopes of a, b unknown): the
 * mismatches are nearly affine, so a few steps converge or the correction is not applied. */
#define EV_HZ_MAX_STEPS 8

/* The twist mismatches count as zero (the problem as affine, one step exact) below this fraction
 * of the largest mismatch: the rounding of the regular patches' mixed derivatives. */
#define EV_HZ_AFFINE_REL 1e-9

/* Gauss–Newton stops when the largest mismatch left is below this fraction of the initial one. */
#define EV_HZ_DONE_REL 1e-10

#endif
