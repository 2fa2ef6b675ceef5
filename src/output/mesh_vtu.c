/* Mesh frames: the triangles of every mesh wall with the force and pressure on each face. */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "adem/vec3.h"
#include "mesh.h"
#include "output.h"
#include "vtu.h"

/* ---------------------------------------------------------------- VTU */

enum { CHUNK = 1024 };

/* Cell or connectivity arrays generated chunk by chunk. */
static int put_cell_array(FILE *f, const adem_mesh *m, const double *face_force, int which) {
  size_t nt = m->ntris;
  for (size_t i = 0; i < nt; i += CHUNK) {
    size_t k = nt - i < CHUNK ? nt - i : CHUNK;
    union {
      int32_t i32[CHUNK];
      int64_t i64[3 * CHUNK];
      double f64[3 * CHUNK];
      uint8_t u8[CHUNK];
    } buf;
    size_t bytes = 0;
    for (size_t j = 0; j < k; ++j) {
      size_t t = i + j;
      adem_vec3 fc = face_force ? v3(face_force[3 * t], face_force[3 * t + 1], face_force[3 * t + 2])
                                : v3_zero();
      switch (which) {
        case 0:
          buf.i32[j] = (int32_t)m->group[t];
          bytes = 4 * k;
          break;
        case 1:
          memcpy(&buf.f64[3 * j], &m->normal[t], 24);
          bytes = 24 * k;
          break;
        case 2:
          memcpy(&buf.f64[3 * j], &fc, 24);
          bytes = 24 * k;
          break;
        case 3:
          buf.f64[j] = v3_norm(fc) / m->area[t];
          bytes = 8 * k;
          break; /* pressure */
        case 4:
          for (int c = 0; c < 3; ++c) buf.i64[3 * j + (size_t)c] = (int64_t)m->tri[t][c];
          bytes = 24 * k;
          break;
        case 5:
          buf.i64[j] = 3 * (int64_t)(t + 1);
          bytes = 8 * k;
          break; /* offsets */
        default:
          buf.u8[j] = 5;
          bytes = k;
          break; /* VTK_TRIANGLE */
      }
    }
    if (fwrite(&buf, 1, bytes, f) != bytes) return 0;
  }
  return 1;
}

typedef struct mesh_vtu {
  const adem_mesh *mesh;
  const double *face_force;
} mesh_vtu;

/* Array k of a mesh frame: cell arrays 0-3, the points (4), then the cell topology. */
static int put_mesh_array(FILE *f, int k, void *user) {
  const mesh_vtu *m = user;
  if (k == 4) return m->mesh->nverts == 0 ||
                     fwrite(m->mesh->vert, sizeof *m->mesh->vert, m->mesh->nverts, f) ==
                         m->mesh->nverts;
  return put_cell_array(f, m->mesh, m->face_force, k < 4 ? k : k - 1);
}

adem_status adem_mesh_write_vtu(const adem_mesh *mesh, const double *face_force, const char *path,
                                adem_error *err) {
  size_t nt = mesh->ntris, nv = mesh->nverts;
  /* Arrays in the order they are appended; connectivity is 3 Int64 per cell but one component
   * in VTK's eyes. */
  const adem_vtu_array arr[] = {
      {"group", "Int32", 1, 4 * nt},
      {"normal", "Float64", 3, 24 * nt},
      {"force", "Float64", 3, 24 * nt},
      {"pressure", "Float64", 1, 8 * nt},
      {"points", "Float64", 3, 24 * nv},
      {"connectivity", "Int64", 1, 24 * nt},
      {"offsets", "Int64", 1, 8 * nt},
      {"types", "UInt8", 1, nt},
  };
  adem_vtu_layout lay = {nv, nt, NULL, "CellData", "Scalars=\"pressure\" Vectors=\"force\"", 4, 5};
  mesh_vtu user = {mesh, face_force};
  return adem_vtu_write(path, &lay, arr, (int)(sizeof arr / sizeof arr[0]), put_mesh_array, &user,
                        err);
}
