/* policy.h — the api stage's thresholds: resource estimates and limits (options.c).  Each figure
 * was measured with /usr/bin/time -v (maximum resident set) on generated tori of 2 500–90 000
 * faces and the shared meshes; docs/cli.md ("Resource limits") has the table. */
#ifndef Q2N_API_POLICY_H
#define Q2N_API_POLICY_H

/* Resident memory of the program before any mesh (libraries, Ceres, glog): the estimate's floor. */
#define Q2N_MEM_BASE 8e6
/* Bytes per face of the construction (mesh, half-edges, parameters, patch data): what `sample`
 * and .obj runs peak at. */
#define Q2N_MEM_BUILD_PER_FACE 560.0
/* Bytes per face the fit adds at its peak with one knot span per patch, besides its caches;
 * refinement multiplies it roughly by the spans per patch, so the estimate is a lower bound for
 * refined fits.  STEP and IGES are streamed into their files: no memory. */
#define Q2N_MEM_FIT_PER_FACE 3150.0
/* The fit's construction caches (side and grid values) per face at one span per patch, up to
 * their budget (Q2N_FIT_CACHE_BYTES, fit/fit_policy.h). */
/* Bytes per face of an extraordinary region, added to the above: the fair construction's
 * per-face energy forms and its sparse factorisation (123 KB measured on a 11 022-face mesh whose
 * every face is extraordinary, 121 KB on the subdivided spot's 638), and the fit's refined
 * extraordinary patches (34 KB on the first: ~13 x 13 control points each). */
#define Q2N_MEM_BUILD_PER_EV_FACE 125e3
#define Q2N_MEM_FIT_PER_EV_FACE 35e3
/* The isotropic frame's second build (model.c frame_choice) runs while the first surface is kept:
 * its patch data, per face and again per extraordinary face.  Measured (maximum resident set of
 * `sample`, the frame tried against --frame off): 19-20 KB per face on subdivided convex hulls
 * whose every face is extraordinary, 23 on a 434-face character mesh, 42 MB on a 3064-face one
 * with a fourth of its faces extraordinary; 12 + 12 KB covers them.  Added where the mesh's
 * estimated stretch asks for the second build. */
#define Q2N_MEM_FRAME_PER_FACE 12e3
#define Q2N_MEM_FRAME_PER_EV_FACE 12e3
/* The extraordinary regions' extent: faces whose face and this many rings of faces around it (the
 * default class's 6 x 6 vertex grid: 2) reach an extraordinary vertex; on a mesh subdivided twice
 * or more, 9 fine faces per unit of the vertex's valence (the 6 x 6 block around a regular vertex
 * is 9 x 4 faces). */
#define Q2N_MEM_EV_RINGS 2
#define Q2N_MEM_EV_REGION_PER_VALENCE 9.0
#define Q2N_MEM_FIT_CACHE_PER_FACE 5750.0
/* Output bytes per face at one span per patch (the fit may refine: again a lower bound). */
#define Q2N_OUT_STEP_PER_FACE 3400.0    /* 3 338 measured on a 5 000-face torus, each distinct control point written once */
#define Q2N_OUT_IGES_PER_FACE 6700.0
#define Q2N_OUT_JSON 1000.0
/* The default --max-memory: this fraction of the physical memory (or of a smaller cgroup limit),
 * leaving the rest to the system and to other programs. */
#define Q2N_MEM_DEFAULT_FRACTION 0.5
/* The accepted relative fit tolerances Q2N_TOL_MIN, Q2N_TOL_MAX are part of the public contract:
 * include/quad2nurbs.h. */

#endif
