/* The kernel of the test-only rolling law (test_law_rows.h): a couple proportional to the relative
 * spin, -eta_r R_r |F_n| omega_rel / (1 rad/s), equal and opposite on the two bodies. */
#ifndef ADEM_TEST_LAW_KERNELS_H
#define ADEM_TEST_LAW_KERNELS_H

static inline void adem_rolling_test_viscous_law(const adem_rolling_input *in, adem_vec3 *hist,
                                                 adem_rolling_output *out) {
  (void)hist;
  double c = adem_rolling_eta(in) * adem_rolling_radius(in->g) * in->f_load;
  out->torque = v3_scale(in->g->omega_rel, -c);
}

#endif
