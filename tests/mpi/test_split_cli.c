/* Claim: `mpirun -np N adem run CASE.yaml` writes what `adem run CASE.yaml` writes: the final
 * checkpoint holds the same particles, contacts and histories bit for bit (compared by id: the
 * storage orders differ), the CSV time series is the same text, for N = 2, 3 and 4 processes
 * of one thread and 2 of two threads; a
 * checkpoint written by one process count resumes under another to the serial run's end; and
 * the same holds for a box periodic along all three axes (slabs that meet across the faces). */
#define _POSIX_C_SOURCE 200809L /* setenv */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include <cmocka.h>

#include "adem/adem.h"
#include "case_file.h"
#include "cli_run.h"
#include "periodic_case.h"
#include "settle_case.h"
#include "split_compare.h"
#include "world_internal.h"

/* Runs `mpirun -np np adem ARGS` (np 0: plain `adem ARGS`), output captured in *out. */
static int adem_np(int np, char **out, const char *fmt, ...) {
  char args[4096];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(args, sizeof args, fmt, ap);
  va_end(ap);
  if (np == 0) return adem(out, "%s", args);
  char *log = path_in_tmp("mpi_output.txt");
  char cmd[8192];
  snprintf(cmd, sizeof cmd, "'%s' -np %d --oversubscribe '%s' %s > '%s' 2>&1 < /dev/null",
           ADEM_MPIEXEC, np, ADEM_BINARY, args, log);
  int status = system(cmd);
  assert_true(status != -1 && WIFEXITED(status));
  FILE *f = fopen(log, "r");
  assert_non_null(f);
  static char buf[1 << 16];
  size_t n = fread(buf, 1, sizeof buf - 1, f);
  buf[n] = '\0';
  fclose(f);
  free(log);
  *out = buf;
  printf("# mpirun -np %d adem %s -> %d\n", np, args, WEXITSTATUS(status));
  if (WEXITSTATUS(status) != 0) printf("# output:\n%s\n", buf);
  return WEXITSTATUS(status);
}

static char *slurp(const char *path) {
  FILE *f = fopen(path, "rb");
  assert_non_null(f);
  char *b = malloc(1 << 22);
  assert_non_null(b);
  size_t n = fread(b, 1, (1 << 22) - 1, f);
  b[n] = '\0';
  fclose(f);
  return b;
}

static adem_case *checkpoint(const char *dir) {
  char path[512];
  snprintf(path, sizeof path, "%s/%s/checkpoint", tmpdir, dir);
  adem_case *c = NULL;
  adem_error err;
  if (adem_checkpoint_read(path, &c, &err)) fail_msg("%s", err.message);
  return c;
}

static int setup(void **state) {
  (void)state;
  if (tmpdir_make("adem_split_cli")) return -1;
  return 0;
}

/* `mpirun -np 2/3/4 adem run` of the case `name` against `adem run`: the final checkpoint by id
 * and the CSV text. extra: more arguments for every run. */
static void runs_equal(const char *name, const char *text, const char *extra) {
  char *out;
  char file[128], serial[128];
  snprintf(file, sizeof file, "%s.yaml", name);
  snprintf(serial, sizeof serial, "%s-serial", name);
  char *yaml = write_case(file, text);
  assert_int_equal(adem_np(0, &out, "run '%s' --out '%s/%s' --threads 1 --quiet %s", yaml, tmpdir,
                           serial, extra),
                   0);
  adem_case *a = checkpoint(serial);
  char csv[512];
  snprintf(csv, sizeof csv, "%s/%s/timeseries.csv", tmpdir, serial);
  char *ta = slurp(csv);
  /* 2, 3, 4 processes of one thread, and 2 processes of 2 threads (threads that do not spin
   * while they wait: four on two cores) */
  setenv("OMP_WAIT_POLICY", "passive", 1);
  for (int np = 2; np <= 5; ++np) {
    int procs = np <= 4 ? np : 2, threads = np <= 4 ? 1 : 2;
    char dir[64];
    snprintf(dir, sizeof dir, "%s-np%dx%d", name, procs, threads);
    assert_int_equal(adem_np(procs, &out, "run '%s' --out '%s/%s' --threads %d --quiet %s", yaml,
                             tmpdir, dir, threads, extra),
                     0);
    adem_case *b = checkpoint(dir);
    const char *why = split_compare(a->world, b->world);
    if (why)
      fail_msg("%s, %d processes x %d threads: %s differs from the serial run's checkpoint", name,
               procs, threads, why);
    snprintf(csv, sizeof csv, "%s/%s/timeseries.csv", tmpdir, dir);
    char *tb = slurp(csv);
    assert_string_equal(ta, tb);
    printf("# %s, %d processes x %d threads: the checkpoint's %zu particles and contacts and the "
           "CSV (%zu bytes) are the serial run's\n",
           name, procs, threads, b->world->p.n, strlen(tb));
    free(tb);
    adem_case_free(b);
  }
  unsetenv("OMP_WAIT_POLICY");
  adem_case_free(a);
  free(ta);
  free(yaml);
}

