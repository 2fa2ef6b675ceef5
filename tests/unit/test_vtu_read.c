/* Reader of particle frames (src/output/vtu_read.c): a frame the engine wrote reads back with the
 * case's centres, radii and ids and the frame's time; every malformed variant of it (truncated at
 * any byte, a header attribute changed, a block size or offset wrong, a non-finite value) is
 * refused with ADEM_ERR_INPUT and a message, never read past its end. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "case_file.h"
#include "cli_run.h"
#include "adem/frames.h"

enum { NS = 7 };
static const double X[NS][4] = {/* x, y, z, radius */
                                {0.00, 0.0, 0.05, 0.010},
                                {0.03, 0.01, 0.05, 0.012},
                                {-0.03, 0.0, 0.06, 0.011},
                                {0.0, 0.04, 0.05, 0.0105},
                                {0.0, -0.04, 0.07, 0.009},
                                {0.05, 0.05, 0.02, 0.0101},
                                {-0.05, -0.05, 0.03, 0.008}};

static unsigned char *frame0; /* the bytes of frames/particles_000000.vtu */
static size_t frame0_len;

static int setup(void **state) {
  (void)state;
  if (tmpdir_make("adem_vturead")) return -1;
  char spheres[4096] = "particles.0.spheres=[";
  for (int i = 0; i < NS; ++i) {
    size_t k = strlen(spheres);
    snprintf(spheres + k, sizeof spheres - k, "%s{position: [%.17g, %.17g, %.17g], radius: %.17g}",
             i ? ", " : "", X[i][0], X[i][1], X[i][2], X[i][3]);
  }
  strncat(spheres, "]", sizeof spheres - strlen(spheres) - 1);
  char *out;
  int rc = adem(&out, "run '%s' --set '%s' --out '%s/out' --threads 1 --quiet",
                case_file_path("vtu-read"), spheres, tmpdir);
  if (rc) return -1;
  char *p = path_in_tmp("out/frames/particles_000000.vtu");
  FILE *f = fopen(p, "rb");
  free(p);
  if (!f) return -1;
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  fseek(f, 0, SEEK_SET);
  frame0 = malloc((size_t)n);
  frame0_len = fread(frame0, 1, (size_t)n, f);
  fclose(f);
  return frame0_len == (size_t)n ? 0 : -1;
}

static int teardown(void **state) {
  free(frame0);
  return tmpdir_teardown(state);
}

/* Claim: the first frame gives back the case's centres and radii bit for bit, ids 0..n-1 in the
 * order of the list, time 0 and step 0; a later frame (read from its file) has the same count,
 * a later time and centres that moved (the spheres fall). */
static void test_reads_engine_frame(void **state) {
  (void)state;
  adem_vtu_frame f;
  adem_error err = {0};
  assert_int_equal(adem_vtu_read_memory(frame0, frame0_len, "frame0", &f, &err), ADEM_OK);
  assert_int_equal(f.n, NS);
  assert_non_null(f.id);
  for (int i = 0; i < NS; ++i) {
    assert_true(f.id[i] >= 0 && f.id[i] < NS);
    int64_t j = f.id[i]; /* the engine may store particles in another order; ids say which */
    assert_true(f.pos[i].x == X[j][0] && f.pos[i].y == X[j][1] && f.pos[i].z == X[j][2]);
    assert_true(f.radius[i] == X[j][3]);
  }
  assert_true(f.time == 0.0 && f.step == 0);
  adem_vtu_frame_free(&f);

  char *p = path_in_tmp("out/frames/particles_000002.vtu");
  assert_int_equal(adem_vtu_read_file(p, &f, &err), ADEM_OK);
  free(p);
  assert_int_equal(f.n, NS);
  assert_true(fabs(f.time - 0.002) < 1e-4 && f.step > 0); /* the step nearest 2 ms */
  double zsum = 0.0;
  for (int i = 0; i < NS; ++i) zsum += f.pos[i].z;
  double z0 = 0.0;
  for (int i = 0; i < NS; ++i) z0 += X[i][2];
  assert_true(zsum < z0); /* g t^2 / 2 = 2e-5 m each */
  adem_vtu_frame_free(&f);
}

