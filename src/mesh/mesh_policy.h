/* mesh_policy.h — the thresholds of the mesh stage, each with why it has this value. */
#ifndef Q2N_MESH_MESH_POLICY_H
#define Q2N_MESH_MESH_POLICY_H

#include <limits.h>
#include <stddef.h>

/* Most vertices, faces or face corners a reader accepts: every index and count of the mesh is an
 * int, so a file with more is refused while it is read (before its arrays grow past it). */
#define Q2N_MESH_MAX_COUNT ((size_t)INT_MAX - 1)

/* Shortest edge, closest pair of opposite quad corners and narrowest face width (vector area /
 * longest edge) a mesh may have, as a fraction of its bounding-box diagonal.  Why 1e-12: it is
 * the finest fit tolerance (--tol accepts 1e-12 and up), so no CAD file written from the mesh
 * could state an uncertainty that keeps the two ends of a shorter edge (or the two sides of a
 * narrower face) apart: the importer merges them and the face has zero area.  It is also where
 * the input's own rounding (2.2e-16 of the coordinates) starts to decide an edge's direction
 * (to 2e-4 rad).  Scale-free: the test runs in coordinates normalised by a power of two. */
#define Q2N_MESH_MIN_LENGTH_REL 1e-12

/* A quad corner counts as reflex (turning against the quad's vector area) when its signed sine,
 * seen along that vector, is below minus this.  Why 1e-12: far above the rounding of a sine
 * computed from normalised coordinates (~1e-15), so a straight corner (180 degrees, as where a
 * vertex sits on the segment of its neighbours) never counts, and far
 * below any corner that really turns back.  Two reflex corners make a bow-tie: rejected. */
#define Q2N_MESH_REFLEX_SIN 1e-12

/* Pairing triangles into quads (pair.c): every corner of the quad two triangles make must have a
 * sine of at least Q2N_PAIR_MIN_SINE (so between 17.5 and 162.5 degrees: a convex quad whose patch
 * corners stay regular; a nearly straight corner — two thin triangles of a fan, a quad that is
 * nearly a triangle — would give a near-degenerate one, and a needle is what pairing is there to
 * avoid), and the two triangles' normals may differ by at most Q2N_PAIR_MAX_BEND radians (60
 * degrees: a pair bent further straddles a crease of the tessellation, and its quad would have to
 * turn that far within one patch; the faces of an icosahedron, 42 degrees apart, still pair, an
 * octahedron's, 71 degrees, do not). */
#define Q2N_PAIR_MIN_SINE 0.3
#define Q2N_PAIR_MAX_BEND (Q2N_PI / 3)

/* The longest augmenting path the pairing follows after its greedy pass (pair.c), in pairs traded:
 * on npm's 3 674-triangle bunny paths of 2, 3, 5 and any length leave 334, 250, 170 and 126 of the
 * greedy pass's 606 triangles unpaired; 8 keeps each search to a few thousand triangles on any mesh
 * (three candidates per triangle at most) while reaching nearly all the paths that exist. */
#define Q2N_PAIR_AUG_DEPTH 8

/* Filling n-gons (fill.c): the grid's shape (a x b cells, a + b = n/2) and where the ring starts
 * are chosen by the smallest corner sine of the harmonic fill.  Every shape and every start is
 * tried for polygons of up to Q2N_FILL_SEARCH_MAX sides; a larger polygon tries a lattice of about
 * Q2N_FILL_COARSE shapes x Q2N_FILL_COARSE starts, then, with the best of those, every shape within
 * one lattice step at its start, then every start within one lattice step with the best shape.  A shape's fills share one factorisation and are solved
 * Q2N_FILL_BATCH starts at a time (3 right-hand sides each).  Why the search: the balanced grid
 * (a = n/4) is what a round cap gets anyway (a 40-gon: a = 10, from vertex 0), but an elongated slot
 * needs a long thin grid — 34 sides: 3 x 14 instead of 8 x 9, smallest corner sine 0.69 against
 * 0.18, its fitted cap 8.1 -> 0.035 curvature oscillation per diagonal at the grid's corners; a
 * 66- or 80-sided slot on the balanced grid folds on 8 faces (stop 38; until then larger polygons
 * took the balanced grid), and on a searched one does not.  Why 128 and 16: the whole search of a
 * 128-gon (32 shapes x 64 starts) takes 0.2 s here, of a 200-gon 1.4 s; the lattice takes 0.1 s
 * on a 200-gon (the same fill as the whole search) and 1.8 s on a 500-gon (its whole search: 27 s).  Why
 * batches of 32: 3 x 32 columns of at most 126 x 126 grid vertices (a 500-gon) take 12 MB.  A candidate must beat the best so far by
 * Q2N_FILL_TIE relatively: the symmetric shapes of a regular polygon differ by rounding only, and
 * the first (the balanced grid from vertex 0) then stays. */
#define Q2N_FILL_SEARCH_MAX 128
#define Q2N_FILL_COARSE 16
#define Q2N_FILL_BATCH 32
#define Q2N_FILL_TIE 1e-9

/* A polygon whose best ring and grid has a corner turning against it (an L, a U: its reflex
 * corners) is split along a chord from a reflex corner into two even polygons, each filled the same
 * way (fill.c fill_poly), at most Q2N_FILL_SPLIT_DEPTH levels deep and Q2N_FILL_SPLIT_TRIES chords
 * tried per polygon.  Why 3: each level resolves at least one reflex corner, and three cover a U
 * (two) with one to spare; a polygon needing more is refused, as before stop 39.  Why 64: every
 * chord of a 16-gon from its reflex corners, in a few milliseconds; larger polygons try the first
 * 64 (from the lowest corner index). */
#define Q2N_FILL_SPLIT_DEPTH 3
#define Q2N_FILL_SPLIT_TRIES 64

/* A polygon is planar, for the odd pairing's new vertex on its edge (fill.c edge_point: kept in the
 * polygon's plane), when its vertices lie within Q2N_FILL_PLANAR_REL of its largest distance from
 * its centroid of the plane through the centroid normal to its vector area.  Why 1e-9: far above
 * the rounding of the coordinates and of that plane (1e-16 relative), far below any warp a
 * modeller means (a nanometre on a metre); a cube's flat 7-gon then stays flat when its new vertex
 * sits on a 90° edge (the four-point point was 6 % of the edge out of both faces). */
#define Q2N_FILL_PLANAR_REL 1e-9

/* The isotropic frame (frame.c).  A vertex whose faces' edges have a moment of determinant below
 * this (trace 1; 0.25 is isotropic) is collinear there and says nothing about a stretch. */
#define Q2N_FRAME_MIN_DET 1e-6
/* Faces of a vertex's fan that its moment reads at most (a fan beyond it is a polygon's centre after
 * Catmull–Clark: its first faces say enough about the region's stretch). */
#define Q2N_FRAME_FAN_MAX 64
/* Weight per vertex of the ridge on log G (toward the identity): small against the isotropy
 * equations (their residuals are O(0.1-1) on stretched meshes), it only fixes what they leave free
 * (a flat mesh's normal direction, which no vertex's tangent plane sees). */
#define Q2N_FRAME_RIDGE 0.05
/* Gauss–Newton steps of the estimate at most (it stops earlier once a step is below rounding): a
 * cap against a slow tail, not a tolerance. */
#define Q2N_FRAME_ITERATIONS 30

#endif
