/* Triangle-mesh walls: triangles appended with a transform, shared vertices, edge adjacency with
 * flat/convex/concave edges and flat regions. Reading STL files is input/stl.h; writing mesh
 * frames is output. Sphere-triangle geometry and the one-contact-per-region rule are in
 * mesh_contact.h. */
#ifndef ADEM_MESH_H
#define ADEM_MESH_H

#include <stddef.h>
#include <stdint.h>

#include "adem/world.h"

/* Largest deviation from coplanar (radians) for an edge to count as flat. STL stores float32
 * coordinates (6e-8 relative): a tilted flat surface of triangles 100 times smaller than their
 * distance from the origin shows normals wobbling by a few 1e-6 rad; 1e-5 absorbs that and is far
 * below any facet angle a CAD export uses for a curved surface (degrees). */
#define ADEM_MESH_FLAT_ANGLE 1e-5

/* Kind of a triangle edge, seen from the side the triangle's normal points to. */
typedef enum adem_mesh_edge_kind {
  ADEM_MESH_EDGE_BORDER = 0,     /* no neighbour: an open edge of the surface */
  ADEM_MESH_EDGE_FLAT = 1,       /* the neighbour is coplanar (within flat_angle) */
  ADEM_MESH_EDGE_CONVEX = 2,     /* the neighbour bends away from the normal side */
  ADEM_MESH_EDGE_CONCAVE = 3,    /* the neighbour bends towards the normal side */
  ADEM_MESH_EDGE_NONMANIFOLD = 4 /* three or more triangles share the edge */
} adem_mesh_edge_kind;

/* A group: one STL file, or one `solid NAME` block of an ASCII file with several. */
typedef struct adem_mesh_group {
  char name[ADEM_NAME_MAX];
  int material;
  int own_vertices;                /* loaded with own_vertices: its vertices are its alone */
  uint32_t first, count;           /* its triangles, first .. first + count - 1 */
  uint32_t vert_first, vert_count; /* the vertices it added (with own_vertices: all of its own) */
} adem_mesh_group;

/* A triangle mesh. Zero-initialise (adem_mesh m = {0}), load into it, free it. Indices never
 * change when more files are appended: new vertices and triangles go at the end. Edge k of a
 * triangle joins its vertices k and (k + 1) % 3. */
typedef struct adem_mesh {
  /* vertices: exactly equal coordinates (after the transform) are one vertex */
  size_t nverts;
  adem_vec3 *vert;
  uint8_t *vert_flat; /* 1: every edge at the vertex is flat (the vertex is inside a flat region) */
  size_t *vt_start;   /* nverts + 1: triangles at vertex v are vt_tri[vt_start[v] .. vt_start[v+1]) */
  uint32_t *vt_tri;   /* ascending within each vertex */

  /* triangles */
  size_t ntris;
  uint32_t (*tri)[3];      /* vertex indices in the file's order */
  adem_vec3 *normal;       /* unit, right-hand rule on that order (the file's winding is kept) */
  double *area;            /* m^2 */
  uint32_t *group;         /* index into groups */
  uint32_t *region;        /* flat region: smallest triangle index of the coplanar set joined by flat edges */
  int32_t (*adj)[3];       /* triangle across edge k, or -1 (border or non-manifold edge) */
  uint8_t (*edge_kind)[3]; /* adem_mesh_edge_kind of edge k */
  uint32_t (*edge_id)[3];  /* id of the undirected edge, 0 .. nedges-1, shared by both sides */
  size_t nedges;

  int ngroups;
  adem_mesh_group *groups;

  /* what loading found (totals over every file loaded) */
  size_t normals_disagreed;  /* triangles whose stored normal pointed against the vertex order */
  size_t degenerate_dropped; /* zero-area triangles or triangles with a repeated vertex */
  size_t nonmanifold_edges;

  double flat_angle; /* radians; 0 means ADEM_MESH_FLAT_ANGLE. Set before loading. */
} adem_mesh;

/* Triangles as read from a file or made in code: 3 corners, the stored normal and where each
 * came from (a file's line of its `facet`, or a triangle index), in named blocks that become
 * groups. */
typedef struct adem_mesh_soup_block {
  char name[ADEM_NAME_MAX];
  size_t line; /* ASCII: line of `solid`; 0 otherwise */
  size_t first, count;
} adem_mesh_soup_block;

typedef struct adem_mesh_soup {
  size_t n, cap;
  adem_vec3 *corner; /* 3 per triangle */
  adem_vec3 *normal;
  size_t *where;
  size_t nblocks, block_cap;
  adem_mesh_soup_block *blocks;
} adem_mesh_soup;

void adem_mesh_soup_free(adem_mesh_soup *s);
/* Appends one triangle to the last block; 0 when out of memory. */
int adem_mesh_soup_push(adem_mesh_soup *s, const adem_vec3 c[3], adem_vec3 normal, size_t where);
/* Starts a block; NULL when out of memory. */
adem_mesh_soup_block *adem_mesh_soup_block_open(adem_mesh_soup *s, const char *name, size_t line);

/* Checks a transform (scale > 0, R a proper rotation, material >= 0); path names it in messages. */
adem_status adem_mesh_check_transform(const adem_mesh_transform *tf, const char *path,
                                      adem_error *err);
/* Appends the soup's blocks as groups (names already chosen and unique), transformed. Builds a
 * new mesh beside the old one and swaps it in, so that a failure leaves mesh untouched. Messages
 * name path and the facet's line (ascii != 0) or the triangle and its byte offset. */
adem_status adem_mesh_append_soup(adem_mesh *mesh, const adem_mesh_soup *s,
                                  const adem_mesh_transform *tf, const char *path, int ascii,
                                  adem_error *err);

/* Appends ntri triangles given as 3 corners each (already in world coordinates) as one group:
 * the same deduplication (own_vertices as in the transform), degenerate-triangle dropping and topology as a loaded file. For meshes
 * made in code. stored_normals (one per triangle, may be NULL or hold zero vectors) are only
 * compared with the vertex order. */
adem_status adem_mesh_add_triangles(adem_mesh *mesh, const adem_vec3 *corners,
                                    const adem_vec3 *stored_normals, size_t ntri,
                                    const char *group_name, int material, int own_vertices,
                                    adem_error *err);

void adem_mesh_free(adem_mesh *mesh);

/* Moves a group loaded with own_vertices by d (a rigid translation keeps normals, adjacency and
 * flat regions). ADEM_ERR_INPUT if the group shares vertices with others. */
adem_status adem_mesh_translate_group(adem_mesh *mesh, int group, adem_vec3 d, adem_error *err);

/* Index of the group with that name, or -1. */
int adem_mesh_find_group(const adem_mesh *mesh, const char *name);

/* Axis-aligned bounding box of the vertices (both zero for an empty mesh). */
void adem_mesh_bounds(const adem_mesh *mesh, adem_vec3 *lo, adem_vec3 *hi);

/* Total area of a group's triangles (group < 0: of every triangle), m^2. */
double adem_mesh_area(const adem_mesh *mesh, int group);

#endif