/* Reads a modified copy: FROM replaced by TO (same or other length) at its first occurrence. */
static adem_status read_edited(const char *from, const char *to, adem_error *err) {
  const char *hit = NULL;
  size_t nf = strlen(from), nt = strlen(to);
  for (size_t i = 0; i + nf <= frame0_len && !hit; ++i)
    if (!memcmp(frame0 + i, from, nf)) hit = (const char *)frame0 + i;
  assert_non_null(hit);
  size_t at = (size_t)(hit - (const char *)frame0);
  size_t len = frame0_len - nf + nt;
  unsigned char *b = malloc(len);
  assert_non_null(b);
  memcpy(b, frame0, at);
  memcpy(b + at, to, nt);
  memcpy(b + at + nt, frame0 + at + nf, frame0_len - at - nf);
  adem_vtu_frame f;
  adem_status st = adem_vtu_read_memory(b, len, "edited", &f, err);
  if (st == ADEM_OK) adem_vtu_frame_free(&f);
  else printf("# %s -> %s: %s\n", from, to, err->message);
  free(b);
  return st;
}

/* Claim: header changes that make the file something else are refused with a message. Offsets
 * change length with the text, so each edit keeps the header's byte count where the appended
 * offsets matter (they count from the '_' marker, so the header may change length). */
static void test_header_errors(void **state) {
  (void)state;
  adem_error err = {0};
  assert_int_equal(read_edited("byte_order=\"LittleEndian\"", "byte_order=\"BigEndian\"", &err),
                   ADEM_ERR_INPUT);
  assert_int_equal(read_edited("header_type=\"UInt64\"", "header_type=\"UInt32\"", &err),
                   ADEM_ERR_INPUT);
  assert_int_equal(read_edited("type=\"UnstructuredGrid\"", "type=\"PolyData\"", &err),
                   ADEM_ERR_INPUT);
  assert_int_equal(read_edited("NumberOfPoints=\"7\"", "NumberOfPoints=\"8\"", &err),
                   ADEM_ERR_INPUT);
  assert_int_equal(read_edited("NumberOfPoints=\"7\"", "NumberOfPoints=\"99999999999999999999\"",
                               &err),
                   ADEM_ERR_INPUT);
  assert_int_equal(read_edited("NumberOfPoints=\"7\"", "NumberOfPoints=\"-7\"", &err),
                   ADEM_ERR_INPUT);
  assert_int_equal(read_edited("Name=\"radius\"", "Name=\"radiux\"", &err), ADEM_ERR_INPUT);
  assert_int_equal(read_edited("Name=\"position\" NumberOfComponents=\"3\"",
                               "Name=\"position\" NumberOfComponents=\"2\"", &err),
                   ADEM_ERR_INPUT);
  assert_int_equal(read_edited("type=\"Float64\" Name=\"radius\"", "type=\"Float32\" Name=\"radius\"",
                               &err),
                   ADEM_ERR_INPUT);
  assert_int_equal(read_edited("Name=\"radius\" format=\"appended\" offset=\"0\"",
                               "Name=\"radius\" format=\"appended\" offset=\"9\"", &err),
                   ADEM_ERR_INPUT); /* a block size read from the middle of the data */
  assert_int_equal(read_edited("Name=\"radius\" format=\"appended\" offset=\"0\"",
                               "Name=\"radius\" format=\"appended\" offset=\"18446744073709551615\"",
                               &err),
                   ADEM_ERR_INPUT);
  assert_int_equal(read_edited("Name=\"radius\" format=\"appended\" offset=\"0\"",
                               "Name=\"radius\" format=\"appended\" offset=0", &err),
                   ADEM_ERR_INPUT); /* unquoted attribute */
  assert_int_equal(read_edited("encoding=\"raw\"", "encoding=\"base64\"", &err), ADEM_ERR_INPUT);
  assert_int_equal(read_edited("<AppendedData", "<AppendedDatum", &err), ADEM_ERR_INPUT);
  assert_int_equal(read_edited("   _", "    ", &err), ADEM_ERR_INPUT);
  assert_int_equal(read_edited(">0</DataArray>", ">nan</DataArray>", &err), ADEM_ERR_INPUT);
  /* a comment and extra blanks are still a frame */
  assert_int_equal(read_edited("<UnstructuredGrid>", "<!-- c --> <UnstructuredGrid >", &err),
                   ADEM_OK);
}

