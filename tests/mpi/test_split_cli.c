/* Claim: `mpirun -np N adem run CASE.yaml` writes what `adem run CASE.yaml` writes: the final
 * checkpoint holds the same particles, contacts and histories bit for bit (compared by id: the
 * storage orders differ), the CSV time series is the same text, for N = 2, 3 and 4; a
 * checkpoint written by one process count resumes under another to the serial run's end; and
 * what the split cannot run yet (a box periodic along all three axes) is refused with the
 * reason. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include <cmocka.h>

#include "adem/adem.h"
#include "cli_run.h"
#include "periodic_case.h"
#include "settle_case.h"
#include "split_compare.h"
#include "world.h"

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

static void test_mpirun_equals_serial(void **state) {
  (void)state;
  char *out;
  char *yaml = write_case("settle.yaml", settle_case);
  assert_int_equal(adem_np(0, &out, "run '%s' --out '%s/serial' --threads 1 --quiet", yaml, tmpdir), 0);
  adem_case *a = checkpoint("serial");
  char csv[512];
  snprintf(csv, sizeof csv, "%s/serial/timeseries.csv", tmpdir);
  char *ta = slurp(csv);
  for (int np = 2; np <= 4; ++np) {
    char dir[64];
    snprintf(dir, sizeof dir, "np%d", np);
    assert_int_equal(adem_np(np, &out, "run '%s' --out '%s/%s' --threads 1 --quiet", yaml, tmpdir, dir), 0);
    adem_case *b = checkpoint(dir);
    const char *why = split_compare(a->world, b->world);
    if (why) fail_msg("%d processes: %s differs from the serial run's checkpoint", np, why);
    snprintf(csv, sizeof csv, "%s/%s/timeseries.csv", tmpdir, dir);
    char *tb = slurp(csv);
    assert_string_equal(ta, tb);
    printf("# %d processes: the checkpoint's %zu particles and contacts and the CSV (%zu bytes) "
           "are the serial run's\n", np, b->world->p.n, strlen(tb));
    free(tb);
    adem_case_free(b);
  }
  free(ta);
  adem_case_free(a);
  free(yaml);
}

/* Half the run on 3 processes, the rest resumed from its checkpoint on 2. */
static void test_resume_other_count(void **state) {
  (void)state;
  char *out;
  char *yaml = write_case("settle.yaml", settle_case);
  assert_int_equal(adem_np(0, &out, "run '%s' --out '%s/whole' --threads 1 --quiet", yaml, tmpdir), 0);
  assert_int_equal(adem_np(3, &out, "run '%s' --out '%s/half' --set time.end=0.007 --threads 1 --quiet",
                           yaml, tmpdir), 0);
  assert_int_equal(adem_np(2, &out, "run --resume '%s/half' --set time.end=0.014 --threads 1 --quiet",
                           tmpdir), 0);
  adem_case *a = checkpoint("whole"), *b = checkpoint("half");
  const char *why = split_compare(a->world, b->world);
  if (why) fail_msg("resumed on another process count: %s differs", why);
  adem_case_free(a);
  adem_case_free(b);
  free(yaml);
}

static void test_refusals(void **state) {
  (void)state;
  char *out;
  /* the periodic bed periodic along z too, without its floor: no axis left to cut along */
  const char *walls = strstr(periodic_case, "walls:\n"), *domain = strstr(periodic_case, "domain:\n");
  char text[4096];
  snprintf(text, sizeof text, "%.*s%s", (int)(walls - periodic_case), periodic_case, domain);
  char *per = strstr(text, "periodic: [true, true, false]");
  assert_non_null(per);
  memcpy(per, "periodic: [true, true,  true]", 29);
  char *yaml = write_case("periodic.yaml", text);
  assert_int_equal(adem_np(2, &out, "run '%s' --out '%s/periodic' --quiet", yaml, tmpdir), 2);
  assert_non_null(strstr(out, "cannot run on more than one MPI process yet because of its periodic "
                              "axes (all three)"));
  free(yaml);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_mpirun_equals_serial),
      cmocka_unit_test(test_resume_other_count),
      cmocka_unit_test(test_refusals),
  };
  return cmocka_run_group_tests(tests, setup, tmpdir_teardown);
}
