/* blas.c — what the process's BLAS can be asked to do (blas.h).  Debian selects the BLAS and LAPACK
 * behind libblas.so.3 / liblapack.so.3 through update-alternatives, so which one a run gets is a
 * property of the machine, found out at run time: OpenBLAS exports openblas_get_parallel (0:
 * sequential build, 1: pthreads, 2: OpenMP); the others do not. */
#include "core/blas.h"

#include <dlfcn.h>
#include <pthread.h>

static int unsafe;
static pthread_once_t once = PTHREAD_ONCE_INIT;

static void probe(void)
{
    void *self = dlopen(NULL, RTLD_LAZY);
    if (!self) return;
    int (*parallel)(void) = NULL;
    void *sym = dlsym(self, "openblas_get_parallel");
    if (sym) *(void **)&parallel = sym; /* POSIX: a function's address through void * */
    unsafe = parallel && parallel() == 0;
    dlclose(self);
}

int q2n_blas_thread_unsafe(void)
{
    pthread_once(&once, probe);
    return unsafe;
}
