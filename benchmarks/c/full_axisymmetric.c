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
 * RK4: y = (q, v), q'' = -omega0^2 Minv g(q) - damping v (Minv the inverse mass block per field, 2 x N x N).
 * Hessian (model/full/axisymmetric_kernels.py, axisymmetric_hessian): with x = (a1r, dw, a2t), the
 * moduli d = W_DD tD tD' + 2 W_T I + W_D d2Delta (neo-Hookean: W_TT = W_TD = 0, W_DD = 2/D^3),
 * tD = 2 (x0 n2, x1 n2, x2 n1); U_k moves x by (dphi_kp, 0, phi_kp / s_p), W_k by (0, dphi_kp, 0):
 *   H += sw_p (dx/dq_k)' d (dx/dq_m).
 * Usage: full_axisymmetric TABLES_FILE N P Q_FILE REPEATS STEPS DT OUT_FILE
 * TABLES_FILE: phi (P x N), dphi (P x N) (a point's values contiguous), s, sw, w, r0, dr0 (P each),
 * Minv (2 x N x N: U then W), omega0^2, damping.
 * Q_FILE: (M, 2N) float64 states q.  OUT_FILE receives g (M, 2N), then the state (4N) after STEPS
 * RK4 steps of DT from (q_0, 0), then the Hessians (M, 2N, 2N).  Prints the time per call in ns of
 * the force, per RK4 step and per call of the Hessian.
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

static void hessian(const double *restrict q, int N, int P, const double *restrict phi, const double *restrict dphi,
                    const double *restrict s, const double *restrict sw, const double *restrict r0,
                    const double *restrict dr0, double *restrict H) {
    int dof = 2 * N;
    for (long i = 0; i < (long)dof * dof; i++) H[i] = 0.0;
    for (int p = 0; p < P; p++) {
        const double *f = phi + (long)p * N, *df = dphi + (long)p * N;
        double du = 0.0, u = 0.0, dw = 0.0;
        for (int k = 0; k < N; k++) {
            du += q[k] * df[k];
            u += q[k] * f[k];
            dw += q[N + k] * df[k];
        }
        double x0 = dr0[p] + du, x1 = dw, x2 = (r0[p] + u) / s[p];
        double n1 = x0 * x0 + x1 * x1, n2 = x2 * x2, e = 1.0 / (n1 * n2);
        double w_t = 1.0, w_d = -e * e, w_dd = 2.0 * e * e * e;
        double tD[3] = {2.0 * x0 * n2, 2.0 * x1 * n2, 2.0 * x2 * n1}, d[3][3];
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) d[i][j] = w_dd * tD[i] * tD[j];
        for (int i = 0; i < 3; i++) d[i][i] += 2.0 * w_t;
        d[0][0] += w_d * 2.0 * n2;
        d[1][1] += w_d * 2.0 * n2;
        d[2][2] += w_d * 2.0 * n1;
        d[0][2] += w_d * 4.0 * x0 * x2;
        d[2][0] += w_d * 4.0 * x0 * x2;
        d[1][2] += w_d * 4.0 * x1 * x2;
        d[2][1] += w_d * 4.0 * x1 * x2;
        double c = sw[p], inv_s = 1.0 / s[p];
        for (int k = 0; k < N; k++) {
            double ak = df[k], bk = f[k] * inv_s;
            double ru0 = c * (d[0][0] * ak + d[2][0] * bk), ru1 = c * (d[0][1] * ak + d[2][1] * bk),
                   ru2 = c * (d[0][2] * ak + d[2][2] * bk);
            double rw0 = c * d[1][0] * ak, rw1 = c * d[1][1] * ak, rw2 = c * d[1][2] * ak;
            double *uu = H + (long)k * dof, *wu = H + (long)(N + k) * dof;
            for (int m = 0; m < N; m++) {
                double al = df[m], bl = f[m] * inv_s;
                uu[m] += ru0 * al + ru2 * bl;
                uu[N + m] += ru1 * al;
                wu[m] += rw0 * al + rw2 * bl;
                wu[N + m] += rw1 * al;
            }
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
            for (int j = 0; j < N; j++) acc += minv[((long)f * N + i) * N + j] * g[f * N + j];
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
    double omega0_2 = minv[2L * N * N], damping = minv[2L * N * N + 1];
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
    double *Hs = aligned_doubles(M * dof * dof);
    start = now();
    for (int r = 0; r < repeats; r++)
        for (long m = 0; m < M; m++) hessian(Q + m * dof, N, P, phi, dphi, s, sw, r0, dr0, Hs + m * dof * dof);
    double hessian_ns = (now() - start) / ((double)repeats * M) * 1e9;
    FILE *f = fopen(argv[8], "wb");
    if (!f) { perror(argv[8]); return 2; }
    fwrite(G, sizeof(double), M * dof, f);
    fwrite(y, sizeof(double), n, f);
    fwrite(Hs, sizeof(double), M * dof * dof, f);
    fclose(f);
    printf("%.3f %.3f %.3f\n", force_ns, step_ns, hessian_ns);
    return 0;
}
