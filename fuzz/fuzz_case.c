/* Fuzz target: the YAML case loader with --set overrides (and whatever stages, pours and mesh
 * walls the text holds).
 * Input: the case text, then up to four --set strings, each after a NUL byte:
 *   "name: x\n...\0time.end=0.1\0materials.glass.friction=0.3"
 * A case that loads is also prepared and stepped twice when it is small, since `adem run` does
 * that with it next. */
#include <stdlib.h>
#include <string.h>

#include "adem/adem.h"
#include "fuzz_common.h"

enum { MAX_INPUT = 32 * 1024,
       MAX_SETS = 4,
       STEP_PARTICLES = 300 };

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc;
  (void)argv;
  fuzz_quiet();
  return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  if (size > MAX_INPUT) return -1;
  char *text = malloc(size + 1);
  if (!text) return 0;
  memcpy(text, data, size);
  text[size] = '\0';
  const char *sets[MAX_SETS];
  int nsets = 0;
  for (char *p = text + strlen(text); p < text + size && nsets < MAX_SETS;) {
    sets[nsets++] = ++p;
    p += strlen(p);
  }
  adem_case *c = NULL;
  adem_error err;
  memset(&err, 0, sizeof err);
  /* Relative mesh files resolve as in cases/ (meshes/hopper.stl). */
  adem_status st = adem_case_load_string_at(text, "fuzz.yaml", ADEM_FUZZ_CASES_DIR, sets, nsets,
                                            &c, &err);
  fuzz_check_status(st, &err, "adem_case_load_string_at");
  if (!st && !c) abort();
  if (st && c) abort();
  if (!st && adem_world_particle_count(c->world) <= STEP_PARTICLES) {
    adem_world_set_threads(c->world, 1);
    st = adem_world_prepare(c->world, &err);
    fuzz_check_status(st, &err, "adem_world_prepare");
    if (!st) {
      st = adem_world_step(c->world, 2, &err);
      fuzz_check_status(st, &err, "adem_world_step");
    }
  }
  adem_case_free(c);
  free(text);
  return 0;
}
