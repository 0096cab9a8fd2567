/* export_policy.h — the export stage's chosen values (STEP and IGES writers), each with its why. */
#ifndef Q2N_IGES_EXPORT_POLICY_H
#define Q2N_IGES_EXPORT_POLICY_H

/* Resolution the files state (IGES global 19, STEP uncertainty) for a model that carries no fit
 * tolerance (exact conversions, as of the ACC patches), as a fraction of its bounding-box
 * diagonal: far above the rounding of the coordinates written (%.17g, ~1e-16), and finer than
 * the confusion tolerance CAD kernels apply to parts (OCCT: 1e-7 model units). */
#define Q2N_EXPORT_RESOLUTION_REL 1e-9

#endif
