/* STL files, ASCII and binary, loaded into a mesh. */
#ifndef ADEM_STL_H
#define ADEM_STL_H

#include "adem/case.h"
#include "adem/world.h"
#include "mesh.h"
#include "world_internal.h"

/* Reads an ASCII or binary STL file, transforms it, and appends it to mesh as one group per file
 * (or per `solid` block of an ASCII file with several). The group is named group_name if given,
 * else the solid's name, else the file's stem; with several solid blocks each group is named
 * PREFIX.SOLID (PREFIX = group_name or the stem, SOLID = the block's name or its 1-based number).
 * A name already used in mesh is an error. Degenerate triangles are dropped with one warning.
 * Errors (ADEM_ERR_INPUT) name the file and the line (ASCII) or triangle and byte offset
 * (binary); on any error mesh is left exactly as it was. */
adem_status adem_mesh_load_stl(const char *path, const adem_mesh_transform *tf,
                               const char *group_name, adem_mesh *mesh, adem_error *err);

/* The same from bytes in memory; path only names them in messages. */
adem_status adem_mesh_load_stl_bytes(const char *data, size_t size, const char *path,
                                     const adem_mesh_transform *tf, const char *group_name,
                                     adem_mesh *mesh, adem_error *err);

/* Parses STL bytes into a soup whose blocks carry the group names (checked against mesh's names);
 * *ascii tells which kind of file it was. On error the soup is empty. */
adem_status adem_stl_parse(const char *data, size_t size, const char *path,
                           const adem_mesh *mesh, const char *group_name, adem_mesh_soup *s,
                           int *ascii, adem_error *err);
/* The same from a file. */
adem_status adem_stl_read(const char *path, const adem_mesh *mesh, const char *group_name,
                          adem_mesh_soup *s, int *ascii, adem_error *err);

/* Adds the triangles of an STL file to the world as one mesh wall (one group per solid), moving
 * with velocity (non-zero needs tf->own_vertices). */
adem_status adem_world_add_stl(adem_world *w, const char *path, const adem_mesh_transform *tf,
                               const char *name, adem_vec3 velocity, adem_error *err);

#endif
