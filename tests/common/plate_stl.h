/* A flat STL plate for mesh-wall tests. Include after cmocka.h. */
#ifndef ADEM_TEST_PLATE_STL_H
#define ADEM_TEST_PLATE_STL_H

#include <stdio.h>

/* Writes to PATH an ASCII STL plate of N x N squares of side H centred on the origin at z = 0,
 * each square cut along a diagonal (H a power of 2: exact in float32 and in the text). */
static inline void write_plate(const char *path, int n, double h) {
  FILE *f = fopen(path, "w");
  assert_non_null(f);
  fprintf(f, "solid plate\n");
  double o = -0.5 * n * h;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      double x0 = o + i * h, x1 = x0 + h, y0 = o + j * h, y1 = y0 + h;
      double t[2][9] = {{x0, y0, 0, x1, y0, 0, x1, y1, 0}, {x0, y0, 0, x1, y1, 0, x0, y1, 0}};
      for (int k = 0; k < 2; ++k)
        fprintf(f,
                "facet normal 0 0 1\nouter loop\nvertex %.17g %.17g %.17g\nvertex %.17g %.17g "
                "%.17g\nvertex %.17g %.17g %.17g\nendloop\nendfacet\n",
                t[k][0], t[k][1], t[k][2], t[k][3], t[k][4], t[k][5], t[k][6], t[k][7], t[k][8]);
    }
  fprintf(f, "endsolid plate\n");
  fclose(f);
}

#endif
