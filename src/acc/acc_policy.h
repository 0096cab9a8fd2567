/* acc_policy.h — the ACC stage's chosen values, each with its why.  (The masks' weights are the
 * papers' formulas and stay in acc_masks.c with their equations.) */
#ifndef Q2N_ACC_ACC_POLICY_H
#define Q2N_ACC_ACC_POLICY_H

/* Gauss–Newton steps at most when a Catmull–Clark limit point is projected onto its ACC patch
 * (the quality measure's distance): the start is the limit point's own parameter, a few steps
 * converge; the cap only bounds the cost where the patch is singular. */
#define Q2N_ACC_PROJECT_STEPS 20

#endif
