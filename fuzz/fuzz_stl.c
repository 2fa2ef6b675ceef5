/* Fuzz target: the STL reader, ASCII and binary (the first bytes decide, as in a file).
 * Input: the file's bytes. It is loaded twice into one mesh (the second time under another group
 * name, its vertices joined to the first's), as a case with two mesh walls does. */
#include <stdlib.h>
#include <string.h>

#include "fuzz_common.h"
#include "stl.h"

enum { MAX_INPUT = 256 * 1024 };

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc;
  (void)argv;
  fuzz_quiet();
  return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  if (size > MAX_INPUT) return -1;
  const char *path = fuzz_file(0, data, size);
  adem_mesh mesh;
  memset(&mesh, 0, sizeof mesh);
  adem_mesh_transform tf = adem_default_mesh_transform();
  adem_error err;
  memset(&err, 0, sizeof err);
  adem_status st = adem_mesh_load_stl(path, &tf, NULL, &mesh, &err);
  fuzz_check_status(st, &err, "adem_mesh_load_stl");
  size_t ntris = mesh.ntris;
  tf.scale = 1e-3;
  tf.translation.z = 0.5;
  st = adem_mesh_load_stl(path, &tf, "second", &mesh, &err);
  fuzz_check_status(st, &err, "adem_mesh_load_stl (second group)");
  /* On an error the mesh is left exactly as it was. */
  if (st && mesh.ntris != ntris) abort();
  adem_mesh_free(&mesh);
  return 0;
}
