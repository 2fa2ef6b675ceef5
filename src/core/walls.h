/* Walls: infinite planes, boxes of planes and triangle-mesh groups, their prescribed motion
 * (positions are a function of time), whether each is switched on, and the loads the particles
 * put on every mesh face. */
#ifndef ADEM_WALLS_H
#define ADEM_WALLS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "adem/world.h"
#include "mesh.h"
#include "motion.h"
#include "stream.h"

typedef struct adem_plane {
  adem_plane_def def;        /* point and unit normal where the plane is now */
  adem_vec3 point0, normal0; /* at time 0 */
  adem_motion motion;        /* prescribed motion (def.velocity makes a constant one) */
  bool inactive;             /* switched off (walls[].active: false, or a stage): no contacts */
  uint8_t csv;               /* ADEM_WALL_CSV_*: which columns the CSV gives it */
} adem_plane;

/* CSV columns a wall gets when some configuration of the run moves it or gives it a servo. */
enum { ADEM_WALL_CSV_MOVES = 1u,
       ADEM_WALL_CSV_SERVO = 2u };

/* One mesh wall: the groups one STL file made (several for an ASCII file with several solids),
 * for its whole-file loads. */
typedef struct adem_mesh_wall {
  char name[ADEM_NAME_MAX]; /* the group's name, or the prefix of its groups' names */
  int first, count;         /* its groups */
  adem_vec3 ref0;           /* point its total torque is taken about, at time 0 */
  uint8_t csv;              /* ADEM_WALL_CSV_* */
} adem_mesh_wall;

typedef struct adem_walls {
  adem_plane *planes;
  int nplanes;
  /* triangle-mesh walls: groups of one mesh (mesh.h) */
  adem_mesh mesh;
  adem_motion *mesh_motion; /* per mesh group (moving groups have their own vertices) */
  double *mesh_reach;       /* per group: farthest reference vertex from its rotation centre */
  adem_vec3 *mesh_vert0;    /* vertices at time 0 */
  adem_vec3 *mesh_normal0;  /* triangle normals at time 0 */
  double time;              /* time the walls are placed at (the time of the forces) */
  double *face_force;       /* 3 per triangle: force of the particles on it, last force pass */
  double *face_torque;      /* 3 per triangle: its moment about its group's reference point */
  uint8_t *mesh_inactive;   /* per group < mesh_inactive_n, 1: switched off (no contacts) */
  int mesh_inactive_n;
  adem_vec3 *mesh_ref0;       /* per group: the point its torque is taken about, at time 0 */
  adem_vec3 *mesh_ref;        /* per group: that point where the group's motion has it now */
  adem_mesh_wall *mesh_walls; /* one per STL file loaded */
  int nmesh_walls;
} adem_walls;

/* What a configuration (a case, or a stage of it) says about a plane and a mesh group. */
typedef struct adem_plane_setting {
  adem_plane_def def;
  adem_vec3 point0, normal0;
  adem_motion motion;
  bool inactive;
} adem_plane_setting;

typedef struct adem_mesh_setting {
  adem_motion motion;
  int material;
  bool inactive;
} adem_mesh_setting;

/* The settings of every plane and mesh group as they are now (motions copied). */
adem_status adem_walls_get_settings(const adem_walls *wl, adem_plane_setting *planes,
                                    adem_mesh_setting *meshes, adem_error *err);
/* Goes from the settings prev to next at time t_s (a stage start): material and on/off, and a
 * wall that is moved or starts a new motion starts it from where it is, its clock at t_s. */
adem_status adem_walls_change(adem_walls *wl, const adem_plane_setting *prev_planes,
                              const adem_plane_setting *next_planes,
                              const adem_mesh_setting *prev_meshes,
                              const adem_mesh_setting *next_meshes, double t_s, adem_error *err);

/* A plane whose material index is below nmaterials; returns its index or -1 with err set. */
int adem_walls_add_plane(adem_walls *wl, const adem_plane_def *def, int nmaterials,
                         adem_error *err);
/* Six planes facing inwards, named NAME.xmin, NAME.xmax, ...; returns the first's index. */
int adem_walls_add_box(adem_walls *wl, const char *name, adem_vec3 lo, adem_vec3 hi, int material,
                       int nmaterials, adem_error *err);
/* Checks what adding a mesh wall needs before its file is read: the transform's material exists,
 * and a moving mesh (velocity != 0) has its own vertices. */
adem_status adem_walls_check_mesh(int nmaterials, const char *path, const adem_mesh_transform *tf,
                                  adem_vec3 velocity, adem_error *err);
/* Adds the blocks of a triangle soup (read from the file `path`) as one mesh wall: one group per
 * block, moving with velocity (non-zero needs tf->own_vertices). */
