/* Shared by the C reference programs of benchmarks/: the quadrature force of
 * model.rom.general_force for any mode set (w_theta terms included).  The slopes
 * a_p = sum_k q_k B_kp, b_p = sum_k q_k T_kp at every quadrature point,
 * D = dr2 r2 + dr2 b^2 + r2 a^2, u = 1 / (rho2 D^2) (the one division: s = rho2 / D^2 =
 * rho2^2 u, 1 / rho2 = D^2 u), then g_k = sum_p 2 a (1 - s r2) w B_kp + 2 b (1 / rho2 -
 * s dr2) w T_kp (a, b: P work values each; restrict pointers, loops over the points
 * innermost). */
#ifndef GENERAL_FORCE_H
#define GENERAL_FORCE_H

static void project(const double *restrict q, int K, int P, const double *restrict basis, double *restrict out) {
    for (int p = 0; p < P; p++) out[p] = q[0] * basis[p];
    for (int k = 1; k < K; k++)
        for (int p = 0; p < P; p++) out[p] += q[k] * basis[(long)k * P + p];
}

static void general_force(const double *restrict q, int K, int P, const double *restrict w, const double *restrict rho2,
                  const double *restrict r2, const double *restrict dr2, const double *restrict B,
                  const double *restrict T, double *restrict a, double *restrict b, double *restrict g) {
    project(q, K, P, B, a);
    project(q, K, P, T, b);
    for (int p = 0; p < P; p++) {
        double ap = a[p], bp = b[p];
        double D = dr2[p] * r2[p] + dr2[p] * bp * bp + r2[p] * ap * ap;
        double u = 1.0 / (rho2[p] * D * D), s = rho2[p] * rho2[p] * u; /* one division */
        a[p] = 2.0 * ap * (1.0 - s * r2[p]) * w[p];
        b[p] = 2.0 * bp * (D * D * u - s * dr2[p]) * w[p];
    }
    for (int k = 0; k < K; k++) {
        const double *bk = B + (long)k * P, *tk = T + (long)k * P;
        double acc = 0.0;
        for (int p = 0; p < P; p++) acc += a[p] * bk[p] + b[p] * tk[p];
        g[k] = acc;
    }
}

#endif
