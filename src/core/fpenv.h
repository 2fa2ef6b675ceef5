/* The floating-point environment a run needs for the same bits everywhere: round to nearest, and
 * subnormals kept (no flush-to-zero, no denormals-are-zero). A library built with -ffast-math
 * (its crtfastmath.o) or a program may have changed them; they are per thread. */
#ifndef ADEM_CORE_FPENV_H
#define ADEM_CORE_FPENV_H

/* Puts this thread's and the nthreads OpenMP threads' environment right where it was not
 * (clears FTZ and DAZ on x86-64, FZ on aarch64, sets round to nearest) and logs a warning saying
 * what was found. Returns the number of threads that had to be reset. */
int adem_fpenv_ensure(int nthreads);

/* What is wrong with this thread's environment, as a bit set: 1 flush-to-zero, 2
 * denormals-are-zero, 4 rounding other than to nearest; 0 if nothing. */
unsigned adem_fpenv_faults(void);

#endif
