/* Fuzz target: what a resumed run reads back from its output folder, the PVD collection (frame
 * times) and the CSV time series (rows kept up to the checkpoint's time), through
 * adem_output_open(resume = true) as adem_run calls it.
 * Input: byte 0: frames already written (low 6 bits) and, in bit 7, "no PVD file"; byte 1: the
 * checkpoint time in ms; then the PVD text, a NUL byte, and the CSV text (no NUL: no CSV file).
 * After opening, the PVD must list exactly the frames already written and the CSV must be the
 * header followed by whole rows with times up to the checkpoint's. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "adem/adem.h"
#include "adem/files.h"
#include "fuzz_common.h"
#include "output.h"
#include "world_internal.h"

enum { MAX_INPUT = 256 * 1024 };

static adem_case *fuzz_case;
static char *pvd_path, *csv_path, *dir;
static const uint64_t track_ids[1] = {1};

/* Two spheres in a box (six named planes: their force columns) with one tracked particle. */
static const char *const case_text =
    "name: resume\n"
    "materials:\n"
    "  - {name: glass, density: 2500, youngs_modulus: 5e6, poisson_ratio: 0.25, restitution: 0.5,"
    " friction: 0.3}\n"
    "particles:\n"
    "  - type: list\n"
    "    material: glass\n"
    "    spheres:\n"
    "      - {position: [0.01, 0.01, 0.01], radius: 0.001}\n"
    "      - {position: [0.01, 0.01, 0.02], radius: 0.001}\n"
    "walls:\n"
    "  - {type: box, name: box, min: [0, 0, 0], max: [0.02, 0.02, 0.04], material: glass}\n"
    "time: {end: 0.01, step: 1e-5}\n";

static void remove_scratch(void) {
  if (!dir) return;
  unlink(pvd_path);
  unlink(csv_path);
  char *frames = adem_file_join(dir, "frames");
  if (frames) rmdir(frames);
  free(frames);
  rmdir(dir);
}

/* Seeds: the PVD and CSV of this case run for 10 frames and 20 rows (and damaged variants: a
 * cut last row, a missing PVD, a foreign header), resumed at several times. Written when
 * ADEM_FUZZ_SEEDS names a folder; the process then exits. */
static void write_seeds(const char *folder) {
  adem_output_track track = {1, track_ids};
  adem_world *w = fuzz_case->world;
  adem_error err;
  if (adem_world_prepare(w, &err)) abort();
  char *csv = adem_output_csv_header(w, &track, NULL);
  size_t csv_len = strlen(csv);
  char pvd[8192];
  int pvd_len = snprintf(pvd, sizeof pvd,
                         "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\" "
                         "byte_order=\"LittleEndian\">\n  <Collection>\n");
  for (int k = 0; k < 20; ++k) {
    if (k > 0 && adem_world_step(w, 100, &err)) abort();
    char *row = adem_output_csv_row(w, &track, NULL);
    csv = realloc(csv, csv_len + strlen(row) + 1);
    memcpy(csv + csv_len, row, strlen(row) + 1);
    csv_len += strlen(row);
    free(row);
    if (k % 2 == 0)
      pvd_len += snprintf(pvd + pvd_len, sizeof pvd - (size_t)pvd_len,
                          "    <DataSet timestep=\"%.17g\" group=\"\" part=\"0\" "
                          "file=\"frames/particles_%06d.vtu\"/>\n",
                          w->time, k / 2);
  }
  pvd_len += snprintf(pvd + pvd_len, sizeof pvd - (size_t)pvd_len, "  </Collection>\n</VTKFile>\n");
  const struct {
    const char *name;
    unsigned char frames, t_ms;
    size_t csv_cut; /* bytes cut from the CSV's end */
    int foreign;    /* another header */
  } seeds[] = {{"all", 10, 19, 0, 0}, {"middle", 5, 9, 0, 0}, {"cut_row", 10, 19, 7, 0}, {"no_pvd", 128 | 4, 8, 0, 0}, {"foreign", 3, 5, 0, 1}, {"start", 1, 0, 0, 0}};
  for (size_t k = 0; k < sizeof seeds / sizeof seeds[0]; ++k) {
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", folder, seeds[k].name);
    FILE *f = fopen(path, "wb");
    if (!f) abort();
    fputc(seeds[k].frames, f);
    fputc(seeds[k].t_ms, f);
    fwrite(pvd, 1, (size_t)pvd_len, f);
    fputc(0, f);
    if (seeds[k].foreign) fputs("time_s,other\n", f);
    fwrite(csv, 1, csv_len - seeds[k].csv_cut, f);
    if (fclose(f) != 0) abort();
  }
  free(csv);
}

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc;
  (void)argv;
  fuzz_quiet();
  adem_error err;
  if (adem_case_load_string(case_text, "resume.yaml", NULL, 0, &fuzz_case, &err)) {
    fprintf(stderr, "fuzz_resume: the built-in case does not load: %s\n", err.message);
    abort();
  }
  const char *seeds = getenv("ADEM_FUZZ_SEEDS");
  if (seeds) {
    write_seeds(seeds);
    adem_case_free(fuzz_case);
    exit(0);
  }
  dir = strdup(fuzz_scratch_dir());
  pvd_path = adem_file_join(dir, "particles.pvd");
  csv_path = adem_file_join(dir, "timeseries.csv");
  if (!dir || !pvd_path || !csv_path) abort();
  atexit(remove_scratch);
  return 0;
}

