/* adem collide */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "adem/files.h"
#include "adem/studies.h"
#include "adem/world.h"
#include "adem/vec3.h"
#include "cli.h"

/* ---------------------------------------------------------------- collide */

const char *const collide_help =
    "Usage:\n"
    "  adem collide [--kind pair|wall] [material options] [--speed LIST] [--angle LIST]\n"
    "               [--lambda LIST] [--ad LIST] [--restitution LIST] [--stiffness-factor LIST]\n"
    "               [--keep-gamma] [deposition options] [--critical-lambda LO:HI[:TOL]]\n"
    "               [--steps-per-tc N] [--out FILE.csv] [--threads N]\n"
    "\n"
    "Runs single collisions in bulk, without a case file: two equal-material spheres head-on\n"
    "(pair) or a sphere on a rigid plane wall at an angle (wall). Every combination of the lists\n"
    "is one collision, in its own world, run in parallel; the rows come out in input order\n"
    "(restitution, then F_hat, then stiffness factor, then Ad, then lambda, then angle, then\n"
    "speed, the last varying fastest). Each row gives e_eff (normal separation/approach speed),\n"
    "whether the spheres stuck, the outcome, the contact duration, the largest overlap and the\n"
    "step used.\n"
    "\n"
    "A LIST is  a,b,c  or  lo:hi:n  (n values, linear)  or  log:lo:hi:n  (n values, logarithmic).\n"
    "\n"
    "Material and impact (defaults: a PSL sphere on quartz, Haervig et al. Fig. 5):\n"
    "  --kind pair|wall         head-on pair or wall impact (default wall)\n"
    "  --radius R               radius r_i of the (first) sphere, m (default 6.35e-7)\n"
    "  --size-ratio B           r_j / r_i of a pair (default 1)\n"
    "  --density RHO            kg/m^3 (default 1026)\n"
    "  --young E                effective Young's modulus E* of the real materials, Pa\n"
    "                           (H2; default 2.71e8)\n"
    "  --poisson NU             Poisson's ratio of the spheres (default 0.3)\n"
    "  --restitution LIST       coefficient of restitution e (default 0.86)\n"
    "  --friction MU            sliding friction (default 0.3)\n"
    "  --surface-energy G       surface energy gamma, J/m^2; 0 gives Hertz (default 0.11)\n"
    "  --stiffness-factor LIST  f = E_mod/E in (0, 1] (default 1); gamma becomes gamma f^(2/5)\n"
    "  --keep-gamma             reduce E only, keep gamma (not H24), for comparison\n"
    "  --speed LIST             relative impact speed, m/s (default 1)\n"
    "  --angle LIST             wall: angle psi between the velocity and the wall, degrees\n"
    "                           (default 90, a normal impact)\n"
    "  --lambda LIST            set E from lambda = E/(rho v^2 sin^2 psi) at each speed\n"
    "  --ad LIST                set gamma from Ad = 3 gamma/(rho v^2 sin^2 psi r_i)\n"
    "                           (1+B^3)/((1+B^2) B) (pair; wall: without the B factor)\n"
    "  --steps-per-tc N         time steps per collision time (default 200)\n"
    "\n"
    "Deposition on the wall (Haervig et al. section 5.3, Figs. 9-10):\n"
    "  --dtk                    DTK adhesive rolling resistance on the sphere-wall pair\n"
    "                           (H18-H22); needs --hysteresis\n"
    "  --hysteresis X           adhesion hysteresis delta_gamma/gamma (> 0)\n"
    "  --no-dtk-modification    F_C, a0 and xi_crit of the modified material as well; the default\n"
    "                           keeps the real ones and modifies only a/a0 (H section 3.2)\n"
    "  --force-ext F            constant force through the centre, parallel to the wall, N,\n"
    "                           along the tangential impact velocity (+x for a normal impact)\n"
    "  --force-hat LIST         or the force as F_ext/F_yield, F_yield = 4 F_C xi_crit / r at\n"
    "                           a = a0 with the real E and gamma (H section 5.3, with the 1/R\n"
    "                           the paper drops)\n"
    "  --at-rest                no impact: the sphere starts at rest at the JKR equilibrium\n"
    "  --rest-periods N         decision window, in rolling periods T_r (default 3)\n"
    "  --max-roll-periods N     longest rolling phase, in T_r (default 400; then undecided)\n"
    "  With --dtk a captured sphere is followed until it is stuck (|xi| below xi_crit and the\n"
    "  centre slower than 2 omega_r xi_crit for a whole window; the time to rest is the start\n"
    "  of the window) or rolling (the rolling torque saturated at k_r xi_crit, the normal motion\n"
    "  settled and the speed not decaying over a window). T_r = 2 pi sqrt(1.4 m r/(4 F_C)).\n"
    "\n"
    "Critical elasticity (Haervig et al. Figs. 11-12, H25):\n"
    "  --critical-lambda LO:HI[:TOL]  instead of a lambda list: for every other combination,\n"
    "                           the lambda in [LO, HI] where the outcome changes between\n"
    "                           captured and rebound, by multisection in log lambda to a\n"
    "                           relative width TOL (default 1e-4). Rows give lambda_crit and\n"
    "                           c = lambda_crit/Ad^(5/2); the fit lambda_crit = c Ad^k per\n"
    "                           restitution goes to standard error.\n"
    "\n"
    "Output:\n"
    "  --out FILE.csv           write the CSV there (default: standard output)\n"
    "  --threads N              threads (default: OMP_NUM_THREADS or all cores); the results\n"
    "                           are identical for every N\n"
    "\n"
    "Ad is the text's definition in Haervig et al. section 5.1 (the caption of their Fig. 7\n"
    "writes gamma/(rho v^2 R), which disagrees). Stuck: the contact's normal energy (kinetic +\n"
    "JKR) has fallen below its value at delta = 0, so the contact can no longer break.\n"
    "\n"
    "Examples:\n"
    "  adem collide --speed log:0.5:20:40 --stiffness-factor 1,0.1,0.01 --out e_eff.csv\n"
    "  adem collide --kind pair --restitution 0.3 --speed 1 --radius 1e-6 --density 1000 \\\n"
    "      --lambda log:1e2:1e7:41 --ad 1,10\n"
    "  adem collide --speed 2 --angle 45 --dtk --hysteresis 0.5 --force-hat 0.5,0.9,1.1,2 \\\n"
    "      --stiffness-factor 1,0.1,0.01\n"
    "  adem collide --radius 1e-6 --density 1000 --ad 100,300,1000 --restitution 0.1:0.9:9 \\\n"
    "      --critical-lambda 1e3:1e13:1e-5\n"
    "\n"
    "Exit status: 0 done; 2 bad option; 3 a collision could not be run (its row says why);\n"
    "4 the CSV could not be written.\n";

