/* Shared by the C reference programs of benchmarks/: the one-mode force table of
 * model.rom (piecewise Chebyshev, degree 7, NCOEF coefficients per piece, row-major
 * (pieces, NCOEF)), evaluated by a Clenshaw sum on the piece containing x in [0, q_max). */
#ifndef FORCE_TABLE_H
#define FORCE_TABLE_H

#define NCOEF 8

static inline double table_row(const double *coef, int pieces, double q_max, double x) {
    double width = q_max / pieces;
    int i = (int)(x / width);
    if (i > pieces - 1) i = pieces - 1;
    double t = 2.0 * (x - i * width) / width - 1.0;
    const double *c = coef + (long)i * NCOEF;
    double b1 = 0.0, b2 = 0.0;
    for (int k = NCOEF - 1; k > 0; k--) { double b = 2.0 * t * b1 - b2 + c[k]; b2 = b1; b1 = b; }
    return t * b1 - b2 + c[0];
}

#endif
