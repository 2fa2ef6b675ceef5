/* Fuzz target: the checkpoint reader (adem run --resume).
 * Input: one mode byte, then the file. With bit 0 of the mode byte set, the header's payload size
 * and checksum are set to match the bytes that follow before the file is written, so that the
 * fuzzer gets past the checksum into the payload; otherwise the file is read as it is.
 * A checkpoint that loads is stepped twice when it is small, as the resumed run does next. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "adem/adem.h"
#include "adem/files.h"
#include "fuzz_common.h"
#include "stages.h"
#include "world_internal.h"

enum { MAX_INPUT = 1 << 20,
       HEADER = 40,
       STEP_PARTICLES = 300 };

/* Seeds: checkpoints of the seed cases (fuzz/seeds/case) before the first step and a few steps
 * in (inside the pour and the first stage), each as a raw file (mode 0) and with its header
 * fixed up (mode 1). Written when ADEM_FUZZ_SEEDS names a folder; the process then exits. */
static const char *const seed_cases[] = {"stages_pour.yaml", "mesh_walls.yaml", "discrete.yaml"};

static void write_seed(const char *dir, const char *name, int mode, const char *ckpt) {
  char *data = NULL;
  size_t n = 0;
  adem_error err;
  if (adem_file_read_all(ckpt, &data, &n, &err)) abort();
  char path[4096];
  snprintf(path, sizeof path, "%s/%s.%d", dir, name, mode);
  FILE *f = fopen(path, "wb");
  unsigned char m = (unsigned char)mode;
  if (!f || fwrite(&m, 1, 1, f) != 1 || fwrite(data, 1, n, f) != n || fclose(f) != 0) abort();
  free(data);
}

static void write_seeds(const char *dir) {
  char ckpt[4096];
  snprintf(ckpt, sizeof ckpt, "%s/.checkpoint", dir);
  for (size_t k = 0; k < sizeof seed_cases / sizeof seed_cases[0]; ++k) {
    char path[4096], name[256];
    snprintf(path, sizeof path, "%s/%s", ADEM_FUZZ_SEEDS_DIR "/case", seed_cases[k]);
    adem_case *c = NULL;
    adem_error err;
    char *text = NULL;
    size_t len = 0;
    /* Meshes are found where the fuzzed cases find them (cases/meshes). */
    if (adem_file_read_all(path, &text, &len, &err) ||
        adem_case_load_string_at(text, path, ADEM_FUZZ_CASES_DIR, NULL, 0, &c, &err)) {
      fprintf(stderr, "%s\n", err.message);
      abort();
    }
    free(text);
    for (int at = 0; at < 3; ++at) {
      if (at == 1) {
        if (adem_world_prepare(c->world, &err) || adem_stages_events(c, &err)) abort();
      }
      if (at == 2) {
        for (int s = 0; s < 300; s += 10)
          if (adem_world_step(c->world, 10, &err) || adem_stages_events(c, &err)) abort();
      }
      if (adem_checkpoint_write(c, ckpt, &err)) abort();
      snprintf(name, sizeof name, "%.*s_%d", (int)strcspn(seed_cases[k], "."), seed_cases[k], at);
      write_seed(dir, name, 0, ckpt);
      write_seed(dir, name, 1, ckpt);
    }
    adem_case_free(c);
  }
  remove(ckpt);
}

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc;
  (void)argv;
  fuzz_quiet();
  const char *seeds = getenv("ADEM_FUZZ_SEEDS");
  if (seeds) {
    write_seeds(seeds);
    exit(0);
  }
  return 0;
}

static uint64_t fnv1a(const uint8_t *b, size_t n) {
  uint64_t h = 0xcbf29ce484222325ULL;
  for (size_t i = 0; i < n; ++i) {
    h ^= b[i];
    h *= 0x100000001b3ULL;
  }
  return h;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  if (size < 1 || size > MAX_INPUT) return -1;
  int fix = data[0] & 1;
  ++data;
  --size;
  uint8_t *file = malloc(size ? size : 1);
  if (!file) return 0;
  if (size) memcpy(file, data, size);
  if (fix && size >= HEADER) {
    uint64_t payload = size - HEADER, hash = fnv1a(file + HEADER, size - HEADER);
    memcpy(file + 16, &payload, 8);
    memcpy(file + 24, &hash, 8);
  }
  const char *path = fuzz_file(0, file, size);
  free(file);
  adem_case *c = NULL;
  adem_error err;
  memset(&err, 0, sizeof err);
  adem_status st = adem_checkpoint_read(path, &c, &err);
  fuzz_check_status(st, &err, "adem_checkpoint_read");
  if (st && c) abort();
  if (!st && adem_world_particle_count(c->world) <= STEP_PARTICLES) {
    adem_world_set_threads(c->world, 1);
    st = adem_world_step(c->world, 2, &err);
    fuzz_check_status(st, &err, "adem_world_step after the checkpoint");
  }
  adem_case_free(c);
  return 0;
}
