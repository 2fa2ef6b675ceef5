/* Insertion: size distributions (uniform, normal, log-normal, tabulated), drawn and measured. */
#include "insert.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cylinder.h"
#include "mesh_contact.h"
#include "dmath.h"
#include "log.h"
#include "adem/vec3.h"
#include "stl.h"
#include "world_internal.h"

/* ---------------------------------------------------------------- size distributions */

/* Standard normal 0.1 % quantile: the step estimate takes radii down to it. */
#define Z_SMALL 3.09

static void lognormal_params(const adem_size_dist *d, double *mu, double *sigma) {
  double s2 = adem_dmath_log1p(d->std * d->std / (d->mean * d->mean));
  *sigma = sqrt(s2);
  *mu = adem_dmath_log(d->mean) - 0.5 * s2;
}

adem_status adem_insert_draw_radius(const adem_size_dist *d, adem_rng *rng, double *r,
                                    adem_error *err) {
  switch (d->kind) {
    case ADEM_SIZE_CONSTANT: *r = d->value; return ADEM_OK;
    case ADEM_SIZE_UNIFORM: *r = d->min + (d->max - d->min) * adem_rng_uniform(rng); return ADEM_OK;
    case ADEM_SIZE_DISCRETE: {
      double u = adem_rng_uniform(rng) * d->cumulative[d->n - 1];
      size_t lo = 0, hi = d->n - 1; /* first k with cumulative[k] > u */
      while (lo < hi) {
        size_t mid = (lo + hi) / 2;
        if (d->cumulative[mid] > u) hi = mid;
        else lo = mid + 1;
      }
      *r = d->values[lo];
      return ADEM_OK;
    }
    case ADEM_SIZE_NORMAL:
    case ADEM_SIZE_LOGNORMAL: break;
  }
  bool lognormal = d->kind == ADEM_SIZE_LOGNORMAL;
  double mu = 0.0, sigma = 0.0;
  if (lognormal) lognormal_params(d, &mu, &sigma);
  for (int tries = 0; tries < 1000; ++tries) {
    double z = adem_rng_normal(rng);
    double x = lognormal ? adem_dmath_exp(mu + sigma * z) : d->mean + d->std * z;
    if (x > 0 && x <= d->limit) {
      *r = x;
      return ADEM_OK;
    }
  }
  return adem_error_set(err, ADEM_ERR_INPUT,
                        "could not draw a radius in (0, %g m] in 1000 tries; the distribution "
                        "does not fit",
                        d->limit);
}

double adem_insert_dist_smallest(const adem_size_dist *d) {
  switch (d->kind) {
    case ADEM_SIZE_CONSTANT: return d->value;
    case ADEM_SIZE_UNIFORM: return d->min;
    case ADEM_SIZE_DISCRETE: {
      double r = INFINITY;
      for (size_t k = 0; k < d->n; ++k) r = fmin(r, d->values[k]);
      return r;
    }
    case ADEM_SIZE_NORMAL: return fmax(d->mean - Z_SMALL * d->std, 0.1 * d->mean);
    case ADEM_SIZE_LOGNORMAL: {
      double mu, sigma;
      lognormal_params(d, &mu, &sigma);
      return adem_dmath_exp(mu - Z_SMALL * sigma);
    }
  }
  return 0.0;
}

double adem_insert_dist_largest(const adem_size_dist *d) {
  switch (d->kind) {
    case ADEM_SIZE_CONSTANT: return d->value;
    case ADEM_SIZE_UNIFORM: return d->max;
    case ADEM_SIZE_DISCRETE: {
      double r = 0.0;
      for (size_t k = 0; k < d->n; ++k) r = fmax(r, d->values[k]);
      return r;
    }
    case ADEM_SIZE_NORMAL: return fmin(d->mean + Z_SMALL * d->std, d->limit);
    case ADEM_SIZE_LOGNORMAL: {
      double mu, sigma;
      lognormal_params(d, &mu, &sigma);
      return fmin(adem_dmath_exp(mu + Z_SMALL * sigma), d->limit);
    }
  }
  return 0.0;
}

void adem_insert_dist_moments(const adem_size_dist *d, double *mean, double *std) {
  switch (d->kind) {
    case ADEM_SIZE_CONSTANT:
      *mean = d->value;
      *std = 0.0;
      return;
    case ADEM_SIZE_UNIFORM:
      *mean = 0.5 * (d->min + d->max);
      *std = (d->max - d->min) / sqrt(12.0);
      return;
    case ADEM_SIZE_DISCRETE: {
      double total = d->cumulative[d->n - 1], m = 0.0, m2 = 0.0, prev = 0.0;
      for (size_t k = 0; k < d->n; ++k) {
        double p = (d->cumulative[k] - prev) / total;
        prev = d->cumulative[k];
        m += p * d->values[k];
        m2 += p * d->values[k] * d->values[k];
      }
      *mean = m;
      *std = sqrt(fmax(m2 - m * m, 0.0));
      return;
    }
    case ADEM_SIZE_NORMAL:
    case ADEM_SIZE_LOGNORMAL:
      *mean = d->mean;
      *std = d->std;
      return;
  }
}

void adem_insert_dist_free(adem_size_dist *d) {
  free(d->values);
  free(d->cumulative);
  d->values = d->cumulative = NULL;
  d->n = 0;
}
