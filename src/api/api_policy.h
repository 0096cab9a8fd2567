/* api_policy.h — the thresholds and caps of the pipeline object (model.c), each with its why. */
#ifndef Q2N_API_API_POLICY_H
#define Q2N_API_API_POLICY_H

/* Points per patch side of the scan every build ends with (cell centres of an n x n grid): every
 * value must be finite, and a normal turning against the face's is reported as a fold.  Why 8:
 * it finds folds that cover more than about 1/8 of a patch side (the folds tests/test_robust.c
 * builds cover a third or more), at 64 evaluations a face, a few per cent
 * of a build; a narrower fold is below the fit's own sampling too. */
#define Q2N_MODEL_SCAN_GRID 8

/* A folded face whose shortest edge is below this fraction of its longest is called nearly a
 * triangle in the fold warning, which then names that edge and the remedies (docs/mesh.md,
 * "near-triangle quad").  Why 0.02: on a regular torus with one edge shortened, the faces beside it
 * fold at a ratio of 0.0025 and not at 0.008; above 0.02 a fold has other causes (a dart, a warped
 * face, a thin feature), which the warning's other hints cover. */
#define Q2N_MODEL_NEAR_TRIANGLE 0.02

/* Where the mesh is flat (q2n_flat_faces_dev: faces whose corners' fans lie in the face's plane), a
 * build whose surface leaves that plane by more than this fraction of the diagonal says so, with
 * the remedy (--keep-flat).  Why 1e-4: ten times the default fit tolerance, so the bulge is the
 * construction's shape, not a fitting error, and visible (a box with support loops bulges ~1e-2);
 * on Q2N_MODEL_FLAT_GRID points a side (9: the faces' middles and quarters). */
#define Q2N_MODEL_FLAT_WARN 1e-4
#define Q2N_MODEL_FLAT_GRID 9

/* Largest bounding-box diagonal accepted, as a power of two: 2^1016 ~ 7e305.  Why: internally
 * everything is normalised, but what is handed back lives in the input's scale, and the surface's
 * first derivatives (up to a few diagonals on a wild mesh) and the sums and differences the CAD
 * writers form from control points need headroom below the largest double (2^1024): 2^8 of it.
 * A larger mesh is refused with a clear message instead of failing later with an overflow. */
#define Q2N_MODEL_MAX_DIAG_LOG2 1016

/* A run that splits polygons by Catmull-Clark suggests --fill-ngons when one has this many sides or
 * more: there the kites around the new centre are thin and pleat (cylinders with flat caps, fitted:
 * 12 sides 0.313 -> 0.072 curvature oscillation per EV diagonal filled, 21 sides 0.403 -> 0.041, 40
 * sides 0.889 -> 0.046), while smaller polygons gain little or lose (a heptagon cap 0.071 -> 0.070
 * and 8 % heavier; a character mesh's scattered pentagons: 60 % more faces, 12 % heavier files,
 * twice the time, more bending energy: docs/mesh.md). */
#define Q2N_MODEL_FILL_HINT_SIDES 12

/* The isotropic frame (model.c frame_choice).  A second build in the mesh's isotropic frame only where
 * the frame's stretch reaches this.  Why 1.25: meshes drawn with near-square faces estimate 1.02-1.21
 * from their faces' own irregularity, where there is no stretch to undo and a second construction
 * would cost its time for a surface hardly different; the smallest stretches where the isotropic
 * frame's build was measured better are 1.3-1.45 (small open and closed sets of unit cubes). */
#define Q2N_MODEL_FRAME_MIN_STRETCH 1.25
/* Samples per face diagonal of the ripple that chooses between the two builds.  Why 17: the
 * construction is a polynomial of degree 5-9 per patch, and a bump of its curvature spans a quarter
 * of a diagonal or more; 17 points see each with 4 samples, at 34 second-derivative evaluations a
 * face (a few per cent of a build). */
#define Q2N_MODEL_RIPPLE_SAMPLES 17
/* Gauss–Legendre points per direction of the bending energy that also decides.  Why 6: the rule is
 * exact for degree 11 per direction, the curvature of a degree 5-9 patch is smooth enough that the
 * energies of two builds compare right at a few per cent of their difference, at 36 evaluations a face. */
#define Q2N_MODEL_ENERGY_RULE 6
/* The gluing choice (model.c gluing_choice): a region's smoothsteps must ripple less than its polynomial
 * gluing by more than this fraction, and bend no more up to it.  Why 1e-3: the 6-point rule's own error
 * is up to 8e-4 of a region's energy (a cube's G2 patches, against 24 points); a capped five-sided
 * cylinder, whose two caps are mirror images, had one cap's smoothsteps 1.1e-4 above and the other's
 * 0.7e-4 below, and a strict comparison glued its caps differently; a region the polynomial gluing
 * leaves as it is (no edge of it glued so) differs from the smoothsteps' by rounding, which a strict
 * comparison of ripples took for a difference (a 50 : 1 plate). */
#define Q2N_MODEL_GLUING_TIE 1e-3

#endif