static void test_mpirun_equals_serial(void **state) {
  (void)state;
  runs_equal("settle", settle_case, "");
}

/* Without the energy balance the pairs carry no balance records (pairs.h): the assembly and the
 * checkpoints without them. */
static void test_without_balance(void **state) {
  (void)state;
  runs_equal("settle-nobalance", settle_case, "--set output.energy_balance=false");
}

/* Half the run on 3 processes, the rest resumed from its checkpoint on 2. */
static void test_resume_other_count(void **state) {
  (void)state;
  char *out;
  char *yaml = write_case("settle.yaml", settle_case);
  assert_int_equal(adem_np(0, &out, "run '%s' --out '%s/whole' --threads 1 --quiet", yaml, tmpdir), 0);
  assert_int_equal(adem_np(3, &out, "run '%s' --out '%s/half' --set time.end=0.007 --threads 1 --quiet",
                           yaml, tmpdir),
                   0);
  assert_int_equal(adem_np(2, &out, "run --resume '%s/half' --set time.end=0.014 --threads 1 --quiet",
                           tmpdir),
                   0);
  adem_case *a = checkpoint("whole"), *b = checkpoint("half");
  const char *why = split_compare(a->world, b->world);
  if (why) fail_msg("resumed on another process count: %s differs", why);
  adem_case_free(a);
  adem_case_free(b);
  free(yaml);
}

/* A gas in a box periodic along x, y and z: two sets of 150 spheres thrown against each other,
 * no walls, no gravity; 2000 steps with contacts all along (up to 36 at once, with tangential
 * and rolling history). The slabs are cut along z, the longest axis, and the first and the last
 * meet across its faces. */
#define periodic_gas case_file_text("mpi-periodic-gas") /* tests/cases/mpi-periodic-gas.yaml */

static void test_triply_periodic(void **state) {
  (void)state;
  runs_equal("periodic-gas", periodic_gas, "");
  /* the control: slabs along z as if it did not wrap (no copies across its faces) */
  char *out;
  char *yaml = write_case("periodic-gas.yaml", periodic_gas);
  setenv("ADEM_SPLIT_BREAK", "periodic_axis", 1);
  int rc = adem_np(2, &out, "run '%s' --out '%s/gas-control' --threads 1 --quiet", yaml, tmpdir);
  unsetenv("ADEM_SPLIT_BREAK");
  const char *why = "the run failed";
  if (rc == 0) {
    adem_case *a = checkpoint("periodic-gas-serial"), *b = checkpoint("gas-control");
    why = split_compare(a->world, b->world);
    adem_case_free(a);
    adem_case_free(b);
  }
  if (!why) fail_msg("the control without copies across the periodic faces ran like the serial run");
  printf("# control without copies across the periodic faces: %s (exit %d)\n", why, rc);
  free(yaml);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_mpirun_equals_serial),
      cmocka_unit_test(test_without_balance),
      cmocka_unit_test(test_resume_other_count),
      cmocka_unit_test(test_triply_periodic),
  };
  return cmocka_run_group_tests(tests, setup, tmpdir_teardown);
}
