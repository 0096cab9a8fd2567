/* blas.h — what the process's BLAS can be asked to do (blas.c). */
#ifndef Q2N_CORE_BLAS_H
#define Q2N_CORE_BLAS_H

/* 1 when the BLAS this process resolved is OpenBLAS built without threading support
 * (openblas_get_parallel() returns 0: Debian's libopenblas0-serial): such a build is not safe for
 * calls from several threads at once (OpenBLAS' FAQ; its USE_LOCKING builds are, but cannot be told
 * apart), and the construction and the fit call BLAS and LAPACK from their worker threads.  0 for
 * every other BLAS.  Looked up once. */
int q2n_blas_thread_unsafe(void);

#endif
