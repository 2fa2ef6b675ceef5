#include "fpenv.h"

#include <fenv.h>

#include "log.h"
#include "parallel.h"

#if defined(__x86_64__) || defined(__i386__)
#include <xmmintrin.h>
#define MXCSR_FTZ 0x8000u /* flush-to-zero */
#define MXCSR_DAZ 0x0040u /* denormals-are-zero */
static unsigned flush_bits(void) {
  unsigned m = _mm_getcsr();
  return (m & MXCSR_FTZ ? 1u : 0u) | (m & MXCSR_DAZ ? 2u : 0u);
}
static void clear_flush(void) { _mm_setcsr(_mm_getcsr() & ~(MXCSR_FTZ | MXCSR_DAZ)); }
#elif defined(__aarch64__)
#define FPCR_FZ (1ull << 24)
static unsigned long long read_fpcr(void) {
  unsigned long long r;
  __asm__ volatile("mrs %0, fpcr"
                   : "=r"(r));
  return r;
}
static unsigned flush_bits(void) { return read_fpcr() & FPCR_FZ ? 1u : 0u; }
static void clear_flush(void) {
  unsigned long long r = read_fpcr() & ~FPCR_FZ;
  __asm__ volatile("msr fpcr, %0"
                   :
                   : "r"(r));
}
#else
static unsigned flush_bits(void) { return 0u; }
static void clear_flush(void) {}
#endif

unsigned adem_fpenv_faults(void) { return flush_bits() | (fegetround() != FE_TONEAREST ? 4u : 0u); }

/* resets this thread; returns what it found */
static unsigned fix_thread(void) {
  unsigned f = adem_fpenv_faults();
  if (f & 3u) clear_flush();
  if (f & 4u) fesetround(FE_TONEAREST);
  return f;
}

int adem_fpenv_ensure(int nthreads) {
  unsigned found = fix_thread();
  int fixed = found ? 1 : 0;
#ifdef ADEM_HAVE_OPENMP
  if (nthreads > 1) {
#pragma omp parallel num_threads(nthreads) reduction(|                    \
                                                     : found) reduction(+ \
                                                                        : fixed)
    {
      if (omp_get_thread_num() != 0) {
        unsigned f = fix_thread();
        found |= f;
        fixed += f ? 1 : 0;
      }
    }
  }
#else
  (void)nthreads;
#endif
  if (fixed)
    adem_log(ADEM_LOG_WARN,
             "the floating-point environment of %d thread(s) had%s%s%s (set by a library built "
             "with -ffast-math, or by the program); reset to IEEE defaults so that results are "
             "the same bits on every host",
             fixed, found & 1u ? " flush-to-zero" : "", found & 2u ? " denormals-are-zero" : "",
             found & 4u ? " a rounding mode other than to nearest" : "");
  return fixed;
}