typedef struct value_list {
  double *v;
  size_t n;
} value_list;

/* "a,b,c", "lo:hi:n" or "log:lo:hi:n" into a fresh list. */
static int parse_list(const char *opt, const char *text, value_list *out) {
  free(out->v);
  out->v = NULL;
  out->n = 0;
  bool logscale = strncmp(text, "log:", 4) == 0;
  const char *s = logscale ? text + 4 : (strncmp(text, "lin:", 4) == 0 ? text + 4 : text);
  if (strchr(s, ':')) {
    char *end;
    double lo = strtod(s, &end);
    double hi = *end == ':' ? strtod(end + 1, &end) : NAN;
    long n = *end == ':' ? strtol(end + 1, &end, 10) : 0;
    if (*end || !isfinite(lo) || !isfinite(hi) || n < 1 || n > 1000000 ||
        (logscale && !(lo > 0.0 && hi > 0.0)))
      return fail(EXIT_INPUT,
                  "%s %s: expected lo:hi:n or log:lo:hi:n (n from 1 to 1000000, log needs lo, hi "
                  "> 0)",
                  opt, text);
    out->v = malloc((size_t)n * sizeof *out->v);
    if (!out->v) return fail(EXIT_INTERNAL, "out of memory");
    for (long k = 0; k < n; ++k) {
      double x = n == 1 ? 0.0 : (double)k / (double)(n - 1);
      out->v[k] = logscale ? lo * pow(hi / lo, x) : lo + (hi - lo) * x;
    }
    out->n = (size_t)n;
    return EXIT_OK;
  }
  size_t cap = 1;
  for (const char *c = s; *c; ++c) cap += *c == ',';
  out->v = malloc(cap * sizeof *out->v);
  if (!out->v) return fail(EXIT_INTERNAL, "out of memory");
  for (const char *c = s;;) {
    char *end;
    double x = strtod(c, &end);
    if (end == c || (*end && *end != ',') || !isfinite(x))
      return fail(EXIT_INPUT, "%s %s: expected numbers separated by commas, lo:hi:n or "
                              "log:lo:hi:n",
                  opt, text);
    out->v[out->n++] = x;
    if (!*end) break;
    c = end + 1;
  }
  return EXIT_OK;
}

