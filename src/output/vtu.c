/* VTU writer: XML header with appended-data offsets, then the raw blocks. */
#include "vtu.h"

#include <errno.h>
#include <inttypes.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "adem/files.h"
#include "log.h"

const char *adem_vtu_byte_order(void) {
  const uint16_t one = 1;
  unsigned char b;
  memcpy(&b, &one, 1);
  return b == 1 ? "LittleEndian" : "BigEndian";
}

adem_status adem_vtu_write(const char *path, const adem_vtu_layout *lay, const adem_vtu_array *arr,
                           int narr, adem_vtu_put_fn *put, void *user, adem_error *err) {
  adem_afile af;
  adem_status st = adem_file_open(&af, path, err);
  if (st) return st;
  FILE *f = af.f;
  fprintf(f,
          "<?xml version=\"1.0\"?>\n"
          "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"%s\" "
          "header_type=\"UInt64\">\n"
          "  <UnstructuredGrid>\n",
          adem_vtu_byte_order());
  if (lay->field_data) fprintf(f, "    <FieldData>\n%s    </FieldData>\n", lay->field_data);
  fprintf(f,
          "    <Piece NumberOfPoints=\"%zu\" NumberOfCells=\"%zu\">\n"
          "      <%s %s>\n",
          lay->npoints, lay->ncells, lay->data_tag, lay->data_attrs);
  uint64_t offset = 0; /* each block: an 8-byte size, then the data */
  for (int k = 0; k < narr; ++k) {
    if (k == lay->points_at) fprintf(f, "      </%s>\n      <Points>\n", lay->data_tag);
    if (k == lay->cells_at) fprintf(f, "      </Points>\n      <Cells>\n");
    fprintf(f, "        <DataArray type=\"%s\" Name=\"%s\" ", arr[k].type, arr[k].name);
    if (arr[k].ncomp > 1) fprintf(f, "NumberOfComponents=\"%d\" ", arr[k].ncomp);
    fprintf(f, "format=\"appended\" offset=\"%" PRIu64 "\"/>\n", offset);
    offset += 8 + (uint64_t)arr[k].bytes;
  }
  fprintf(f,
          "      </Cells>\n"
          "    </Piece>\n"
          "  </UnstructuredGrid>\n"
          "  <AppendedData encoding=\"raw\">\n"
          "   _");
  int ok = 1;
  for (int k = 0; k < narr && ok; ++k) {
    uint64_t nbytes = arr[k].bytes;
    ok = fwrite(&nbytes, 8, 1, f) == 1 && put(f, k, user);
  }
  fprintf(f, "\n  </AppendedData>\n</VTKFile>\n");
  if (!ok || ferror(f)) {
    int e = errno ? errno : EIO;
    adem_file_abort(&af);
    return adem_error_set(err, ADEM_ERR_IO, "cannot write %s: %s", path, strerror(e));
  }
  return adem_file_commit(&af, err);
}
