/* A periodic bed: 300 frictional spheres thrown sideways (0.5 m/s along x, -0.3 along y) into a
 * box periodic in x and y, falling onto a frictionless floor, 2000 steps (14 ms): many crossings
 * of the periodic faces, contacts through them with tangential history, and neighbour rebuilds
 * on both sides of the halfway point. The random fill stays a radius and a bit off the periodic
 * faces (it does not look through them). Line numbers are in the comments. */
#ifndef ADEM_TEST_PERIODIC_CASE_H
#define ADEM_TEST_PERIODIC_CASE_H

#define PERIODIC_STEPS 2000

static const char *const periodic_case =
    "name: periodic-bed\n"                                                 /* 1 */
    "seed: 7\n"                                                            /* 2 */
    "materials:\n"                                                         /* 3 */
    "  - {name: glass, density: 2500, youngs_modulus: 1.0e6, poisson_ratio: 0.3,\n" /* 4 */
    "     restitution: 0.5, friction: 0.5}\n"                              /* 5 */
    "  - {name: steel, rigid: true, friction: 0.4}\n"                      /* 6 */
    "interactions:\n"                                                      /* 7 */
    "  - {materials: [glass, steel], friction: 0}\n"                       /* 8 */
    "particles:\n"                                                         /* 9 */
    "  - type: random\n"                                                   /* 10 */
    "    material: glass\n"                                                /* 11 */
    "    radius: {distribution: uniform, min: 0.0008, max: 0.0012}\n"      /* 12 */
    "    min: [0.0012, 0.0012, 0.0005]\n"                                  /* 13 */
    "    max: [0.0138, 0.0138, 0.03]\n"                                    /* 14 */
    "    count: 300\n"                                                     /* 15 */
    "    velocity: [0.5, -0.3, -0.5]\n"                                    /* 16 */
    "walls:\n"                                                             /* 17 */
    "  - type: plane\n"                                                    /* 18 */
    "    name: floor\n"                                                    /* 19 */
    "    material: steel\n"                                                /* 20 */
    "    point: [0, 0, 0]\n"                                               /* 21 */
    "    normal: [0, 0, 1]\n"                                              /* 22 */
    "domain:\n"                                                            /* 23 */
    "  min: [0, 0, -0.01]\n"                                               /* 24 */
    "  max: [0.015, 0.015, 0.06]\n"                                        /* 25 */
    "  periodic: [true, true, false]\n"                                    /* 26 */
    "time:\n"                                                              /* 27 */
    "  end: 0.014\n"                                                       /* 28 */
    "  step: 7.0e-6\n"                                                     /* 29 */
    "output:\n"                                                            /* 30 */
    "  frame_interval: 0.0035\n"                                           /* 31 */
    "  csv_interval: 0.00035\n"                                            /* 32 */
    "  checkpoint_interval: 0\n";                                          /* 33 */

#endif