static int parse_number_option(const char *opt, const char *text, double *x) {
  char *end;
  *x = strtod(text, &end);
  if (end == text || *end || !isfinite(*x))
    return fail(EXIT_INPUT, "%s needs a number, not '%s'", opt, text);
  return EXIT_OK;
}

/* Every value of the list satisfies lo < x (or lo <= x) and x <= hi. */
static int check_list(const char *opt, const value_list *l, double lo, bool lo_open, double hi,
                      const char *allowed) {
  for (size_t k = 0; k < l->n; ++k)
    if ((lo_open ? !(l->v[k] > lo) : !(l->v[k] >= lo)) || !(l->v[k] <= hi))
      return fail(EXIT_INPUT, "%s: %g is out of range: it must be %s", opt, l->v[k], allowed);
  return EXIT_OK;
}

/* "LO:HI" or "LO:HI:TOL" of --critical-lambda. */
static int parse_critical(const char *text, double *lo, double *hi, double *tol) {
  char *end;
  *lo = strtod(text, &end);
  *hi = *end == ':' ? strtod(end + 1, &end) : NAN;
  *tol = 1e-4;
  if (*end == ':') *tol = strtod(end + 1, &end);
  if (*end || !(*lo > 0.0) || !(*hi > *lo) || !isfinite(*hi) || !(*tol > 0.0 && *tol < 1.0))
    return fail(EXIT_INPUT, "--critical-lambda %s: expected LO:HI or LO:HI:TOL with 0 < LO < HI "
                            "and 0 < TOL < 1",
                text);
  return EXIT_OK;
}

static void set_lambda_cli(adem_collide_spec *s, double x, void *user) {
  (void)user;
  adem_collide_set_lambda(s, x);
}

/* The CSV cell of a message: quoted, inner quotes made single. */
static void status_cell(char *out, size_t n, adem_status st, const char *message) {
  if (!st) {
    snprintf(out, n, "ok");
    return;
  }
  snprintf(out, n, "\"error: %s\"", message);
  for (char *q = out + 1; q[0] && q[1]; ++q)
    if (*q == '"') *q = '\'';
}

