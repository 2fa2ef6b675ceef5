/* OpenMP in one place. Every parallel loop writes only its own elements, so results do not depend
 * on the number of threads; sums go through adem_sum (fixed blocks). Functions that use
 * ADEM_PARALLEL_FOR declare `int nthreads` first. */
#ifndef ADEM_PARALLEL_H
#define ADEM_PARALLEL_H


/* Calls fn(ctx, i) for every i in [0, n): on a team of nthreads threads, or in a plain loop for
 * one thread, because entering an OpenMP region costs more than a tiny system's whole loop. */
#define ADEM_FOR(nthreads, n, fn, ctx)                                         \
  do {                                                                         \
    size_t adem_n_ = (n);                                                      \
    if ((nthreads) > 1) {                                                      \
      ADEM_PARALLEL_FOR                                                        \
      for (size_t adem_i_ = 0; adem_i_ < adem_n_; ++adem_i_) fn(ctx, adem_i_); \
    } else {                                                                   \
      for (size_t adem_i_ = 0; adem_i_ < adem_n_; ++adem_i_) fn(ctx, adem_i_); \
    }                                                                          \
  } while (0)

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
