/* Mesh walls in a periodic box. Meshes are not imaged across periodic faces; a shell that is the
 * same all along a periodic axis (a drum or a pipe extruded along it) needs no image as long as it
 * reaches past both faces by the largest radius and the skin: a particle anywhere in the box,
 * or drifted out of it by less than the skin between builds, sees the same cross-section as the
 * shell's infinite continuation would show it. */
#ifndef ADEM_MESH_PERIODIC_H
#define ADEM_MESH_PERIODIC_H

#include "adem/base.h"
#include "mesh.h"

/* Accepts the mesh in a box periodic along axis (0..2) from lo to lo + len when no triangle
 * comes within reach of a face, or when those that do belong to a shell the same along the axis
 * (normals perpendicular to it; each strip of its cross-section tiled without a gap) reaching
 * past both faces by reach; refuses it otherwise with a message saying what to do. */
adem_status adem_mesh_check_periodic(const adem_mesh *m, int axis, double lo, double len,
                                     double reach, adem_error *err);

#endif
