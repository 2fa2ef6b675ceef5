/* Accessors and struct sizes for bindings that cannot read C structs (adem/binding.h). */
#include <stdio.h>
#include <string.h>

#include "adem/case.h"
#include "adem/frames.h"
#include "adem/run.h"
#include "adem/world.h"
#include "adem/binding.h"

adem_world *adem_case_world(adem_case *c) { return c->world; }

adem_status adem_case_set_output_dir(adem_case *c, const char *dir, adem_error *err) {
  if (strlen(dir) >= sizeof c->output.dir)
    return adem_error_set(err, ADEM_ERR_INPUT, "the output folder name is longer than %d characters",
                          ADEM_PATH_MAX - 1);
  snprintf(c->output.dir, sizeof c->output.dir, "%s", dir);
  return ADEM_OK;
}

const char *adem_case_output_dir(const adem_case *c) { return c->output.dir; }
double adem_case_end_time(const adem_case *c) { return c->end_time; }
const char *adem_case_name(const adem_case *c) { return c->name; }

size_t adem_abi_sizeof(const char *type) {
#define ADEM_SIZE(T) \
  if (!strcmp(type, #T)) return sizeof(T);
  ADEM_SIZE(adem_error)
  ADEM_SIZE(adem_vec3)
  ADEM_SIZE(adem_material_def)
  ADEM_SIZE(adem_interaction_def)
  ADEM_SIZE(adem_particle_def)
  ADEM_SIZE(adem_plane_def)
  ADEM_SIZE(adem_servo_def)
  ADEM_SIZE(adem_motion_def)
  ADEM_SIZE(adem_mesh_transform)
  ADEM_SIZE(adem_diagnostics)
  ADEM_SIZE(adem_contact_info)
  ADEM_SIZE(adem_step_estimate)
  ADEM_SIZE(adem_progress)
  ADEM_SIZE(adem_run_options)
  ADEM_SIZE(adem_vtu_frame)
  ADEM_SIZE(adem_particle_field)
#undef ADEM_SIZE
  return 0;
}
