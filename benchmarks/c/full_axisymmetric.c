/* The axisymmetric force and RK4 free motion of the full model (model/full/axisymmetric_kernels.py),
 * in C: the hardware reference of benchmarks/bench_full_axisymmetric.py (compiled there with
 * -O3 -march=native -ffast-math, the freedom the numba kernels' fastmath has).
 *
 * Neo-Hookean law in the trace T and determinant D of the metric: W_T = 1, W_D = -1/D^2.
 * Per quadrature point p, with q = (U, W) on N basis functions:
 *   du = sum_k U_k dphi_kp, u = sum_k U_k phi_kp, dw = sum_k W_k dphi_kp,
 *   a1r = dr0_p + du, a2t = (r0_p + u) / s_p, n1 = a1r^2 + dw^2, n2 = a2t^2, e = 1/(n1 n2),
 *   f1 = 2 (1 - e^2 n2) sw_p, f2 = 2 (1 - e^2 n1) a2t w_p,
 *   g_U,k += f1 a1r dphi_kp + f2 phi_kp,   g_W,k += f1 dw dphi_kp.
 * RK4: y = (q, v), q'' = -omega0^2 Minv g(q) - damping v (Minv the inverse mass block, N x N).
 * Usage: full_axisymmetric TABLES_FILE N P Q_FILE REPEATS STEPS DT OUT_FILE
 * TABLES_FILE: phi (P x N), dphi (P x N) (a point's values contiguous), s, sw, w, r0, dr0 (P each),
 * Minv (N x N), omega0^2, damping.
 * Q_FILE: (M, 2N) float64 states q.  OUT_FILE receives g (M, 2N), then the state (4N) after STEPS
 * RK4 steps of DT from (q_0, 0).  Prints the time per call in ns of the force and per RK4 step.
 */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "read_doubles.h"

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static void gradient(const double *restrict q, int N, int P, const double *restrict phi, const double *restrict dphi,
                     const double *restrict s, const double *restrict sw, const double *restrict w,
                     const double *restrict r0, const double *restrict dr0, double *restrict g) {
    for (int k = 0; k < 2 * N; k++) g[k] = 0.0;
    for (int p = 0; p < P; p++) {
        double du = 0.0, u = 0.0, dw = 0.0;
        for (int k = 0; k < N; k++) {
            du += q[k] * dphi[(long)p * N + k];
            u += q[k] * phi[(long)p * N + k];
            dw += q[N + k] * dphi[(long)p * N + k];
        }
        double a1r = dr0[p] + du, a2t = (r0[p] + u) / s[p];
        double n1 = a1r * a1r + dw * dw, n2 = a2t * a2t, e = 1.0 / (n1 * n2);
        double f1 = 2.0 * (1.0 - e * e * n2) * sw[p], f2 = 2.0 * (1.0 - e * e * n1) * a2t * w[p];
        double gr = f1 * a1r, gz = f1 * dw;
        for (int k = 0; k < N; k++) {
            g[k] += gr * dphi[(long)p * N + k] + f2 * phi[(long)p * N + k];
            g[N + k] += gz * dphi[(long)p * N + k];
        }
    }
}

static void rhs(const double *restrict y, int N, int P, const double *restrict phi, const double *restrict dphi,
                const double *restrict s, const double *restrict sw, const double *restrict w, const double *restrict r0,
                const double *restrict dr0, const double *restrict minv, double omega0_2, double damping,
                double *restrict g, double *restrict out) {
    int dof = 2 * N;
    gradient(y, N, P, phi, dphi, s, sw, w, r0, dr0, g);
    for (int i = 0; i < dof; i++) out[i] = y[dof + i];
    for (int f = 0; f < 2; f++)
        for (int i = 0; i < N; i++) {
            double acc = 0.0;
            for (int j = 0; j < N; j++) acc += minv[(long)i * N + j] * g[f * N + j];
            out[dof + f * N + i] = -omega0_2 * acc - damping * y[dof + f * N + i];
        }
}

int main(int argc, char **argv) {
    if (argc != 9) {
        fprintf(stderr, "usage: %s TABLES_FILE N P Q_FILE REPEATS STEPS DT OUT_FILE\n", argv[0]);
        return 2;
    }
    int N = atoi(argv[2]), P = atoi(argv[3]), repeats = atoi(argv[5]), steps = atoi(argv[6]);
    double dt = atof(argv[7]);
    long nt, nq;
    double *t = read_doubles(argv[1], &nt), *Q = read_doubles(argv[4], &nq);
    const double *phi = t, *dphi = t + (long)P * N, *s = dphi + (long)N * P, *sw = s + P, *w = sw + P, *r0 = w + P,
                 *dr0 = r0 + P, *minv = dr0 + P;
    double omega0_2 = minv[(long)N * N], damping = minv[(long)N * N + 1];
    int dof = 2 * N;
    long M = nq / dof;
    double *G = aligned_doubles(M * dof), *g = aligned_doubles(dof);
    double start = now();
    for (int r = 0; r < repeats; r++)
        for (long m = 0; m < M; m++) gradient(Q + m * dof, N, P, phi, dphi, s, sw, w, r0, dr0, G + m * dof);
    double force_ns = (now() - start) / ((double)repeats * M) * 1e9;
    int n = 2 * dof;
    double *y = aligned_doubles(n), *stage = aligned_doubles(n), *k = aligned_doubles(4L * n);
    for (int i = 0; i < n; i++) y[i] = i < dof ? Q[i] : 0.0;
    static const double offset[4] = {0.0, 0.5, 0.5, 1.0}, weight[4] = {1.0, 2.0, 2.0, 1.0};
    start = now();
    for (int step = 0; step < steps; step++) {
        for (int i = 0; i < 4; i++) {
            for (int j = 0; j < n; j++) stage[j] = i == 0 ? y[j] : y[j] + offset[i] * dt * k[(long)(i - 1) * n + j];
            rhs(stage, N, P, phi, dphi, s, sw, w, r0, dr0, minv, omega0_2, damping, g, k + (long)i * n);
        }
        for (int j = 0; j < n; j++)
            y[j] += dt / 6.0 * (weight[0] * k[j] + weight[1] * k[n + j] + weight[2] * k[2L * n + j] + weight[3] * k[3L * n + j]);
    }
    double step_ns = (now() - start) / (double)steps * 1e9;
    FILE *f = fopen(argv[8], "wb");
    if (!f) { perror(argv[8]); return 2; }
    fwrite(G, sizeof(double), M * dof, f);
    fwrite(y, sizeof(double), n, f);
    fclose(f);
    printf("%.3f %.3f\n", force_ns, step_ns);
    return 0;
}
