/* Building a case, section by section: what the files of the case loader share. case.c's build()
 * calls the sections in the order of the case file (its table of contents); each section's file
 * is named after it: case_materials.c (materials, interactions, groups), case_motion.c (wall
 * motion and servos), case_walls_build.c (walls and mesh walls; case_walls.c the curved ones),
 * case_particles.c (particle sets, lattices, random fills, states, frozen sets), case_pours.c
 * (size distributions, regions, pours), case_time.c (run-until conditions, the time step and its
 * checks), case_output.c (tracked particles and output regions), case_stages.c (stages). */
#ifndef ADEM_CASE_BUILD_H
#define ADEM_CASE_BUILD_H

#include <stdbool.h>
#include <stddef.h>

#include "adem/case.h"
#include "adem/world.h"
#include "case_yaml.h"
#include "insert.h"
#include "stages.h"
#include "until.h"
#include "world_internal.h"

/* Sets larger than this are surely a typo and would only exhaust memory. */
#define MAX_SET_SPHERES 100000000.0

/* Loads a case as adem_case_load_string does; with LOAD_STAGE it is a stage's configuration: its
 * own stages are read but not prepared, and nothing is logged. */
enum { LOAD_STAGE = 1 };
adem_status adem_case_load_string_flags(const char *text, const char *name_for_messages,
                                        const char *base_dir, const char *const *sets, int nsets,
                                        unsigned flags, adem_case **out, adem_error *err);

/* ---- shared checks (case.c) ---- */
adem_status adem_case_check_box(case_ctx *ctx, adem_vec3 lo, adem_vec3 hi,
                                const yaml_node_t *hi_node, const map_cursor *m);

/* ---- materials, interactions, groups (case_materials.c) ---- */
adem_status adem_case_build_materials(case_ctx *ctx, const map_cursor *root);
adem_status adem_case_build_interactions(case_ctx *ctx, const map_cursor *root);
adem_status adem_case_build_groups(case_ctx *ctx, const map_cursor *root);
/* Index of the material (group) called name (given at node), or an error naming the known ones. */
adem_status adem_case_find_material(case_ctx *ctx, const char *name, const yaml_node_t *node,
                                    const char *path, int *index);
adem_status adem_case_find_group(case_ctx *ctx, const char *name, const yaml_node_t *node,
                                 const char *path, int *index);
void adem_case_warn_unused_law_params(case_ctx *ctx, const char *where, const adem_materials *mt,
                                      const adem_stages *stages);
void adem_case_warn_brof_turning(const char *where, const adem_world *w,
                                 const adem_stages *stages);

/* ---- walls and their motion (case_walls_build.c, case_motion.c) ---- */
adem_status adem_case_build_walls(case_ctx *ctx, const map_cursor *root);
char *adem_case_mesh_path(const case_ctx *ctx, const char *file);
adem_status adem_case_read_motion(case_ctx *ctx, const map_cursor *wall, adem_motion_def *def,
                                  double **time, adem_vec3 **vel, bool *given, yaml_node_t **at);
adem_status adem_case_servo_groups(case_ctx *ctx, const map_cursor *m, int first,
                                   bool *unmeasured);

/* ---- particles (case_particles.c) ---- */
adem_status adem_case_build_particles(case_ctx *ctx, const map_cursor *root);
void adem_case_box_include(case_ctx *ctx, adem_vec3 lo, adem_vec3 hi);
adem_status adem_case_check_memory(case_ctx *ctx, double extra, const yaml_node_t *node,
                                   const char *path);
double adem_case_spheres_for_volume(const adem_size_dist *d, double volume);

/* ---- sizes, regions, pours (case_pours.c) ---- */
adem_status adem_case_build_pours(case_ctx *ctx, const map_cursor *root);
adem_status adem_case_get_numbers(case_ctx *ctx, const map_cursor *m, const char *key,
                                  double **out, size_t *n, yaml_node_t **node);
adem_status adem_case_read_dist(case_ctx *ctx, const map_cursor *m, double fit,
                                const char *fit_what, const char *region_word, adem_size_dist *d,
                                map_cursor *dm);
adem_status adem_case_read_region(case_ctx *ctx, const map_cursor *m, bool box_keys,
                                  adem_region *r, const char **word);
adem_status adem_case_read_region_map(case_ctx *ctx, const map_cursor *rm, adem_region *r,
                                      const char **word);

/* ---- run-until, time step and its checks (case_time.c) ---- */
adem_status adem_case_read_until(case_ctx *ctx, const map_cursor *parent, adem_until_def *def,
                                 bool *given);
adem_status adem_case_choose_step(case_ctx *ctx, const map_cursor *time, adem_vec3 g);
adem_status adem_case_warn_pulling_forces(case_ctx *ctx);

/* ---- output (case_output.c) ---- */
/* `output`, read into ctx->c->output; *out its mapping (the outlets read it later). */
adem_status adem_case_build_output(case_ctx *ctx, const map_cursor *root, map_cursor *out);

/* ---- stages (case_stages.c) ---- */
adem_status adem_case_build_stages(case_ctx *ctx, const map_cursor *root);
adem_status adem_case_stages_prepare(adem_case *c, adem_error *err);

#endif
