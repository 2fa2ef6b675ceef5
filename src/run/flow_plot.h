/* flow.png: the outlets' and mass flows' columns of a run's CSV (flow_plot.c). */
#ifndef ADEM_FLOW_PLOT_H
#define ADEM_FLOW_PLOT_H

#include <stdbool.h>

#include "adem/case.h"
#include "outlets.h"

/* Draws png from csv when the case has outlets or mass flows (nothing otherwise). */
adem_status adem_run_plot_flow(const adem_case *c, const char *csv, const char *png,
                               adem_error *err);

#endif
