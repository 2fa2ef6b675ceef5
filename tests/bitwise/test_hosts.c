/* Claim: a run gives the same bits on every x86-64 host, whatever glibc picks for it. glibc
 * dispatches exp, log, pow, sin, cos, tan, log1p ... to FMA variants on CPUs that have FMA, and
 * those differ from the SSE2 ones in the last bit. Masking the CPU's FMA and AVX2 through
 * GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA,-AVX512F makes this host behave as one without them:
 * each case runs twice in a child process, with and without the mask, and the state hashes must be
 * equal. The test first proves the mask works (a hash of libm results changes under it); on a host
 * without FMA, or a libc that ignores the tunable, it is skipped.
 *
 * The cases reach every transcendental function of a run: a bed of JKR spheres with log-normal
 * radii (Box-Muller's log and cos, exp), reduced stiffness (gamma_mod = gamma f^(2/5)), DTK
 * rolling (a0 per contact), damping (beta = ln e / ...) and the automatic step (t_c ~ x^(1/5));
 * and a drum: a mesh box turning about a horizontal axis (cos and sin of the angle at every step)
 * with normal radii and model C rolling. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "adem/adem.h"
#include "case_file.h"
#include "tmpdir.h"

#define BED_STEPS 1000
#define DRUM_STEPS 20000
#define HOSTS_MASK "glibc.cpu.hwcaps=-AVX2,-FMA,-AVX512F"

/* The cases: tests/cases/hosts-bed.yaml and hosts-drum.yaml. */

static uint64_t fnv(uint64_t h, const void *data, size_t n) {
  const unsigned char *c = data;
  for (size_t k = 0; k < n; ++k) h = (h ^ c[k]) * 1099511628211ull;
  return h;
}

/* FNV-1a of the results of the libm functions that glibc dispatches by CPU. */
static uint64_t libm_hash(void) {
  uint64_t h = 1469598103934665603ull, s = 1;
  for (int i = 0; i < 20000; ++i) {
    s = s * 6364136223846793005ull + 1442695040888963407ull;
    double u = (double)(s >> 11) * 0x1p-53, x = 0.001 + 100.0 * u;
    double r[6] = {sin(x), cos(x), pow(x, 0.4), log(x), exp(10.0 * u - 5.0), log1p(u)};
    h = fnv(h, r, sizeof r);
  }
  return h;
}

/* FNV-1a of the positions, velocities and spins after STEPS steps of the case (as bench_bed's). */
static uint64_t state_hash(const char *name, uint64_t steps, size_t *n_out) {
  adem_case *c = NULL;
  adem_error err;
  if (adem_case_load_file(case_file_path(name), NULL, 0, &c, &err)) {
    fprintf(stderr, "case does not load: %s\n", err.message);
    exit(2);
  }
  if (adem_world_prepare(c->world, &err) || adem_world_step(c->world, steps, &err)) {
    fprintf(stderr, "run: %s\n", err.message);
    exit(3);
  }
  size_t n = adem_world_particle_count(c->world);
  double *buf = malloc(3 * n * sizeof *buf + 1);
  uint64_t h = 1469598103934665603ull;
  adem_particle_field fields[] = {ADEM_FIELD_POSITION, ADEM_FIELD_VELOCITY,
                                  ADEM_FIELD_ANGULAR_VELOCITY};
  for (int f = 0; f < 3; ++f) {
    if (!buf || adem_world_get_particles(c->world, fields[f], buf, 3 * n, &err)) exit(4);
    h = fnv(h, buf, 3 * n * sizeof *buf);
  }
  free(buf);
  *n_out = n;
  adem_case_free(c);
  return h;
}

/* In the child: prints "libm HASH" or "state HASH N" for what argv asks, nothing else. */
static int child(const char *what) {
  size_t n = 0;
  uint64_t h;
  if (!strcmp(what, "libm"))
    h = libm_hash();
  else if (!strcmp(what, "bed"))
    h = state_hash("hosts-bed", BED_STEPS, &n);
  else if (!strcmp(what, "drum"))
    h = state_hash("hosts-drum", DRUM_STEPS, &n);
  else
    return 2;
  printf("%016llx %zu\n", (unsigned long long)h, n);
  return 0;
}

static const char *self_path;

/* Runs this program as `self --child WHAT` with GLIBC_TUNABLES set to MASK (NULL: unset) and
 * returns the hash it prints. */
static uint64_t run_child(const char *what, const char *mask, size_t *n) {
  char cmd[1024];
  snprintf(cmd, sizeof cmd, "%s%s%s '%s' --child %s --dir '%s'", mask ? "GLIBC_TUNABLES=" : "",
           mask ? mask : "", mask ? "" : "env -u GLIBC_TUNABLES", self_path, what, tmpdir);
  FILE *p = popen(cmd, "r");
  assert_non_null(p);
  unsigned long long h = 0;
  int got = fscanf(p, "%llx %zu", &h, n);
  int status = pclose(p);
  if (got != 2 || status != 0) fail_msg("`%s` failed (status %d)", cmd, status);
  return (uint64_t)h;
}

static int mask_works(void) {
  size_t n;
  uint64_t plain = run_child("libm", NULL, &n), masked = run_child("libm", HOSTS_MASK, &n);
  printf("# libm hash %016llx, with %s %016llx\n", (unsigned long long)plain, HOSTS_MASK,
         (unsigned long long)masked);
  return plain != masked;
}

static void same_with_and_without_mask(const char *what) {
  if (!mask_works()) {
    printf("# the mask changes no libm result on this host (no FMA, or the tunable is ignored)\n");
    skip();
  }
  size_t n1 = 0, n2 = 0;
  uint64_t plain = run_child(what, NULL, &n1), masked = run_child(what, HOSTS_MASK, &n2);
  printf("# %s: %zu particles, state hash %016llx; with the mask %zu particles, %016llx\n", what,
         n1, (unsigned long long)plain, n2, (unsigned long long)masked);
  assert_true(n1 > 100);
  assert_int_equal(n1, n2);
  assert_true(plain == masked);
}

static void test_bed_same_bits_without_fma(void **state) {
  (void)state;
  same_with_and_without_mask("bed");
}

static void test_drum_same_bits_without_fma(void **state) {
  (void)state;
  same_with_and_without_mask("drum");
}

static int setup(void **state) {
  (void)state;
  return tmpdir_make("adem_hosts");
}

int main(int argc, char **argv) {
  if (argc == 5 && !strcmp(argv[1], "--child") && !strcmp(argv[3], "--dir")) {
    snprintf(tmpdir, sizeof tmpdir, "%s", argv[4]);
    return child(argv[2]);
  }
  self_path = argv[0];
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_bed_same_bits_without_fma),
      cmocka_unit_test(test_drum_same_bits_without_fma),
  };
  return cmocka_run_group_tests(tests, setup, tmpdir_teardown);
}
