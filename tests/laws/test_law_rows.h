/* A rolling law that exists only in the test build (tests/laws): one row, added at build time
 * through ADEM_EXTRA_LAWS_HEADER, with no edit of the schema, the loader or the force pass. */
#ifndef ADEM_TEST_LAW_ROWS_H
#define ADEM_TEST_LAW_ROWS_H

#define ADEM_EXTRA_ROLLING_LAWS(X)                                                        \
  X(ADEM_ROLLING_TEST_VISCOUS, "test_viscous", adem_rolling_test_viscous_law, 0, "", 0,   \
    "rolling_friction", "test", "Test only: viscous rolling couple -eta_r R_r |F_n| (omega_rel / 1 rad/s).")

#endif
