/* The quadrature force and force + Jacobian of model/rom.py, in C: the hardware reference
 * of benchmarks/bench_force.py (compiled there with -O3 -march=native -ffast-math, the
 * freedom the numba kernels' fastmath has).
 *
 * The neo-Hookean law in the determinant of the in-plane metric, e = 1 / delta (the one
 * division per point; docs/model.md, "Transverse energy").
 * Axisymmetric mode sets: the algorithm of model.rom.axisymmetric_force and
 * axisymmetric_force_jacobian: the slope a_p = sum_k q_k B_kp at every quadrature point,
 * delta = hoop2 (radial2 + a^2), then
 *   g_k = sum_p 2 a (1 - e^2 hoop2) w B_kp                                   (force)
 *   J_kl = sum_p (2 - 2 e^2 hoop2 + 8 e^3 hoop2^2 a^2) w B_kp B_lp           (Jacobian)
 * in one pass over the points for the fused variant; three modes written out, one pass
 * over the points for both (as the numba kernels).
 * Any mode set (w_theta terms): the algorithm of model.rom.general_force and
 * general_force_jacobian: the slopes a_p = sum_k q_k B_kp, b_p = sum_k q_k T_kp,
 * bt = b inv_rho2, delta = hoop2 (radial2 + a^2) + radial2 b bt, per point
 *   fa = 2 a (1 - e^2 hoop2) w,  fb = 2 bt (1 - e^2 radial2) w                         (force)
 *   iaa = (2 - 2 e^2 hoop2 + 8 e^3 hoop2^2 a^2) w,  iab = 8 e^3 hoop2 radial2 a bt w,
 *   ibb = (2 inv_rho2 (1 - e^2 radial2) + 8 e^3 radial2^2 bt^2) w                    (Jacobian)
 * then g_k = sum_p fa B_kp + fb T_kp and
 * J_kl = sum_p iaa B_kp B_lp + iab (B_kp T_lp + T_kp B_lp) + ibb T_kp T_lp.
 * Restrict pointers, loops over the points innermost.
 * Usage: force_jacobian TABLES_FILE K P Q_FILE REPEATS OUT_FILE
 * TABLES_FILE: weight, inv_rho2, hoop2, radial2 (P each) then B = b_rho (K x P), and for the general
 * kernels T = b_theta (K x P), float64 (the file's size says which).
 * Q_FILE: (M, K) float64.  OUT_FILE receives g (M, K) then J (M, K, K).
 * Prints the time per call in ns of the force and of the force + Jacobian.
 */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "axisymmetric_force.h"
