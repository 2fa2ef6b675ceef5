/* Cases for tests/mpi/test_split_features.c: what the split runs beyond plane walls, each small
 * and short (a second or so serial).
 *   - press: the settle case's 300 spheres with a lid: a first stage cut short by its `until`
 *     (the floor's load steady), a second lowering the lid, a third where a servo presses it
 *     on the bed (plane forces every step), a time.until checked all along (never met) and a
 *     counting region;
 *   - pour: 150 spheres in the settle box and 160 more poured in 8 batches (the test also
 *     runs it without the 150);
 *   - hopper: the flagship hopper's meshes (cases/meshes) with 300 spheres of 6 mm, the gate
 *     pulled aside at 30 ms and switched off by a stage at 60 ms;
 *   - mesh servo: bitwise/test_servo.c's case, a mesh plate pressed by a servo (face loads
 *     every step), with stages, and frames;
 *   - silo: bitwise/test_outlets.c's 300 spheres through a 24 mm orifice (cases/silo), removed by
 *     a region outlet and a domain-face outlet, with mass flows through a plane and of a region,
 *     run to 0.12 s. */
#ifndef ADEM_TEST_FEATURE_CASES_H
#define ADEM_TEST_FEATURE_CASES_H

#include "case_file.h"

#define press_case case_file_text("mpi-press") /* tests/cases/mpi-press.yaml */
#define pour_case case_file_text("mpi-pour")   /* tests/cases/mpi-pour.yaml */
/* tests/cases/mpi-hopper.yaml runs where it is (its meshes are cases/meshes/). The mesh servo is
 * tests/cases/bitwise-servo.yaml with frames, the silo tests/cases/outlets-silo.yaml shorter with
 * a windowed flow (feature_case_with_sets in test_split_features.c). */

#endif
