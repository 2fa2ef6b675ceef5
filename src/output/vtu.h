/* VTK XML UnstructuredGrid files with raw appended binary data (UInt64 block headers), shared by
 * the particle frames and the mesh frames. Written atomically through fileio. */
#ifndef ADEM_VTU_H
#define ADEM_VTU_H

#include <stddef.h>
#include <stdio.h>
#include "adem/base.h"

typedef struct adem_vtu_array {
  const char *name, *type; /* "radius", "Float64" */
  int ncomp;               /* components as VTK sees them (1 is not written) */
  size_t bytes;            /* size of the data block */
} adem_vtu_array;

/* Writes the data of array k (exactly arr[k].bytes bytes); returns 0 on a write error. */
typedef int adem_vtu_put_fn(FILE *f, int k, void *user);

typedef struct adem_vtu_layout {
  size_t npoints, ncells;
  const char *field_data;  /* XML lines inside <FieldData>, or NULL for none */
  const char *data_tag;    /* "PointData" or "CellData": the arrays before points_at */
  const char *data_attrs;  /* e.g. "Scalars=\"radius\" Vectors=\"velocity\"" */
  int points_at, cells_at; /* index of the <Points> array and of the first <Cells> array */
} adem_vtu_layout;

adem_status adem_vtu_write(const char *path, const adem_vtu_layout *lay, const adem_vtu_array *arr,
                           int narr, adem_vtu_put_fn *put, void *user, adem_error *err);

/* "LittleEndian" or "BigEndian": the byte order of this machine, for VTK headers. */
const char *adem_vtu_byte_order(void);

#endif
