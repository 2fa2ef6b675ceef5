/* OpenMP in one place. Every parallel loop writes only its own elements, so results do not depend
 * on the number of threads; sums go through adem_sum (fixed blocks). Functions that use
 * ADEM_PARALLEL_FOR declare `int nthreads` first. */
#ifndef ADEM_PARALLEL_H
#define ADEM_PARALLEL_H


#ifdef ADEM_HAVE_OPENMP
#include <omp.h>
#define ADEM_PARALLEL_FOR _Pragma("omp parallel for schedule(static) num_threads(nthreads)")
#define ADEM_PARALLEL_FOR_MAX(var) \
  _Pragma(ADEM_STR(omp parallel for schedule(static) num_threads(nthreads) reduction(max : var)))
#define ADEM_STR(x) #x
static inline int adem_default_threads(void) { return omp_get_max_threads(); }
#else
#define ADEM_PARALLEL_FOR (void)nthreads;
#define ADEM_PARALLEL_FOR_MAX(var) (void)nthreads;
static inline int adem_default_threads(void) { return 1; }
#endif

#endif
