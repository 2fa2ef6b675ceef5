/* Contact frames (output.contacts, src/output/contact_frames.c): written with the particle frames
 * as frames/contacts_NNNNNN.vtp in contacts.pvd (and .csv), they hold every touching contact of
 * the time series' count; they read back (adem_contact_frame_read_file) with the pair's line
 * from centre to centre and a wall's to its contact point; a run stopped and resumed writes the
 * same contact frames and contacts.pvd, byte for byte, as one that never stopped (perturbed: with
 * the resumed run not reading back the earlier contacts.pvd, the two contacts.pvd differ). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "case_file.h"
#include "cli_run.h"
#include "adem/frames.h"

#define case_text case_file_text("contact-frames") /* tests/cases/contact-frames.yaml */

static int setup(void **state) {
  (void)state;
  return tmpdir_make("adem_contactframes");
}

static char *slurp(const char *path, size_t *n) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  fseek(f, 0, SEEK_END);
  long len = ftell(f);
  fseek(f, 0, SEEK_SET);
  char *b = malloc((size_t)len + 1);
  assert_non_null(b);
  assert_int_equal(fread(b, 1, (size_t)len, f), (size_t)len);
  b[len] = '\0';
  fclose(f);
  *n = (size_t)len;
  return b;
}

static void same_file(const char *a, const char *b) {
  size_t na, nb;
  char *x = slurp(a, &na), *y = slurp(b, &nb);
  if (!x || !y) fail_msg("missing %s or %s", a, b);
  if (na != nb || memcmp(x, y, na)) fail_msg("%s and %s differ", a, b);
  free(x);
  free(y);
}

static void test_contact_frames(void **state) {
  (void)state;
  char *path = write_case("contacts.yaml", case_text), *out;
  char one[600], two[600];
  snprintf(one, sizeof one, "%s/one", tmpdir);
  snprintf(two, sizeof two, "%s/two", tmpdir);
  assert_int_equal(adem(&out, "run %s --out %s --threads 1", path, one), 0);
  /* the same run stopped at 0.02 s and resumed to its end */
  assert_int_equal(adem(&out, "run %s --out %s --threads 2 --set time.end=0.02", path, two), 0);
  assert_int_equal(adem(&out, "run --resume %s --set time.end=0.04 --threads 1", two), 0);
  for (int k = 0; k <= 4; ++k) {
    char a[700], b[700];
    snprintf(a, sizeof a, "%s/frames/contacts_%06d.vtp", one, k);
    snprintf(b, sizeof b, "%s/frames/contacts_%06d.vtp", two, k);
    same_file(a, b);
    snprintf(a, sizeof a, "%s/frames/contacts_%06d.csv", one, k);
    snprintf(b, sizeof b, "%s/frames/contacts_%06d.csv", two, k);
    same_file(a, b);
  }
  char a[700], b[700];
  snprintf(a, sizeof a, "%s/contacts.pvd", one);
  snprintf(b, sizeof b, "%s/contacts.pvd", two);
  same_file(a, b);
  size_t n;
  char *pvd = slurp(a, &n);
  int entries = 0;
  for (char *p = pvd; (p = strstr(p, "<DataSet")); ++p) entries++;
  assert_int_equal(entries, 5);
  free(pvd);

  /* the last frame: every touching contact of the time series, lines as described */
  snprintf(a, sizeof a, "%s/frames/contacts_000004.vtp", one);
  adem_contact_frame cf;
  adem_error err;
  memset(&err, 0, sizeof err);
  if (adem_contact_frame_read_file(a, &cf, &err)) fail_msg("%s", err.message);
  snprintf(b, sizeof b, "%s/timeseries.csv", one);
  int pp = (int)csv_value(b, 5, "contacts_pp"), pw = (int)csv_value(b, 5, "contacts_pw");
  size_t npair = 0, nwall = 0;
  for (size_t k = 0; k < cf.n; ++k) {
    double len = sqrt(pow(cf.p1[k].x - cf.p0[k].x, 2) + pow(cf.p1[k].y - cf.p0[k].y, 2) +
                      pow(cf.p1[k].z - cf.p0[k].z, 2));
    if (cf.kind[k] == 0) {
      npair++;
      assert_true(cf.id_a[k] < cf.id_b[k]);
      assert_true(len > 0.0016 * 0.9 && len < 0.0024); /* two radii, less the overlap */
    } else {
      nwall++;
      assert_int_equal(cf.kind[k], 1);
      assert_true(len > 0.0007 && len < 0.0012); /* a radius less the overlap */
      /* the contact point is on a face of the box */
      double x[3] = {cf.p1[k].x, cf.p1[k].y, cf.p1[k].z};
      int on = 0;
      for (int u = 0; u < 3; ++u) on |= fabs(x[u]) < 1e-12 || fabs(x[u] - (u == 2 ? 0.04 : 0.01)) < 1e-12;
      assert_true(on);
    }
  }
  printf("last frame: %zu particle contacts (time series %d), %zu wall contacts (%d)\n", npair, pp,
         nwall, pw);
  assert_int_equal((int)npair, pp);
  assert_int_equal((int)nwall, pw);
  assert_true(npair > 30 && nwall > 10);
  adem_contact_frame_free(&cf);
  free(path);
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_contact_frames)};
  return cmocka_run_group_tests(tests, setup, tmpdir_teardown);
}
