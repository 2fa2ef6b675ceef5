/* adem check */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "adem/case.h"
#include "adem/run.h"
#include "adem/world.h"
#include "adem/vec3.h"
#include "cli.h"

const char *const check_help =
    "Usage:\n"
    "  adem check CASE.yaml [--set key.path=value ...]\n"
    "\n"
    "Reads and validates the case exactly as `adem run` would (including overlapping initial\n"
    "particles and particles outside walls), without running it, and prints:\n"
    "  - the particles (count, radius range) and walls;\n"
    "  - the geometry: each mesh group's bounding box; where each moving wall is at the start,\n"
    "    at the knots of its motion table, where a stage gives it a new motion and at the end,\n"
    "    and when stages switch walls off or on; a warning for each fill or pour region that\n"
    "    crosses an active plane or mesh group, lies behind a plane, or lies outside every\n"
    "    closed mesh wall large enough to hold it;\n"
    "  - per pair of materials that can meet: the effective Young's and shear moduli E*, G*\n"
    "    (the modified ones when stiffness_factor < 1), the range of the effective radius R*,\n"
    "    restitution e, damping factor beta = ln e / sqrt(ln^2 e + pi^2), friction, the normal\n"
    "    and rolling models, and the rolling friction each rolling law uses (BROF:\n"
    "    min(eta_i r_i, eta_j r_j); on a wall the particle's eta_r) and where it comes from;\n"
    "  - for each JKR pair, at its smallest spheres, real and modified (stiffness_factor, H24):\n"
    "    E*, gamma, a0, the equilibrium overlap a0^2/(3R), F_C = 3 pi gamma R, the pull-off\n"
    "    force (8/9) F_C, the Hertz collision time and the step t_c/50, the speed-up of the step\n"
    "    (E/E_mod)^(2/5), the Tabor parameter (a warning below 3, where JKR does not apply) and\n"
    "    the largest external force that stays below 10% of the modified pull-off force;\n"
    "  - the Hertz collision time at the reference speed v_ref, the Rayleigh time, the\n"
    "    proposed step min(t_c/50, 0.2 t_R, stability limit/5), the chosen step and whether it is automatic;\n"
    "  - the number of steps, frames, CSV rows and checkpoints;\n"
    "  - an estimate of the memory the run needs (every particle, the pours' totals included,\n"
    "    their candidate pairs, the neighbour grid), the limit it is held against\n"
    "    (limits.max_memory, or what the machine has available), and of the disk space of its\n"
    "    output.\n"
    "A case whose memory estimate exceeds the limit, or whose time.step is above the step\n"
    "limit min(t_collision/5, the contacts' stability limit) (unless limits.allow_large_step: true),\n"
    "is refused.\n"
    "\n"
    "Options:\n"
    "  --set key.path=value  override one value of the case file (as for adem run)\n"
    "  -h, --help            show this help\n"
    "\n"
    "Example:\n"
    "  adem check cases/pour.yaml --set time.step=1e-6\n"
    "\n"
    "Exit status: 0 the case is valid; 2 it is not (the message says what and where).\n";

/* ---------------------------------------------------------------- check */

int cmd_check(int argc, char **argv) {
  cli_options o;
  int rc = parse_options(argc, argv, &o, 0, "check");
  if (rc || o.help) {
    free(o.sets);
    if (o.help && !rc) fputs(check_help, stdout);
    return rc;
  }
  if (!o.case_path) {
    free(o.sets);
    return fail(EXIT_INPUT, "adem check needs a case file; see: adem check --help");
  }
  adem_error err;
  memset(&err, 0, sizeof err);
  adem_case *c = NULL;
  adem_status st = adem_case_load_file(o.case_path, o.sets, o.nsets, &c, &err);
  free(o.sets);
  if (!st) {
    st = adem_world_prepare(c->world, &err); /* overlaps, particles behind walls */
  }
  if (st) {
    adem_case_free(c);
    return fail(exit_code(st), "%s", err.message);
  }
  if ((st = adem_case_report(c, stdout, &err))) rc = fail(exit_code(st), "%s", err.message);
  else printf("\nthe case is valid\n");
  adem_case_free(c);
  return rc;
}
