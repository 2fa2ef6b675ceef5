/* For the restart tests: a run through adem_run stopped after every chunk and resumed from its
 * checkpoint each time, and byte comparison of the output files two runs wrote below tmpdir.
 * Include after cmocka.h. */
#ifndef ADEM_TEST_RESTART_RUN_H
#define ADEM_TEST_RESTART_RUN_H

#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "adem/adem.h"
#include "adem/files.h"
#include "tmpdir.h"

/* Runs C with OPT and the stop flag always set, reading C->output.dir/checkpoint back after every
 * stop, to the end; returns the finished case (C itself is freed) and the stops in *STOPS. */
static inline adem_case *run_stopped_everywhere(adem_case *c, adem_run_options opt, int *stops) {
  volatile sig_atomic_t stop = 1;
  opt.stop_flag = &stop;
  char ckpt[sizeof c->output.dir + sizeof "/checkpoint"];
  snprintf(ckpt, sizeof ckpt, "%s/checkpoint", c->output.dir);
  adem_error err;
  *stops = 0;
  for (;;) {
    adem_status st = adem_run(c, &opt, &err);
    if (st == ADEM_OK) break;
    if (st != ADEM_INTERRUPTED) fail_msg("%s", err.message);
    ++*stops;
    adem_case_free(c);
    c = NULL;
    if (adem_checkpoint_read(ckpt, &c, &err)) fail_msg("%s", err.message);
  }
  return c;
}

/* Fails with "NAME differs after AFTER" unless tmpdir/DIR_A/NAME and tmpdir/DIR_B/NAME have the
 * same bytes, for each NAME of the NULL-terminated NAMES. */
static inline void assert_same_files(const char *dir_a, const char *dir_b, const char *const *names,
                                     const char *after) {
  for (; *names; ++names) {
    char pa[512], pb[512];
    snprintf(pa, sizeof pa, "%s/%s/%s", tmpdir, dir_a, *names);
    snprintf(pb, sizeof pb, "%s/%s/%s", tmpdir, dir_b, *names);
    char *a, *b;
    size_t na, nb;
    adem_error err;
    if (adem_file_read_all(pa, &a, &na, &err)) fail_msg("%s", err.message);
    if (adem_file_read_all(pb, &b, &nb, &err)) fail_msg("%s", err.message);
    if (na != nb || memcmp(a, b, na) != 0) fail_msg("%s differs after %s", *names, after);
    free(a);
    free(b);
  }
}

#endif
