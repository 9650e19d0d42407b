/* The quadrature force and force + Jacobian of model/rom.py for axisymmetric mode sets, in
 * C: the hardware reference of benchmarks/bench_force.py (compiled there with
 * -O3 -march=native -ffast-math, the freedom the numba kernels' fastmath has).
 *
 * Same algorithm as model.rom.axisymmetric_force and axisymmetric_force_jacobian: the slope
 * a_p = sum_k q_k B_kp at every quadrature point, D = r2 (dr2 + a^2), s = rho2 / D^2, then
 *   g_k = sum_p 2 a (1 - s r2) w B_kp                                   (force)
 *   J_kl = sum_p (2 - 2 s r2 + 8 s / D r2^2 a^2) w B_kp B_lp             (Jacobian)
 * in one pass over the points for the fused variant; restrict pointers.
 * Usage: force_jacobian TABLES_FILE K P Q_FILE REPEATS OUT_FILE
 * TABLES_FILE: weight, rho2, r2, dr2 (P each) then B (K x P), float64.
 * Q_FILE: (M, K) float64.  OUT_FILE receives g (M, K) then J (M, K, K).
 * Prints the time per call in ns of the force and of the force + Jacobian.
 */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "axisymmetric_force.h"
#include "read_doubles.h"

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static void force_jacobian(const double *restrict q, int K, int P, const double *restrict w,
                           const double *restrict rho2, const double *restrict r2, const double *restrict dr2,
                           const double *restrict B, double *restrict a, double *restrict fa,
                           double *restrict iaa, double *restrict g, double *restrict J) {
    for (int p = 0; p < P; p++) a[p] = q[0] * B[p];
    for (int k = 1; k < K; k++)
        for (int p = 0; p < P; p++) a[p] += q[k] * B[(long)k * P + p];
    for (int p = 0; p < P; p++) {
        double ap = a[p], D = r2[p] * (dr2[p] + ap * ap), s = rho2[p] / (D * D);
        fa[p] = 2.0 * ap * (1.0 - s * r2[p]) * w[p];
        iaa[p] = (2.0 - 2.0 * s * r2[p] + 8.0 * s / D * r2[p] * r2[p] * ap * ap) * w[p];
    }
    for (int k = 0; k < K; k++) {
        const double *bk = B + (long)k * P;
        double acc = 0.0;
        for (int p = 0; p < P; p++) acc += fa[p] * bk[p];
        g[k] = acc;
        for (int l = k; l < K; l++) {
            const double *bl = B + (long)l * P;
            double s = 0.0;
            for (int p = 0; p < P; p++) s += iaa[p] * bk[p] * bl[p];
            J[k * K + l] = s;
            J[l * K + k] = s;
        }
    }
}

int main(int argc, char **argv) {
    if (argc != 7) { fprintf(stderr, "usage: %s TABLES K P Q REPEATS OUT\n", argv[0]); return 2; }
    long n;
    double *tables = read_doubles(argv[1], &n);
    int K = atoi(argv[2]), P = atoi(argv[3]), repeats = atoi(argv[5]);
    double *w = tables, *rho2 = tables + P, *r2 = tables + 2 * P, *dr2 = tables + 3 * P, *B = tables + 4 * P;
    long nq;
    double *Q = read_doubles(argv[4], &nq);
    long M = nq / K;
    double *a = malloc(P * sizeof(double)), *fa = malloc(P * sizeof(double)), *iaa = malloc(P * sizeof(double));
    double *G = malloc(M * K * sizeof(double)), *JJ = malloc(M * K * K * sizeof(double));
    double sink = 0.0;
    double t0 = now();
    for (int r = 0; r < repeats; r++)
        for (long m = 0; m < M; m++) { force(Q + m * K, K, P, w, rho2, r2, dr2, B, a, G + m * K); sink += G[m * K]; }
    double t1 = now();
    for (int r = 0; r < repeats; r++)
        for (long m = 0; m < M; m++) {
            force_jacobian(Q + m * K, K, P, w, rho2, r2, dr2, B, a, fa, iaa, G + m * K, JJ + m * K * K);
            sink += JJ[m * K * K];
        }
    double t2 = now();
    FILE *out = fopen(argv[6], "wb");
    if (!out) { perror(argv[6]); return 2; }
    fwrite(G, sizeof(double), M * K, out);
    fwrite(JJ, sizeof(double), M * K * K, out);
    fclose(out);
    printf("%.3f %.3f %g\n", (t1 - t0) / (repeats * M) * 1e9, (t2 - t1) / (repeats * M) * 1e9, sink);
    return 0;
}
