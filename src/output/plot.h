/* PNG plots by gnuplot: declared in the public adem/output.h. */
#ifndef ADEM_PLOT_H
#define ADEM_PLOT_H

#include "adem/output.h"

#endif