int cmd_collide(int argc, char **argv) {
  adem_collide_spec base = adem_default_collide_spec();
  adem_error perr;
  if (adem_collide_psl_quartz(&base, &perr)) return fail(EXIT_INTERNAL, "%s", perr.message);
  base.friction = 0.3;
  value_list speed = {0}, angle = {0}, lambda = {0}, ad = {0}, fs = {0}, rest = {0}, fhat = {0};
  const char *out = NULL, *critical = NULL;
  int threads = 0, rc = EXIT_OK;
  static const struct {
    const char *name;
    size_t offset;
  } numbers[] = {
      {"--radius", offsetof(adem_collide_spec, radius)},
      {"--size-ratio", offsetof(adem_collide_spec, size_ratio)},
      {"--density", offsetof(adem_collide_spec, density)},
      {"--young", offsetof(adem_collide_spec, young)},
      {"--poisson", offsetof(adem_collide_spec, poisson)},
      {"--friction", offsetof(adem_collide_spec, friction)},
      {"--surface-energy", offsetof(adem_collide_spec, surface_energy)},
      {"--steps-per-tc", offsetof(adem_collide_spec, steps_per_tc)},
      {"--hysteresis", offsetof(adem_collide_spec, hysteresis)},
      {"--force-ext", offsetof(adem_collide_spec, force_ext)},
      {"--rest-periods", offsetof(adem_collide_spec, rest_periods)},
      {"--max-roll-periods", offsetof(adem_collide_spec, max_roll_periods)},
  };
  static const char *const list_names[] = {"--speed", "--angle", "--lambda", "--ad",
                                           "--stiffness-factor", "--restitution", "--force-hat"};
  value_list *lists[] = {&speed, &angle, &lambda, &ad, &fs, &rest, &fhat};
  enum { NLISTS = sizeof lists / sizeof lists[0] };
  static const struct {
    const char *name;
    size_t offset;
  } flags[] = {
      {"--keep-gamma", offsetof(adem_collide_spec, keep_gamma)},
      {"--dtk", offsetof(adem_collide_spec, dtk)},
      {"--at-rest", offsetof(adem_collide_spec, at_rest)},
  };
  for (int i = 0; i < argc && !rc; ++i) {
    const char *a = argv[i], *v;
    int missing = 0, done = 0;
    if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
      fputs(collide_help, stdout);
      rc = -1;
      break;
    }
    for (size_t k = 0; k < sizeof flags / sizeof flags[0] && !done; ++k)
      if (strcmp(a, flags[k].name) == 0) {
        *(bool *)((char *)&base + flags[k].offset) = true;
        done = 1;
      }
    if (!done && strcmp(a, "--no-dtk-modification") == 0) {
      base.dtk_modification = false;
      done = 1;
    }
    for (size_t k = 0; k < sizeof numbers / sizeof numbers[0] && !done && !rc; ++k)
      if ((v = option_value(argc, argv, &i, numbers[k].name, &missing)) || missing) {
        done = 1;
        rc = missing ? fail(EXIT_INPUT, "%s needs a value", numbers[k].name)
                     : parse_number_option(numbers[k].name, v,
                                           (double *)((char *)&base + numbers[k].offset));
      }
    for (size_t k = 0; k < NLISTS && !done && !rc; ++k)
      if ((v = option_value(argc, argv, &i, list_names[k], &missing)) || missing) {
        done = 1;
        rc = missing ? fail(EXIT_INPUT, "%s needs a value", list_names[k])
                     : parse_list(list_names[k], v, lists[k]);
      }
    if (done || rc) continue;
    if ((v = option_value(argc, argv, &i, "--kind", &missing)) || missing) {
      if (!missing && strcmp(v, "pair") == 0) base.kind = ADEM_COLLIDE_PAIR;
      else if (!missing && strcmp(v, "wall") == 0) base.kind = ADEM_COLLIDE_WALL;
      else rc = fail(EXIT_INPUT, "--kind needs pair or wall, not '%s'", missing ? "" : v);
    } else if ((v = option_value(argc, argv, &i, "--critical-lambda", &missing)) || missing) {
      if (missing || !*v) rc = fail(EXIT_INPUT, "--critical-lambda needs LO:HI or LO:HI:TOL");
      else critical = v;
    } else if ((v = option_value(argc, argv, &i, "--out", &missing)) || missing) {
      if (missing || !*v) rc = fail(EXIT_INPUT, "--out needs a file name");
      else out = v;
    } else if ((v = option_value(argc, argv, &i, "--threads", &missing)) || missing) {
      char *end = NULL;
      long t = missing ? 0 : strtol(v, &end, 10);
      if (missing || !end || *end || t < 1 || t > 4096)
        rc = fail(EXIT_INPUT, "--threads needs a whole number from 1 to 4096, not '%s'",
                  missing ? "" : v);
      else threads = (int)t;
    } else {
      rc = fail(EXIT_INPUT, "unknown option or argument '%s' for adem collide (see: adem collide "
                            "--help)",
                a);
    }
  }
  /* Checks of what every collision shares, then of each list. */
  bool wall = base.kind == ADEM_COLLIDE_WALL;
  double crit_lo = 0.0, crit_hi = 0.0, crit_tol = 0.0;
  if (!rc && !(base.radius > 0.0)) rc = fail(EXIT_INPUT, "--radius must be > 0");
  if (!rc && !(base.size_ratio > 0.0)) rc = fail(EXIT_INPUT, "--size-ratio must be > 0");
  if (!rc && !(base.density > 0.0)) rc = fail(EXIT_INPUT, "--density must be > 0");
  if (!rc && !(base.young > 0.0)) rc = fail(EXIT_INPUT, "--young must be > 0");
  if (!rc && !(base.poisson > -1.0 && base.poisson < 0.5))
    rc = fail(EXIT_INPUT, "--poisson %g is outside (-1, 0.5)", base.poisson);
  if (!rc && !(base.friction >= 0.0)) rc = fail(EXIT_INPUT, "--friction must be >= 0");
  if (!rc && !(base.surface_energy >= 0.0))
    rc = fail(EXIT_INPUT, "--surface-energy %g must be >= 0 (0: Hertz, no adhesion)",
              base.surface_energy);
  if (!rc && !(base.steps_per_tc >= 10.0))
    rc = fail(EXIT_INPUT, "--steps-per-tc must be at least 10");
  if (!rc && !(base.hysteresis >= 0.0)) rc = fail(EXIT_INPUT, "--hysteresis must be >= 0");
  if (!rc && base.dtk && !(base.hysteresis > 0.0))
    rc = fail(EXIT_INPUT, "--dtk needs --hysteresis X > 0 (xi_crit = a0/12 X, H18)");
  if (!rc && !(base.force_ext >= 0.0))
    rc = fail(EXIT_INPUT, "--force-ext must be >= 0 N (it points along the tangential velocity)");
  if (!rc && !(base.rest_periods > 0.0)) rc = fail(EXIT_INPUT, "--rest-periods must be > 0");
  if (!rc && !(base.max_roll_periods >= base.rest_periods))
    rc = fail(EXIT_INPUT, "--max-roll-periods must be at least --rest-periods");
  if (!rc) rc = check_list("--speed", &speed, 0.0, true, INFINITY, "> 0 m/s");
  if (!rc) rc = check_list("--angle", &angle, 0.0, true, 90.0, "in (0, 90] degrees");
  if (!rc) rc = check_list("--lambda", &lambda, 0.0, true, INFINITY, "> 0");
  if (!rc) rc = check_list("--ad", &ad, 0.0, false, INFINITY, ">= 0");
  if (!rc) rc = check_list("--stiffness-factor", &fs, 0.0, true, 1.0, "in (0, 1]");
  if (!rc) rc = check_list("--restitution", &rest, 0.0, true, 1.0, "in (0, 1]");
  if (!rc) rc = check_list("--force-hat", &fhat, 0.0, false, INFINITY, ">= 0");
  if (!rc && !wall && angle.n)
    rc = fail(EXIT_INPUT, "--angle is for wall impacts (--kind wall); pairs collide head-on");
  if (!rc && !wall && (base.force_ext > 0.0 || fhat.n || base.at_rest || base.dtk))
    rc = fail(EXIT_INPUT, "--dtk, --force-ext, --force-hat and --at-rest are for wall impacts "
                          "(--kind wall)");
  if (!rc && (base.dtk || base.at_rest) && !(base.surface_energy > 0.0 || ad.n))
    rc = fail(EXIT_INPUT, "--dtk and --at-rest need adhesion: --surface-energy > 0 or --ad");
  if (!rc && fhat.n && !base.dtk)
    rc = fail(EXIT_INPUT, "--force-hat needs --dtk (F_yield = 4 F_C xi_crit / r comes from the "
                          "DTK law); give the force in N with --force-ext instead");
  if (!rc && fhat.n && base.force_ext > 0.0)
    rc = fail(EXIT_INPUT, "give the force either in N (--force-ext) or as F_ext/F_yield "
                          "(--force-hat), not both");
  if (!rc && critical && lambda.n)
    rc = fail(EXIT_INPUT, "--critical-lambda finds lambda: do not give --lambda as well");
  if (!rc && critical && base.at_rest)
    rc = fail(EXIT_INPUT, "--critical-lambda needs impacts: it cannot go with --at-rest");
  if (!rc && critical) rc = parse_critical(critical, &crit_lo, &crit_hi, &crit_tol);
  static double one = 1.0, ninety = 90.0, zero = 0.0;
  double e0 = base.restitution;
  value_list dspeed = {&one, 1}, dangle = {&ninety, 1}, dnone = {NULL, 1}, dfs = {&one, 1};
  value_list drest = {&e0, 1}, dfhat = {&zero, 1};
  const value_list *S = speed.n ? &speed : &dspeed, *A = angle.n ? &angle : &dangle;
  const value_list *L = lambda.n ? &lambda : &dnone, *D = ad.n ? &ad : &dnone;
  const value_list *F = fs.n ? &fs : &dfs, *E = rest.n ? &rest : &drest;
  const value_list *H = fhat.n ? &fhat : &dfhat;
  size_t n = S->n * A->n * L->n * D->n * F->n * E->n * H->n;
  adem_collide_spec *sp = NULL;
  adem_collide_result *res = NULL;
  double *lcrit = NULL;
  char(*lmsg)[ADEM_MSG_MAX] = NULL;
  if (!rc && n > 10000000) rc = fail(EXIT_INPUT, "%zu collisions are too many (at most 1e7)", n);
  if (!rc) {
    sp = malloc(n * sizeof *sp);
    res = critical ? NULL : malloc(n * sizeof *res);
    lcrit = critical ? malloc(n * sizeof *lcrit) : NULL;
    lmsg = critical ? calloc(n, sizeof *lmsg) : NULL;
    if (!sp || (critical ? !lcrit || !lmsg : !res)) rc = fail(EXIT_INTERNAL, "out of memory");
  }
  if (!rc) {
    size_t k = 0;
    for (size_t e = 0; e < E->n; ++e)
      for (size_t h = 0; h < H->n; ++h)
        for (size_t f = 0; f < F->n; ++f)
          for (size_t d = 0; d < D->n; ++d)
            for (size_t l = 0; l < L->n; ++l)
              for (size_t g = 0; g < A->n; ++g)
                for (size_t v = 0; v < S->n; ++v, ++k) {
                  adem_collide_spec c = base;
                  c.restitution = E->v[e];
                  c.force_hat = H->v[h];
                  c.stiffness_factor = F->v[f];
                  c.speed = S->v[v];
                  c.angle = A->v[g] * ADEM_PI / 180.0;
                  if (lambda.n) adem_collide_set_lambda(&c, L->v[l]);
                  if (ad.n) adem_collide_set_ad(&c, D->v[d]);
                  sp[k] = c;
                }
    double t0 = cli_now();
    int nt = threads > 0 ? threads : adem_default_thread_count();
    if (nt < 1) nt = 1;
    size_t failed = 0, first_failed = n;
    if (critical) {
      for (size_t q = 0; q < n; ++q) {
        adem_error err;
        memset(&err, 0, sizeof err);
        adem_status st = adem_collide_threshold(&sp[q], set_lambda_cli, NULL, crit_lo, crit_hi,
                                                crit_tol, nt, &lcrit[q], &err);
        if (st) {
          lcrit[q] = NAN;
          snprintf(lmsg[q], sizeof lmsg[q], "%s", err.message);
          if (!failed++) first_failed = q;
        }
      }
    } else {
      adem_collide_many(sp, res, n, nt);
      for (size_t q = 0; q < n; ++q)
        if (res[q].status && !failed++) first_failed = q;
    }
    double spent = cli_now() - t0;
    adem_afile af;
    adem_error err;
    FILE *f = stdout;
    if (out) {
      adem_status st = adem_file_open(&af, out, &err);
      if (st) rc = fail(exit_code(st), "%s", err.message);
      else f = af.f;
    }
    size_t stuck = 0, undecided = 0, counts[4] = {0};
    if (!rc && critical) {
      fputs("kind,radius_m,size_ratio,density_kg_m3,poisson,restitution,friction,speed_m_s,"
            "angle_deg,Ad,stiffness_factor,gamma_by_H24,dtk,hysteresis,F_hat,lambda_crit,c,"
            "rel_tol,status\n",
            f);
      for (size_t q = 0; q < n; ++q) {
        const adem_collide_spec *c = &sp[q];
        char status[ADEM_MSG_MAX + 16];
        status_cell(status, sizeof status, isnan(lcrit[q]) ? ADEM_ERR_RUNTIME : ADEM_OK, lmsg[q]);
        double a = adem_collide_ad(c);
        fprintf(f, "%s,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%d,%d,%.10g,"
                   "%.10g,%.10g,%.10g,%.3g,%s\n",
                wall ? "wall" : "pair", c->radius, wall ? 0.0 : c->size_ratio, c->density,
                c->poisson, c->restitution, c->friction, c->speed, c->angle * 180.0 / ADEM_PI, a,
                c->stiffness_factor, c->keep_gamma ? 0 : 1, c->dtk ? 1 : 0, c->hysteresis,
                c->force_hat, lcrit[q], lcrit[q] / pow(a, 2.5), crit_tol, status);
      }
    } else if (!rc) {
      fputs("kind,radius_m,size_ratio,density_kg_m3,E_Pa,poisson,gamma_J_m2,stiffness_factor,"
            "gamma_by_H24,restitution,friction,speed_m_s,angle_deg,lambda,Ad,e_eff,stuck,"
            "undecided,v_n_in_m_s,v_n_out_m_s,v_t_out_m_s,omega_out_rad_s,contact_duration_s,"
            "max_overlap_m,t_c_s,dt_s,steps,dtk,hysteresis,dtk_modification,at_rest,F_ext_N,"
            "F_hat,outcome,outcome_code,roll_distance_m,t_rest_s,v_end_m_s,xi_crit_m,t_roll_s,"
            "status\n",
            f);
      for (size_t q = 0; q < n; ++q) {
        const adem_collide_spec *c = &sp[q];
        const adem_collide_result *r = &res[q];
        if (!r->status) {
          stuck += r->stuck;
          undecided += r->undecided;
          counts[r->outcome]++;
        }
        char status[300];
        status_cell(status, sizeof status, r->status, r->message);
        double fy = adem_collide_yield_force(c);
        fprintf(f, "%s,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%d,%.10g,%.10g,%.10g,%.10g,%.10g,"
                   "%.10g,%.10g,%d,%d,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%llu,",
                wall ? "wall" : "pair", c->radius, wall ? 0.0 : c->size_ratio, c->density,
                c->young, c->poisson, c->surface_energy, c->stiffness_factor, c->keep_gamma ? 0 : 1,
                c->restitution, c->friction, c->speed, c->angle * 180.0 / ADEM_PI,
                adem_collide_lambda(c), adem_collide_ad(c), r->e_eff, r->stuck ? 1 : 0,
                r->undecided ? 1 : 0, r->v_n_in, r->v_n_out, r->v_t_out, r->omega_out,
                r->duration, r->max_overlap, r->t_c, r->dt, (unsigned long long)r->steps);
        fprintf(f, "%d,%.10g,%d,%d,%.10g,%.10g,%s,%d,%.10g,%.10g,%.10g,%.10g,%.10g,%s\n",
                c->dtk ? 1 : 0, c->hysteresis, c->dtk_modification ? 1 : 0, c->at_rest ? 1 : 0,
                r->force_ext, fy > 0.0 ? r->force_ext / fy : NAN,
                adem_collide_outcome_name(r->outcome), (int)r->outcome, r->roll_distance,
                r->t_rest, r->v_end, r->xi_crit, r->t_roll, status);
      }
    }
    if (!rc) {
      if (out) {
        adem_status st = adem_file_commit(&af, &err);
        if (st) rc = fail(exit_code(st), "%s", err.message);
      } else if (fflush(stdout) != 0) {
        rc = fail(EXIT_IO, "standard output could not be written");
      }
    }
    if (!rc && critical) {
      fprintf(stderr, "adem: %zu critical lambda%s in %.2f s on %d thread%s%s%s\n", n,
              n == 1 ? "" : "s", spent, nt, nt == 1 ? "" : "s", out ? "; CSV in " : "",
              out ? out : "");
      /* H25 per restitution: the fit over the other lists' combinations */
      size_t per = n / E->n;
      double *x = malloc(per * sizeof *x), *y = malloc(per * sizeof *y);
      for (size_t e = 0; x && y && e < E->n; ++e) {
        for (size_t q = 0; q < per; ++q) {
          x[q] = adem_collide_ad(&sp[e * per + q]);
          y[q] = lcrit[e * per + q];
        }
        double c, k;
        size_t used = adem_collide_fit_power(x, y, per, &c, &k);
        if (used >= 2 && isfinite(k))
          fprintf(stderr, "adem: e = %g: lambda_crit = %.5g Ad^%.4f (%zu points)\n", E->v[e], c,
                  k, used);
      }
      free(x);
      free(y);
    } else if (!rc) {
      fprintf(stderr, "adem: %zu collision%s in %.2f s on %d thread%s: %zu stuck%s", n,
              n == 1 ? "" : "s", spent, nt, nt == 1 ? "" : "s", stuck, undecided ? " (" : "");
      if (undecided) fprintf(stderr, "%zu undecided after the time limit)", undecided);
      fprintf(stderr, ", %zu rebounded", counts[ADEM_OUTCOME_REBOUND]);
      if (base.dtk)
        fprintf(stderr, "; on the wall: %zu rolling, %zu at rest", counts[ADEM_OUTCOME_ROLLING],
                counts[ADEM_OUTCOME_STUCK]);
      fprintf(stderr, "%s%s\n", out ? "; CSV in " : "", out ? out : "");
    }
    if (!rc && failed)
      rc = fail(EXIT_RUNTIME, "%zu %s could not be run; the first (row %zu): %s", failed,
                critical ? (failed == 1 ? "threshold" : "thresholds")
                         : (failed == 1 ? "collision" : "collisions"),
                first_failed + 1, critical ? lmsg[first_failed] : res[first_failed].message);
  }
  free(sp);
  free(res);
  free(lcrit);
  free(lmsg);
  for (size_t k = 0; k < NLISTS; ++k) free(lists[k]->v);
  return rc < 0 ? EXIT_OK : rc;
}
