/* The monodromy block of one asymmetric family of the full model along an axisymmetric orbit
 * (model/full/family_kernels.py), in C: the hardware reference of
 * benchmarks/bench_full_families.py (compiled there with -O3 -march=native -ffast-math, the
 * freedom the numba kernels' fastmath has).
 *
 * Neo-Hookean law in the trace T and determinant D of the metric: W_T = 1, W_D = -1/D^2,
 * W_TT = W_TD = 0, W_DD = 2/D^3.  Per RK4 stage, from the orbit's coordinates q = (U, W) on N
 * basis functions at that stage:
 *   per quadrature point p: x0 = dr0 + U.dphi, x1 = W.dphi, x2 = (r0 + U.phi) / s, the tangent
 *   moduli A (6 x 6) at a1 = (x0, 0, x1), a2 = (0, x2, 0), the 2 x 2 matrices
 *   C_ab = [g_a . A g_b] sw_p of every pair of the family's F fields (g: their variations per
 *   phi' and per phi / s), and K_ab[k, l] += [dpsi_k, psi_k / s] C_ab [dpsi_l, psi_l / s]^T
 *   over the family's M functions psi;
 *   then the stage's slopes of the block X (2m x 2m, m = F M): X_q' = X_v,
 *   X_v' = -omega0^2 Minv (K X_q) - rate X_v, Minv the inverse mass of one field (M x M).
 * Usage: full_families TABLES_FILE N P M F STAGES_FILE STEPS DT REPEATS OUT_FILE
 * TABLES_FILE: phi (P x N), dphi (P x N), psi (P x M), dpsi (P x M) (a point's values contiguous),
 * s, sw, r0, dr0 (P each), g (F x 2 x 6), Minv (M x M), omega0^2, rate.
 * STAGES_FILE: (STEPS, 4, 2N) the orbit's coordinates at the stages.  OUT_FILE receives the
 * block (2m x 2m, row-major).  Prints the time per period in ns (the median of REPEATS runs).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "read_doubles.h"

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static void moduli(double x0, double x1, double x2, double A[6][6]) {
    double n1 = x0 * x0 + x1 * x1, n2 = x2 * x2, D = n1 * n2;
    double w_t = 1.0, w_d = -1.0 / (D * D), w_dd = 2.0 / (D * D * D);
    double t[3] = {2.0 * x0, 2.0 * x1, 2.0 * x2}, d[3] = {2.0 * n2 * x0, 2.0 * n2 * x1, 2.0 * n1 * x2};
    memset(A, 0, 36 * sizeof(double));
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) A[2 * i][2 * j] = w_dd * d[i] * d[j];
    for (int i = 0; i < 6; i++) A[i][i] += 2.0 * w_t;
    A[0][0] += w_d * 2.0 * n2;
    A[2][2] += w_d * 2.0 * n2;
    A[4][4] += w_d * 2.0 * n1;
    A[0][4] += w_d * 4.0 * x0 * x2; A[4][0] += w_d * 4.0 * x0 * x2;
    A[2][4] += w_d * 4.0 * x1 * x2; A[4][2] += w_d * 4.0 * x1 * x2;
    A[3][3] += w_d * 2.0 * x1 * x1;
    A[5][5] += w_d * 2.0 * x0 * x0;
    A[3][5] -= w_d * 2.0 * x0 * x1; A[5][3] -= w_d * 2.0 * x0 * x1;
    A[1][3] -= w_d * 2.0 * x0 * x2; A[3][1] -= w_d * 2.0 * x0 * x2;
    A[1][5] -= w_d * 2.0 * x1 * x2; A[5][1] -= w_d * 2.0 * x1 * x2;
}

typedef struct {
    int N, P, M, F;
    const double *phi, *dphi, *psi, *dpsi, *s, *sw, *r0, *dr0, *g, *minv;
    double omega0_2, rate;
} Tables;

static void stiffness(const Tables *t, const double *restrict q, double *restrict K) {
    int N = t->N, M = t->M, F = t->F, m = F * M;
    double A[6][6], C[3][3][2][2];
    for (long i = 0; i < (long)m * m; i++) K[i] = 0.0;
    for (int p = 0; p < t->P; p++) {
        const double *ph = t->phi + (long)p * N, *dph = t->dphi + (long)p * N;
        double du = 0.0, u = 0.0, dw = 0.0;
        for (int k = 0; k < N; k++) {
            du += q[k] * dph[k];
            u += q[k] * ph[k];
            dw += q[N + k] * dph[k];
        }
        moduli(t->dr0[p] + du, dw, (t->r0[p] + u) / t->s[p], A);
        for (int a = 0; a < F; a++)
            for (int b = 0; b < F; b++)
                for (int i = 0; i < 2; i++)
                    for (int j = 0; j < 2; j++) {
                        const double *ga = t->g + (a * 2 + i) * 6, *gb = t->g + (b * 2 + j) * 6;
                        double acc = 0.0;
                        for (int x = 0; x < 6; x++)
                            for (int y = 0; y < 6; y++) acc += ga[x] * A[x][y] * gb[y];
                        C[a][b][i][j] = acc * t->sw[p];
                    }
        double inv_s = 1.0 / t->s[p];
        const double *ps = t->psi + (long)p * M, *dps = t->dpsi + (long)p * M;
        for (int a = 0; a < F; a++)
            for (int b = a; b < F; b++)
                for (int k = 0; k < M; k++) {
                    double pk = ps[k] * inv_s;
                    double l1 = C[a][b][0][0] * dps[k] + C[a][b][1][0] * pk;
                    double l2 = C[a][b][0][1] * dps[k] + C[a][b][1][1] * pk;
                    double *row = K + (long)(a * M + k) * m + b * M;
                    for (int l = 0; l < M; l++) row[l] += l1 * dps[l] + l2 * ps[l] * inv_s;
                }
    }
    for (int a = 0; a < F; a++)
        for (int b = a + 1; b < F; b++)
            for (int k = 0; k < M; k++)
                for (int l = 0; l < M; l++) K[(long)(b * M + l) * m + a * M + k] = K[(long)(a * M + k) * m + b * M + l];
}

/* out (2m x n) = slopes of the block X (2m x n): (X_v, -omega0^2 Minv K X_q - rate X_v) */
static void slopes(const Tables *t, const double *restrict K, const double *restrict X, double *restrict force,
                   double *restrict out) {
    int M = t->M, F = t->F, m = F * M, n = 2 * m;
    for (long i = 0; i < (long)m * n; i++) out[i] = X[(long)m * n + i];
    for (int i = 0; i < m; i++) {
        double *fr = force + (long)i * n;
        for (int c = 0; c < n; c++) fr[c] = 0.0;
        for (int k = 0; k < m; k++) {
            double kik = K[(long)i * m + k];
            const double *xr = X + (long)k * n;
            for (int c = 0; c < n; c++) fr[c] += kik * xr[c];
        }
    }
    for (int a = 0; a < F; a++)
        for (int i = 0; i < M; i++) {
            double *o = out + (long)(m + a * M + i) * n;
            const double *v = X + (long)(m + a * M + i) * n;
            for (int c = 0; c < n; c++) o[c] = -t->rate * v[c];
            for (int j = 0; j < M; j++) {
                double w = -t->omega0_2 * t->minv[(long)i * M + j];
                const double *fr = force + (long)(a * M + j) * n;
                for (int c = 0; c < n; c++) o[c] += w * fr[c];
            }
        }
}

