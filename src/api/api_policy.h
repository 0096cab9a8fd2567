/* api_policy.h — the thresholds and caps of the pipeline object (model.c), each with its why. */
#ifndef Q2N_API_API_POLICY_H
#define Q2N_API_API_POLICY_H

/* Points per patch side of the scan every build ends with (cell centres of an n x n grid): every
 * value must be finite, and a normal turning against the face's is reported as a fold.  Why 8:
 * it finds folds that cover more than about 1/8 of a patch side (the bow-tie, dart and helmet
 * folds of tests/test_robust.c cover a third or more), at 64 evaluations a face, a few per cent
 * of a build; a narrower fold is below the fit's own sampling too. */
#define Q2N_MODEL_SCAN_GRID 8

#endif
