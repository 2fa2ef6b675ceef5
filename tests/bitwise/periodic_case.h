/* A periodic bed, tests/cases/periodic.yaml: 300 frictional spheres thrown sideways into a box
 * periodic in x and y, onto a frictionless floor, 2000 steps (the file says why so). Include
 * after cmocka.h. */
#ifndef ADEM_TEST_PERIODIC_CASE_H
#define ADEM_TEST_PERIODIC_CASE_H

#include "case_file.h"

#define PERIODIC_STEPS 2000

/* The case's text (tests/cases/periodic.yaml); periodic_load loads it with overrides. */
#define periodic_case case_file_text("periodic")
#define periodic_load(sets, nsets) case_file_load("periodic", sets, nsets)

#endif