static void put_file(const char *path, const uint8_t *data, size_t n, int present) {
  unlink(path);
  if (!present) return;
  FILE *f = fopen(path, "wb");
  if (!f || (n && fwrite(data, 1, n, f) != n) || fclose(f) != 0) abort();
}

static void check_pvd(size_t frames_done) {
  char *text = NULL;
  size_t len = 0;
  adem_error err;
  if (adem_file_read_all(pvd_path, &text, &len, &err)) abort();
  size_t n = 0;
  for (const char *p = text; (p = strstr(p, "<DataSet ")); ++p) ++n;
  if (n != frames_done || !strstr(text, "</VTKFile>\n")) {
    fprintf(stderr, "resumed PVD lists %zu frames, not %zu\n", n, frames_done);
    abort();
  }
  free(text);
}

static void check_csv(const char *header, double t_resume) {
  char *text = NULL;
  size_t len = 0;
  adem_error err;
  if (adem_file_read_all(csv_path, &text, &len, &err)) abort();
  if (strncmp(text, header, strlen(header)) != 0 || (len > 0 && text[len - 1] != '\n') ||
      strlen(text) != len) {
    fprintf(stderr, "resumed CSV does not start with the header or ends inside a row\n");
    abort();
  }
  for (const char *row = text + strlen(header); *row;) {
    char *end;
    double t = strtod(row, &end);
    if (end == row || !(t <= t_resume)) {
      fprintf(stderr, "resumed CSV keeps a row past t = %g\n", t_resume);
      abort();
    }
    row = strchr(row, '\n') + 1;
  }
  free(text);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  if (size < 2 || size > MAX_INPUT) return -1;
  size_t frames_done = data[0] & 63u;
  int have_pvd = !(data[0] & 128u);
  double t_resume = 1e-3 * data[1];
  data += 2;
  size -= 2;
  const uint8_t *nul = memchr(data, 0, size);
  size_t pvd_len = nul ? (size_t)(nul - data) : size;
  put_file(pvd_path, data, pvd_len, have_pvd);
  put_file(csv_path, nul ? nul + 1 : NULL, nul ? size - pvd_len - 1 : 0, nul != NULL);

  adem_output_track track = {1, track_ids};
  adem_output out;
  adem_error err;
  memset(&err, 0, sizeof err);
  adem_status st = adem_output_open(&out, dir, fuzz_case->world, true, true, true, frames_done,
                                    1e-3, t_resume, false, &track, NULL, &err);
  fuzz_check_status(st, &err, "adem_output_open (resume)");
  if (st) return 0;
  adem_output_close(&out);
  check_pvd(frames_done);
  char *header = adem_output_csv_header(fuzz_case->world, &track, NULL);
  if (!header) abort();
  check_csv(header, t_resume);
  free(header);
  return 0;
}
