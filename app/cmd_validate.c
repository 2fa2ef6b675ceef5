/* adem validate */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "adem/studies.h"
#include "adem/world.h"
#include "adem/vec3.h"
#include "cli.h"

/* ---------------------------------------------------------------- validate */

const char *const validate_help =
    "Usage:\n"
    "  adem validate [NAME ...] [--out DIR] [--threads N] [--quick]\n"
    "  adem validate --list\n"
    "\n"
    "Reproduces figures of the two source papers (all of them, or the NAMEs given) and checks\n"
    "each paper's claim. For each NAME it writes DIR/NAME.csv (the numbers, with a header\n"
    "naming quantity and unit) and DIR/NAME.png (gnuplot), and for the whole run\n"
    "DIR/summary.md and DIR/summary.json: the claim with its figure, what was measured, notes\n"
    "(parameters the paper omits, data that are not available) and pass/fail.\n"
    "\n"
    "Options:\n"
    "  --out DIR     output folder (default out/validate); created if missing\n"
    "  --threads N   threads (default: OMP_NUM_THREADS or all cores)\n"
    "  --quick       smaller versions (fewer points, coarser bisection), as the tests run them\n"
    "  --list        list the validations and exit\n"
    "  -h, --help    show this help\n"
    "\n"
    "Examples:\n"
    "  adem validate --list\n"
    "  adem validate haervig-fig5 haervig-fig13 --out out/v\n"
    "  adem validate --quick\n"
    "\n"
    "Exit status: 0 every claim holds; 3 at least one validation failed its claim or could not\n"
    "run (summary.md says which); 2 bad option or unknown name; 4 a file could not be written.\n";

int cmd_validate(int argc, char **argv) {
  const char **names = calloc((size_t)argc + 1, sizeof *names);
  if (!names) return fail(EXIT_INTERNAL, "out of memory");
  int nnames = 0, threads = 0, list = 0, rc = EXIT_OK;
  adem_validation_context ctx = {"out/validate", 0, false, NULL, NULL};
  for (int i = 0; i < argc && !rc; ++i) {
    const char *a = argv[i], *v;
    int missing = 0;
    if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
      fputs(validate_help, stdout);
      free(names);
      return EXIT_OK;
    } else if (strcmp(a, "--quick") == 0) {
      ctx.quick = true;
    } else if (strcmp(a, "--list") == 0) {
      list = 1;
    } else if ((v = option_value(argc, argv, &i, "--out", &missing)) || missing) {
      if (missing || !*v) rc = fail(EXIT_INPUT, "--out needs a folder");
      else ctx.out_dir = v;
    } else if ((v = option_value(argc, argv, &i, "--threads", &missing)) || missing) {
      char *end = NULL;
      long t = missing ? 0 : strtol(v, &end, 10);
      if (missing || !end || *end || t < 1 || t > 4096)
        rc = fail(EXIT_INPUT, "--threads needs a whole number from 1 to 4096, not '%s'",
                  missing ? "" : v);
      else threads = (int)t;
    } else if (a[0] == '-' && a[1] != '\0') {
      rc = fail(EXIT_INPUT, "unknown option %s for adem validate (see: adem validate --help)", a);
    } else if (!adem_validation_find(a)) {
      rc = fail(EXIT_INPUT, "unknown validation '%s'; adem validate --list shows them", a);
    } else {
      names[nnames++] = a;
    }
  }
  if (!rc && list) {
    for (size_t k = 0; k < adem_validation_count(); ++k) {
      const adem_validation *v = adem_validation_at(k);
      printf("%-16s %-34s %s\n", v->name, v->source, v->title);
    }
  } else if (!rc) {
    ctx.nthreads = threads > 0 ? threads : adem_default_thread_count();
    if (ctx.nthreads < 1) ctx.nthreads = 1;
    adem_error err;
    memset(&err, 0, sizeof err);
    int failed = 0;
    adem_status st = adem_validation_run(names, nnames, &ctx, &failed, &err);
    if (st) {
      rc = fail(exit_code(st), "%s", err.message);
    } else {
      size_t total = nnames ? (size_t)nnames : adem_validation_count();
      fprintf(stderr, "adem: %zu of %zu validation%s passed; summary in %s/summary.md\n",
              total - (size_t)failed, total, total == 1 ? "" : "s", ctx.out_dir);
      rc = failed ? EXIT_RUNTIME : EXIT_OK;
    }
  }
  free(names);
  return rc;
}