#include "general_force.h"
#include "read_doubles.h"

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static void force_jacobian(const double *restrict q, int K, int P, const double *restrict w,
                           const double *restrict inv_rho2, const double *restrict hoop2,
                           const double *restrict radial2, const double *restrict B, double *restrict a, double *restrict fa,
                           double *restrict iaa, double *restrict g, double *restrict J) {
    if (K == 3) { /* the three modes written out: one pass over the points, as the numba kernel */
        double g0 = 0.0, g1 = 0.0, g2 = 0.0, j00 = 0.0, j01 = 0.0, j02 = 0.0, j11 = 0.0, j12 = 0.0, j22 = 0.0;
        for (int p = 0; p < P; p++) {
            double c0 = B[p], c1 = B[P + p], c2 = B[2L * P + p];
            double ap = q[0] * c0 + q[1] * c1 + q[2] * c2, e = 1.0 / (hoop2[p] * (radial2[p] + ap * ap));
            double f = 2.0 * ap * (1.0 - e * e * hoop2[p]) * w[p];
            double ia = (2.0 - 2.0 * e * e * hoop2[p] + 8.0 * e * e * e * hoop2[p] * hoop2[p] * ap * ap) * w[p];
            g0 += f * c0;
            g1 += f * c1;
            g2 += f * c2;
            j00 += ia * c0 * c0;
            j01 += ia * c0 * c1;
            j02 += ia * c0 * c2;
            j11 += ia * c1 * c1;
            j12 += ia * c1 * c2;
            j22 += ia * c2 * c2;
        }
        g[0] = g0;
        g[1] = g1;
        g[2] = g2;
        J[0] = j00;
        J[1] = J[3] = j01;
        J[2] = J[6] = j02;
        J[4] = j11;
        J[5] = J[7] = j12;
        J[8] = j22;
        return;
    }
    for (int p = 0; p < P; p++) a[p] = q[0] * B[p];
    for (int k = 1; k < K; k++)
        for (int p = 0; p < P; p++) a[p] += q[k] * B[(long)k * P + p];
    for (int p = 0; p < P; p++) {
        double ap = a[p], e = 1.0 / (hoop2[p] * (radial2[p] + ap * ap));
        fa[p] = 2.0 * ap * (1.0 - e * e * hoop2[p]) * w[p];
        iaa[p] = (2.0 - 2.0 * e * e * hoop2[p] + 8.0 * e * e * e * hoop2[p] * hoop2[p] * ap * ap) * w[p];
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

static void general_force_jacobian(const double *restrict q, int K, int P, const double *restrict w,
                           const double *restrict inv_rho2, const double *restrict hoop2,
                           const double *restrict radial2, const double *restrict B, const double *restrict T, double *restrict a,
                           double *restrict b, double *restrict fa, double *restrict fb, double *restrict iaa,
                           double *restrict iab, double *restrict ibb, double *restrict g, double *restrict J) {
    project(q, K, P, B, a);
    project(q, K, P, T, b);
    for (int p = 0; p < P; p++) {
        double ap = a[p], bp = b[p];
        double bt = bp * inv_rho2[p];
        double e = 1.0 / (hoop2[p] * (radial2[p] + ap * ap) + radial2[p] * bp * bt); /* one division */
        double e2 = e * e, e3 = 8.0 * e2 * e;
        fa[p] = 2.0 * ap * (1.0 - e2 * hoop2[p]) * w[p];
        fb[p] = 2.0 * bt * (1.0 - e2 * radial2[p]) * w[p];
        iaa[p] = (2.0 - 2.0 * e2 * hoop2[p] + e3 * hoop2[p] * hoop2[p] * ap * ap) * w[p];
        iab[p] = e3 * hoop2[p] * radial2[p] * ap * bt * w[p];
        ibb[p] = (2.0 * inv_rho2[p] * (1.0 - e2 * radial2[p]) + e3 * radial2[p] * radial2[p] * bt * bt) * w[p];
    }
    for (int k = 0; k < K; k++) {
        const double *bk = B + (long)k * P, *tk = T + (long)k * P;
        double acc = 0.0;
        for (int p = 0; p < P; p++) acc += fa[p] * bk[p] + fb[p] * tk[p];
        g[k] = acc;
        for (int l = k; l < K; l++) {
            const double *bl = B + (long)l * P, *tl = T + (long)l * P;
            double s = 0.0;
            for (int p = 0; p < P; p++)
                s += iaa[p] * bk[p] * bl[p] + iab[p] * (bk[p] * tl[p] + tk[p] * bl[p]) + ibb[p] * tk[p] * tl[p];
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
    double *w = tables, *inv_rho2 = tables + P, *hoop2 = tables + 2L * P, *radial2 = tables + 3L * P,
           *B = tables + 4L * P;
    double *T = B + (long)K * P;
    int general = n == 4L * P + 2L * K * P; /* the tables carry b_theta */
    if (!general && n != 4L * P + (long)K * P) { fprintf(stderr, "%s: %ld values for K = %d, P = %d\n", argv[1], n, K, P); return 2; }
    long nq;
    double *Q = read_doubles(argv[4], &nq);
    long M = nq / K;
    double *work = aligned_doubles(7L * P);
    double *a = work, *b = work + P, *fa = work + 2L * P, *fb = work + 3L * P, *iaa = work + 4L * P,
           *iab = work + 5L * P, *ibb = work + 6L * P;
    double *G = aligned_doubles(M * K), *JJ = aligned_doubles(M * K * K);
    double sink = 0.0;
    double t0 = now();
    for (int r = 0; r < repeats; r++)
        for (long m = 0; m < M; m++) {
            if (general)
                general_force(Q + m * K, K, P, w, inv_rho2, hoop2, radial2, B, T, a, b, G + m * K);
            else
                force(Q + m * K, K, P, w, inv_rho2, hoop2, radial2, B, a, G + m * K);
            sink += G[m * K];
        }
    double t1 = now();
    for (int r = 0; r < repeats; r++)
        for (long m = 0; m < M; m++) {
            if (general)
                general_force_jacobian(Q + m * K, K, P, w, inv_rho2, hoop2, radial2, B, T, a, b, fa, fb, iaa, iab, ibb,
                                       G + m * K, JJ + m * K * K);
            else
                force_jacobian(Q + m * K, K, P, w, inv_rho2, hoop2, radial2, B, a, fa, iaa, G + m * K, JJ + m * K * K);
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
