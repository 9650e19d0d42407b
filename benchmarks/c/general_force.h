/* Shared by the C reference programs of benchmarks/: the quadrature force of
 * model.rom.general_force for any mode set (w_theta terms included).  The slopes
 * a_p = sum_k q_k B_kp, b_p = sum_k q_k T_kp at every quadrature point,
 * the determinant of the in-plane metric delta = hoop2 (radial2 + a^2) + radial2 b^2 inv_rho2
 * and e = 1 / delta (the one division), then (the neo-Hookean law) g_k = sum_p 2 a (1 - e^2
 * hoop2) w B_kp + 2 b inv_rho2 (1 - e^2 radial2) w T_kp (a, b: P work values each; restrict
 * pointers, loops over the points innermost). */
#ifndef GENERAL_FORCE_H
#define GENERAL_FORCE_H

static void project(const double *restrict q, int K, int P, const double *restrict basis, double *restrict out) {
    for (int p = 0; p < P; p++) out[p] = q[0] * basis[p];
    for (int k = 1; k < K; k++)
        for (int p = 0; p < P; p++) out[p] += q[k] * basis[(long)k * P + p];
}

static void general_force(const double *restrict q, int K, int P, const double *restrict w, const double *restrict inv_rho2,
                  const double *restrict hoop2, const double *restrict radial2, const double *restrict B,
                  const double *restrict T, double *restrict a, double *restrict b, double *restrict g) {
    project(q, K, P, B, a);
    project(q, K, P, T, b);
    for (int p = 0; p < P; p++) {
        double ap = a[p], bp = b[p];
        double bt = bp * inv_rho2[p];
        double e = 1.0 / (hoop2[p] * (radial2[p] + ap * ap) + radial2[p] * bp * bt); /* one division */
        a[p] = 2.0 * ap * (1.0 - e * e * hoop2[p]) * w[p];
        b[p] = 2.0 * bt * (1.0 - e * e * radial2[p]) * w[p];
    }
    for (int k = 0; k < K; k++) {
        const double *bk = B + (long)k * P, *tk = T + (long)k * P;
        double acc = 0.0;
        for (int p = 0; p < P; p++) acc += a[p] * bk[p] + b[p] * tk[p];
        g[k] = acc;
    }
}

#endif