static void monodromy(const Tables *t, const double *stages, int steps, double dt, double *big, double *work) {
    int m = t->F * t->M, n = 2 * m;
    long nn = (long)n * n;
    double *K = work, *force = K + (long)m * m, *ps = force + (long)m * n, *kp = ps + nn;
    static const double offset[4] = {0.0, 0.5, 0.5, 1.0}, weight[4] = {1.0, 2.0, 2.0, 1.0};
    for (long i = 0; i < nn; i++) big[i] = 0.0;
    for (int i = 0; i < n; i++) big[(long)i * n + i] = 1.0;
    for (int step = 0; step < steps; step++) {
        for (int i = 0; i < 4; i++) {
            for (long j = 0; j < nn; j++) ps[j] = i == 0 ? big[j] : big[j] + offset[i] * dt * kp[(long)(i - 1) * nn + j];
            stiffness(t, stages + ((long)step * 4 + i) * 2 * t->N, K);
            slopes(t, K, ps, force, kp + (long)i * nn);
        }
        for (long j = 0; j < nn; j++)
            big[j] += dt / 6.0 * (weight[0] * kp[j] + weight[1] * kp[nn + j] + weight[2] * kp[2 * nn + j]
                                  + weight[3] * kp[3 * nn + j]);
    }
}

static int compare(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv) {
    if (argc != 11) {
        fprintf(stderr, "usage: %s TABLES_FILE N P M F STAGES_FILE STEPS DT REPEATS OUT_FILE\n", argv[0]);
        return 2;
    }
    Tables t;
    t.N = atoi(argv[2]); t.P = atoi(argv[3]); t.M = atoi(argv[4]); t.F = atoi(argv[5]);
    int steps = atoi(argv[7]), repeats = atoi(argv[9]);
    double dt = atof(argv[8]);
    long nt, ns;
    double *tab = read_doubles(argv[1], &nt), *stages = read_doubles(argv[6], &ns);
    int N = t.N, P = t.P, M = t.M, F = t.F, m = F * M, n = 2 * m;
    t.phi = tab; t.dphi = t.phi + (long)P * N; t.psi = t.dphi + (long)P * N; t.dpsi = t.psi + (long)P * M;
    t.s = t.dpsi + (long)P * M; t.sw = t.s + P; t.r0 = t.sw + P; t.dr0 = t.r0 + P; t.g = t.dr0 + P;
    t.minv = t.g + F * 12; t.omega0_2 = t.minv[(long)M * M]; t.rate = t.minv[(long)M * M + 1];
    double *big = aligned_doubles((long)n * n);
    double *work = aligned_doubles((long)m * m + (long)m * n + 5L * n * n);
    double *times = aligned_doubles(repeats);
    for (int r = 0; r < repeats; r++) {
        double start = now();
        monodromy(&t, stages, steps, dt, big, work);
        times[r] = (now() - start) * 1e9;
    }
    qsort(times, repeats, sizeof(double), compare);
    FILE *f = fopen(argv[10], "wb");
    if (!f) { perror(argv[10]); return 2; }
    fwrite(big, sizeof(double), (long)n * n, f);
    fclose(f);
    printf("%.1f\n", times[repeats / 2]);
    return 0;
}