/* Claim: a file cut at any byte, or an empty one, is refused (never read past its end), and so
 * are a block size that does not match the points and non-finite or non-positive values. */
static void test_truncated_and_bad_data(void **state) {
  (void)state;
  adem_error err = {0};
  adem_vtu_frame f;
  for (size_t len = 0; len < frame0_len - 12; ++len) { /* up to "</AppendedData>" */
    unsigned char *b = malloc(len ? len : 1);
    assert_non_null(b);
    memcpy(b, frame0, len);
    adem_status st = adem_vtu_read_memory(b, len, "cut", &f, &err);
    free(b);
    if (st != ADEM_ERR_INPUT) fail_msg("cut at %zu of %zu bytes: status %d", len, frame0_len, st);
    assert_null(f.pos);
  }
  /* the data section: the radius block's size, then its first value */
  const unsigned char *u = (const unsigned char *)strstr((const char *)frame0, "   _") + 4;
  size_t data = (size_t)(u - frame0);
  unsigned char *b = malloc(frame0_len);
  assert_non_null(b);
  uint64_t sz;
  memcpy(b, frame0, frame0_len);
  memcpy(&sz, b + data, 8);
  assert_int_equal(sz, 8 * NS);
  sz = 8 * NS - 8;
  memcpy(b + data, &sz, 8);
  assert_int_equal(adem_vtu_read_memory(b, frame0_len, "size", &f, &err), ADEM_ERR_INPUT);
  printf("# %s\n", err.message);
  const double bad[3] = {NAN, -0.01, 0.0};
  for (int k = 0; k < 3; ++k) {
    memcpy(b, frame0, frame0_len);
    memcpy(b + data + 8 + 8 * 3, &bad[k], 8); /* radius of the fourth particle */
    assert_int_equal(adem_vtu_read_memory(b, frame0_len, "value", &f, &err), ADEM_ERR_INPUT);
    printf("# %s\n", err.message);
  }
  free(b);
  assert_int_equal(adem_vtu_read_file("/nonexistent/particles.vtu", &f, &err), ADEM_ERR_INPUT);
  printf("# %s\n", err.message);
}

/* Claim: random byte flips anywhere in the file either give a frame of 7 particles or a refusal;
 * nothing else (a crash, a read past the end under a sanitizer) happens. A cheap fuzz pass. */
static void test_byte_flips(void **state) {
  (void)state;
  uint64_t s = 12345;
  unsigned char *b = malloc(frame0_len);
  assert_non_null(b);
  int refused = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    memcpy(b, frame0, frame0_len);
    for (int k = 0; k < 3; ++k) {
      s = s * 6364136223846793005ULL + 1442695040888963407ULL;
      size_t at = (size_t)(s >> 33) % frame0_len;
      b[at] ^= (unsigned char)(1u << ((s >> 20) & 7));
    }
    adem_vtu_frame f;
    adem_error err = {0};
    adem_status st = adem_vtu_read_memory(b, frame0_len, "flip", &f, &err);
    if (st == ADEM_OK) {
      assert_int_equal(f.n, NS);
      adem_vtu_frame_free(&f);
    } else {
      assert_int_equal(st, ADEM_ERR_INPUT);
      assert_true(err.message[0] != '\0');
      ++refused;
    }
  }
  printf("# %d of 4000 flipped files refused\n", refused);
  free(b);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_reads_engine_frame),
      cmocka_unit_test(test_header_errors),
      cmocka_unit_test(test_truncated_and_bad_data),
      cmocka_unit_test(test_byte_flips),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
