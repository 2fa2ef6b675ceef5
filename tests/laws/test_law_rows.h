/* Contact laws that exist only in the test build (tests/laws): rows added at build time through
 * ADEM_EXTRA_LAWS_HEADER, with no edit of the schema, the loader or the force pass. Their
 * descriptive columns are a designated initializer as the library's rows are (adem/laws.h). */
#ifndef ADEM_TEST_LAW_ROWS_H
#define ADEM_TEST_LAW_ROWS_H

// clang-format off
#define ADEM_EXTRA_ROLLING_LAWS(X)                                                                \
  X(ADEM_ROLLING_TEST_VISCOUS, adem_rolling_test_viscous_law, 0, .name = "test_viscous",         \
    .params = "rolling_friction", .equations = "test",                                           \
    .doc = "Test only: viscous rolling couple -eta_r R_r |F_n| (omega_rel / 1 rad/s).")          \
  X(ADEM_ROLLING_TEST_MODEL_C_STIFF, adem_rolling_test_model_c_stiff_law, 3,                     \
    .name = "test_model_c_stiff", .params = "rolling_friction rolling_damping",                  \
    .equations = "test", .doc = "Test only, a wrong law: model C with k_r 1.1 times Ai et al.'s.") \
  X(ADEM_ROLLING_TEST_MODEL_C_HALF_LIMIT, adem_rolling_test_model_c_half_limit_law, 3,           \
    .name = "test_model_c_half_limit", .params = "rolling_friction rolling_damping",             \
    .equations = "test",                                                                         \
    .doc = "Test only, a wrong law: model C limited to half of eta_r R_r |F_n|.")                \
  X(ADEM_ROLLING_TEST_DTK_SOFT, adem_rolling_test_dtk_soft_law, 3, .name = "test_dtk_soft",      \
    .requires = "jkr", .params = "adhesion_hysteresis", .equations = "test",                     \
    .doc = "Test only, a wrong law: DTK with k_r 0.2 times H20's.")
// clang-format on

/* Deliberately wrong normal laws, for the tests that show a validation fails with a wrong law
 * (tests/laws/test_perturbed_validations.c); and a JKR-like law under another name whose cold
 * path (collision time, pull-off force, checks, report) comes from its hooks alone
 * (tests/laws/test_law_hooks.c). */
// clang-format off
#define ADEM_EXTRA_NORMAL_LAWS(X)                                                                 \
  X(ADEM_NORMAL_TEST_JKR_FC105, adem_normal_test_jkr_fc105_law, 0, .name = "test_jkr_fc105",     \
    .params = "surface_energy", .equations = "test",                                             \
    .doc = "Test only, a wrong law: simplified JKR with gamma (so F_C) x 1.05.")                 \
  X(ADEM_NORMAL_TEST_JKR_EPULL, adem_normal_test_jkr_epull_law, 0, .name = "test_jkr_epull",     \
    .params = "surface_energy", .equations = "test",                                             \
    .doc = "Test only, a wrong law: simplified JKR with gamma x (E/E_real)^0.05: a pull-off "    \
           "that depends on the stiffness factor.")                                              \
  X(ADEM_NORMAL_TEST_JKR_LIKE, adem_normal_test_jkr_like_law, 0, .name = "test_jkr_like",        \
    .params = "surface_energy", .equations = "test",                                             \
    .doc = "Test only: simplified JKR under another name; its collision time, pull-off force, "  \
           "checks and report lines are JKR's through its hooks alone.",                         \
    .hooks = &adem_jkr_hooks)
// clang-format on

#endif