adem_status adem_walls_add_mesh_soup(adem_walls *wl, int nmaterials, const adem_mesh_soup *s,
                                     const adem_mesh_transform *tf, const char *path, int ascii,
                                     const char *name, adem_vec3 velocity, adem_error *err);
/* Point (at time 0) the torques of mesh wall `wall` and of each of its groups are taken about;
 * by default each group's area centroid and the file's. */
adem_status adem_walls_set_mesh_torque_point(adem_walls *wl, int wall, adem_vec3 point,
                                             adem_error *err);
/* Force and torque of the particles on each mesh group (ngroups entries each) and on each mesh
 * wall (nmesh_walls entries; either pair of pointers may be NULL): sums of face_force and
 * face_torque in face order, so the same for any thread count. Torques are about the reference
 * points where the walls' motion has them now. */
void adem_walls_mesh_loads(const adem_walls *wl, adem_vec3 *group_force, adem_vec3 *group_torque,
                           adem_vec3 *wall_force, adem_vec3 *wall_torque);
/* Prescribed motion of a mesh group (loaded with own vertices) or of a plane. */
adem_status adem_walls_set_mesh_motion(adem_walls *wl, int group, const adem_motion_def *def,
                                       adem_error *err);
adem_status adem_walls_set_plane_motion(adem_walls *wl, int plane, const adem_motion_def *def,
                                        adem_error *err);
/* Puts planes and mesh groups where their motion has them at time t. */
void adem_walls_place(adem_walls *wl, double t);
/* Switches a plane or a mesh group on or off; the neighbour lists need a rebuild. */
adem_status adem_walls_set_plane_active(adem_walls *wl, int plane, bool active, adem_error *err);
adem_status adem_walls_set_mesh_active(adem_walls *wl, int group, bool active, adem_error *err);
static inline bool adem_walls_mesh_active(const adem_walls *wl, uint32_t group) {
  return (int)group >= wl->mesh_inactive_n || !wl->mesh_inactive[group];
}
/* Largest distance a moving wall has travelled between t0 and the walls' time; a rotating plane
 * is bounded by the extent of the box lo..hi (has_box false: none). */
double adem_walls_shift(const adem_walls *wl, double t0, bool has_box, adem_vec3 lo, adem_vec3 hi);
/* The face loads of the force pass: cleared, then added to face by face. */
void adem_walls_clear_face_loads(adem_walls *wl);
static inline void adem_walls_add_face_load(adem_walls *wl, size_t t, adem_vec3 f, adem_vec3 tq) {
  double *ff = &wl->face_force[3 * t], *ft = &wl->face_torque[3 * t];
  ff[0] += f.x;
  ff[1] += f.y;
  ff[2] += f.z;
  ft[0] += tq.x;
  ft[1] += tq.y;
  ft[2] += tq.z;
}
void adem_walls_free(adem_walls *wl);

/* ---- servos (motion.servo) ---- */
bool adem_walls_has_servo(const adem_walls *wl);
/* Advances every servo of a switched-on wall by dt: its measured force from the loads of the last
 * force pass (plane_force: the particles' force on each plane; mesh walls from the face loads,
 * summed in face order, so the same for any thread count), filtered, then v = clamp(gain (F -
 * target)), u += v dt within the travel. A mesh wall's servo is its file's: the first servo
 * group's settings, the measured groups' loads, one state copied to all its servo groups. */
void adem_walls_servo_step(adem_walls *wl, const adem_vec3 *plane_force, double dt);
/* The servo of plane k / mesh wall k (NULL: none now). */
const adem_motion *adem_walls_plane_servo(const adem_walls *wl, int k);
const adem_motion *adem_walls_mesh_wall_servo(const adem_walls *wl, int k);
/* Displacement of plane k's point / mesh wall k's torque point since its motion began (the
 * case's start, or the stage that gave it its motion): prescribed and servo parts. */
adem_vec3 adem_walls_plane_displacement(const adem_walls *wl, int k);
adem_vec3 adem_walls_mesh_wall_displacement(const adem_walls *wl, int k);
/* Marks the walls the settings move or servo (ADEM_WALL_CSV_*), for the CSV columns. */
void adem_walls_note_settings(adem_walls *wl, const adem_plane_setting *planes,
                              const adem_mesh_setting *meshes);
/* Where the walls are placed from and their servos' state: what a stage change sets from where the
 * walls are (not a function of time once a servo has moved them), for checkpoints. */
void adem_walls_save_state(adem_writer *wr, const adem_walls *wl);
void adem_walls_load_state(adem_reader *rd, adem_walls *wl);
/* The walls' whole set-up (planes, meshes as time-0 triangles, motions, on/off, torque points),
 * for checkpoints of worlds made through the API; loading adds them to empty walls. */
void adem_walls_save_setup(adem_writer *wr, const adem_walls *wl);
adem_status adem_walls_load_setup(adem_reader *rd, adem_walls *wl, int nmaterials,
                                  adem_error *err);

#endif
