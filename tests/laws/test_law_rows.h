/* A rolling law that exists only in the test build (tests/laws): one row, added at build time
 * through ADEM_EXTRA_LAWS_HEADER, with no edit of the schema, the loader or the force pass. */
#ifndef ADEM_TEST_LAW_ROWS_H
#define ADEM_TEST_LAW_ROWS_H

// clang-format off
#define ADEM_EXTRA_ROLLING_LAWS(X)                                                        \
  X(ADEM_ROLLING_TEST_VISCOUS, "test_viscous", adem_rolling_test_viscous_law, 0, "", 0,   \
    "rolling_friction", "test", "Test only: viscous rolling couple -eta_r R_r |F_n| (omega_rel / 1 rad/s).") \
  X(ADEM_ROLLING_TEST_MODEL_C_STIFF, "test_model_c_stiff", adem_rolling_test_model_c_stiff_law, 3, \
    "", 0, "rolling_friction rolling_damping", "test",                                   \
    "Test only, a wrong law: model C with k_r 1.1 times Ai et al.'s.")                  \
  X(ADEM_ROLLING_TEST_MODEL_C_HALF_LIMIT, "test_model_c_half_limit",                     \
    adem_rolling_test_model_c_half_limit_law, 3, "", 0, "rolling_friction rolling_damping", \
    "test", "Test only, a wrong law: model C limited to half of eta_r R_r |F_n|.")         \
  X(ADEM_ROLLING_TEST_DTK_SOFT, "test_dtk_soft", adem_rolling_test_dtk_soft_law, 3, "jkr", 0, \
    "adhesion_hysteresis", "test", "Test only, a wrong law: DTK with k_r 0.2 times H20's.")
// clang-format on

/* Deliberately wrong normal laws, for the tests that show a validation fails with a wrong law
 * (tests/laws/test_perturbed_validations.c). */
// clang-format off
#define ADEM_EXTRA_NORMAL_LAWS(X)                                                         \
  X(ADEM_NORMAL_TEST_JKR_FC105, "test_jkr_fc105", adem_normal_test_jkr_fc105_law, 0, "", 0, \
    "surface_energy", "test", "Test only, a wrong law: simplified JKR with gamma (so F_C) x 1.05.") \
  X(ADEM_NORMAL_TEST_JKR_EPULL, "test_jkr_epull", adem_normal_test_jkr_epull_law, 0, "", 0, \
    "surface_energy", "test",                                                             \
    "Test only, a wrong law: simplified JKR with gamma x (E/E_real)^0.05: a pull-off that "   \
    "depends on the stiffness factor.")
// clang-format on

#endif
