/* Shared by the C reference programs of benchmarks/: the tables of a ROM as the benchmarks
 * write them (those of an axisymmetric set; a general set's b_theta follows them), and the
 * quadrature force of model.rom.axisymmetric_force.
 * The slope
 * a_p = sum_k q_k B_kp at every quadrature point, the determinant of the in-plane metric
 * delta = hoop2 (radial2 + a^2), then (the neo-Hookean law)
 *   g_k = sum_p 2 a (1 - hoop2 / delta^2) w B_kp
 * (a: P work values; restrict pointers, loops over the points innermost; three modes in
 * one pass over the points). */
#ifndef AXISYMMETRIC_FORCE_H
#define AXISYMMETRIC_FORCE_H

/* The arrays of model.rom.RomTables, in the order of the benchmarks' tables file: weight,
 * inv_rho2, hoop2, radial2 (P each), B (K x P, row-major), k_force (K), load (K), float64. */
typedef struct { const double *w, *inv_rho2, *hoop2, *radial2, *B, *k_force, *load; } QuadratureTables;

static inline QuadratureTables quadrature_tables(const double *tables, int K, int P) {
    QuadratureTables t = {tables, tables + P, tables + 2 * P, tables + 3 * P, tables + 4 * P,
                          tables + 4 * P + (long)K * P, tables + 4 * P + (long)K * P + K};
    return t;
}

static void force(const double *restrict q, int K, int P, const double *restrict w, const double *restrict inv_rho2,
                  const double *restrict hoop2, const double *restrict radial2, const double *restrict B,
                  double *restrict a, double *restrict g) {
    if (K == 3) { /* the three modes written out: one pass over the points, as the numba kernel */
        double g0 = 0.0, g1 = 0.0, g2 = 0.0;
        for (int p = 0; p < P; p++) {
            double c0 = B[p], c1 = B[P + p], c2 = B[2L * P + p];
            double s = q[0] * c0 + q[1] * c1 + q[2] * c2, e = 1.0 / (hoop2[p] * (radial2[p] + s * s));
            double f = 2.0 * s * (1.0 - e * e * hoop2[p]) * w[p];
            g0 += f * c0;
            g1 += f * c1;
            g2 += f * c2;
        }
        g[0] = g0;
        g[1] = g1;
        g[2] = g2;
        return;
    }
    for (int p = 0; p < P; p++) a[p] = q[0] * B[p];
    for (int k = 1; k < K; k++)
        for (int p = 0; p < P; p++) a[p] += q[k] * B[(long)k * P + p];
    for (int p = 0; p < P; p++) {
        double ap = a[p], e = 1.0 / (hoop2[p] * (radial2[p] + ap * ap));
        a[p] = 2.0 * ap * (1.0 - e * e * hoop2[p]) * w[p];
    }
    for (int k = 0; k < K; k++) {
        double acc = 0.0;
        for (int p = 0; p < P; p++) acc += a[p] * B[(long)k * P + p];
        g[k] = acc;
    }
}

#endif
