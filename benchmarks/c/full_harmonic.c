/* The force, Hessian and RK4 free motion of the full model on circumferential harmonics
 * (model/full/harmonic_kernels.py), in C: the hardware reference of
 * benchmarks/bench_full_harmonic.py (compiled there with -O3 -march=native -ffast-math, the
 * freedom the numba kernels' fastmath has).
 *
 * The coordinates are B blocks of N coefficients; block b has a field (0: U on cos k theta,
 * 1: V on sin k theta, 2: W on cos k theta) and a harmonic k.  Per radial point p the blocks'
 * values and s-derivatives, then per angular point t the columns
 *   a1 = (dr0 + u_s, v_s, w_s),  a2 = ((u_t - v) / s, (r0 + u + v_t) / s, w_t / s),
 * the neo-Hookean law in the trace T and determinant D of the metric (W_T = 1, W_D = -1/D^2,
 * W_DD = 2/D^3), the first Piola stress P1 = 2 (W_T + W_D n2) a1 - 2 W_D c a2,
 * P2 = 2 (W_T + W_D n1) a2 - 2 W_D c a1, and its projection on each block's variations field by
 * field (U: P1_r cos per phi', P2_theta cos - k P2_r sin per phi / s; V: P1_theta sin,
 * k P2_theta cos - P2_r sin; W: P1_z cos, -k P2_z sin).
 * Hessian: the moduli A = W_DD dD dD' + 2 W_T I + W_D d2Delta at each (p, t), the angular sums
 * C_bc = sum_t w_t g_b' A g_c (2 x 2 per block pair; each g has at most two components, given
 * by their indices and values), then [phi', phi/s] C_bc [phi', phi/s]' s ds.
 * RK4: y = (q, v), q'' = -omega0^2 scale_b Minv g_b(q) - damping v, without the numba motion's
 * bias (the pre-stretch's rounding, 8e-13 s^-2 in units of Re at order 8).
 * Usage: full_harmonic TABLES_FILE N P T B Q_FILE REPEATS STEPS DT OUT_FILE
 * TABLES_FILE: phi (P x N), dphi (P x N), s, sw, w, r0, dr0 (P each), Minv (N x N), scale (B),
 * field (B), wave (B), cos (B x T), sin (B x T), theta weights (T), the variations' component
 * indices (B x 2 x 2) and values (B x T x 2 x 2), omega0^2, damping.  Q_FILE: (M, B N) float64 states q.  OUT_FILE receives g (M, B N), the state
 * (2 B N) after STEPS RK4 steps of DT from (q_0, 0), then the Hessians (M, B N, B N).  Prints the
 * time per call in ns of the force, per RK4 step and per call of the Hessian.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "read_doubles.h"

typedef struct {
    int N, P, T, B;
    const double *phi, *dphi, *s, *sw, *w, *r0, *dr0, *minv, *scale, *wave, *cs, *sn, *tw, *vv;
    int *field;
    long *vi;
    double omega0_2, damping;
} Tables;

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static void radial_values(const Tables *t, const double *restrict q, int p, double *restrict value,
                          double *restrict slope) {
    const double *f = t->phi + (long)p * t->N, *df = t->dphi + (long)p * t->N;
    for (int b = 0; b < t->B; b++) {
        double v = 0.0, d = 0.0;
        for (int j = 0; j < t->N; j++) {
            v += q[(long)b * t->N + j] * f[j];
            d += q[(long)b * t->N + j] * df[j];
        }
        value[b] = v;
        slope[b] = d;
    }
}

static void columns(const Tables *t, const double *restrict value, const double *restrict slope, int p, int k,
                    double *restrict a) {
    double u = 0, us = 0, ut = 0, v = 0, vs = 0, vt = 0, ws = 0, wt = 0, inv_s = 1.0 / t->s[p];
    for (int b = 0; b < t->B; b++) {
        double c = t->cs[(long)b * t->T + k], sn = t->sn[(long)b * t->T + k], kk = t->wave[b];
        int field = t->field[b];
        if (field == 0) {
            u += value[b] * c;
            us += slope[b] * c;
            ut -= kk * value[b] * sn;
        } else if (field == 1) {
            v += value[b] * sn;
            vs += slope[b] * sn;
            vt += kk * value[b] * c;
        } else {
            ws += slope[b] * c;
            wt -= kk * value[b] * sn;
        }
    }
    a[0] = t->dr0[p] + us;
    a[1] = vs;
    a[2] = ws;
    a[3] = (ut - v) * inv_s;
    a[4] = (t->r0[p] + u + vt) * inv_s;
    a[5] = wt * inv_s;
}

static void gradient(const Tables *t, const double *restrict q, double *restrict g, double *restrict work) {
    int B = t->B, N = t->N;
    double *value = work, *slope = work + B, *along1 = work + 2 * B, *along2 = work + 3 * B, a[6];
    memset(g, 0, sizeof(double) * (size_t)B * N);
    for (int p = 0; p < t->P; p++) {
        radial_values(t, q, p, value, slope);
        for (int b = 0; b < B; b++) along1[b] = along2[b] = 0.0;
        for (int k = 0; k < t->T; k++) {
            columns(t, value, slope, p, k, a);
            double n1 = a[0] * a[0] + a[1] * a[1] + a[2] * a[2], n2 = a[3] * a[3] + a[4] * a[4] + a[5] * a[5];
            double c = a[0] * a[3] + a[1] * a[4] + a[2] * a[5], e = 1.0 / (n1 * n2 - c * c), w_d = -e * e;
            double f1 = 2.0 * (1.0 + w_d * n2), f2 = 2.0 * (1.0 + w_d * n1), cross = -2.0 * w_d * c, tw = t->tw[k];
            double P[6];
            for (int i = 0; i < 3; i++) {
                P[i] = (f1 * a[i] + cross * a[3 + i]) * tw;
                P[3 + i] = (f2 * a[3 + i] + cross * a[i]) * tw;
            }
            for (int b = 0; b < B; b++) {
                double c = t->cs[(long)b * t->T + k], sn = t->sn[(long)b * t->T + k], kk = t->wave[b];
                int field = t->field[b];
                if (field == 0) {
                    along1[b] += P[0] * c;
                    along2[b] += P[4] * c - kk * P[3] * sn;
                } else if (field == 1) {
                    along1[b] += P[1] * sn;
                    along2[b] += kk * P[4] * c - P[3] * sn;
                } else {
                    along1[b] += P[2] * c;
                    along2[b] -= kk * P[5] * sn;
                }
            }
        }
        const double *f = t->phi + (long)p * N, *df = t->dphi + (long)p * N;
        for (int b = 0; b < B; b++) {
            double c1 = along1[b] * t->sw[p], c2 = along2[b] * t->w[p];
            for (int j = 0; j < N; j++) g[(long)b * N + j] += c1 * df[j] + c2 * f[j];
        }
    }
}

static void moduli(const double *restrict a, double A[6][6]) {
    double n1 = a[0] * a[0] + a[1] * a[1] + a[2] * a[2], n2 = a[3] * a[3] + a[4] * a[4] + a[5] * a[5];
    double c = a[0] * a[3] + a[1] * a[4] + a[2] * a[5], e = 1.0 / (n1 * n2 - c * c);
    double w_d = -e * e, w_dd = 2.0 * e * e * e, dD[6];
    for (int i = 0; i < 3; i++) {
        dD[i] = 2.0 * n2 * a[i] - 2.0 * c * a[3 + i];
        dD[3 + i] = 2.0 * n1 * a[3 + i] - 2.0 * c * a[i];
    }
    for (int i = 0; i < 6; i++) {
        for (int j = 0; j < 6; j++) A[i][j] = w_dd * dD[i] * dD[j];
        A[i][i] += 2.0;
    }
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            A[i][j] -= 2.0 * w_d * a[3 + i] * a[3 + j];
            A[3 + i][3 + j] -= 2.0 * w_d * a[i] * a[j];
            double cross = w_d * (4.0 * a[i] * a[3 + j] - 2.0 * a[3 + i] * a[j]);
            A[i][3 + j] += cross;
            A[3 + j][i] += cross;
        }
        A[i][i] += 2.0 * w_d * n2;
        A[3 + i][3 + i] += 2.0 * w_d * n1;
        A[i][3 + i] -= 2.0 * w_d * c;
        A[3 + i][i] -= 2.0 * w_d * c;
    }
}

static void hessian(const Tables *t, const double *restrict q, double *restrict H, double *restrict work) {
    int B = t->B, N = t->N, dof = B * N;
    double *value = work, *slope = work + B, *C = work + 2 * B, a[6], A[6][6];
    memset(H, 0, sizeof(double) * (size_t)dof * dof);
    for (int p = 0; p < t->P; p++) {
        radial_values(t, q, p, value, slope);
        memset(C, 0, sizeof(double) * 4L * B * B);
        for (int k = 0; k < t->T; k++) {
            columns(t, value, slope, p, k, a);
            moduli(a, A);
            for (int b = 0; b < B; b++)
                for (int alpha = 0; alpha < 2; alpha++) {
                    const long *ib = t->vi + ((long)b * 2 + alpha) * 2;
                    const double *vb = t->vv + (((long)b * t->T + k) * 2 + alpha) * 2;
                    double v0 = vb[0] * t->tw[k], v1 = vb[1] * t->tw[k];
                    for (int c = b; c < B; c++)
                        for (int beta = 0; beta < 2; beta++) {
                            const long *ic = t->vi + ((long)c * 2 + beta) * 2;
                            const double *vc = t->vv + (((long)c * t->T + k) * 2 + beta) * 2;
                            C[(((long)b * B + c) * 2 + alpha) * 2 + beta] +=
                                v0 * (A[ib[0]][ic[0]] * vc[0] + A[ib[0]][ic[1]] * vc[1]) +
                                v1 * (A[ib[1]][ic[0]] * vc[0] + A[ib[1]][ic[1]] * vc[1]);
                        }
                }
        }
        const double *f = t->phi + (long)p * N, *df = t->dphi + (long)p * N;
        double inv_s = 1.0 / t->s[p];
        for (int b = 0; b < B; b++)
            for (int c = b; c < B; c++) {
                const double *cc = C + ((long)b * B + c) * 4;
                double c11 = cc[0] * t->sw[p], c12 = cc[1] * t->w[p], c21 = cc[2] * t->w[p],
                       c22 = cc[3] * t->w[p] * inv_s;
                for (int j = 0; j < N; j++) {
                    double l1 = c11 * df[j] + c21 * f[j], l2 = c12 * df[j] + c22 * f[j];
                    double *row = H + ((long)b * N + j) * dof + (long)c * N;
                    for (int m = 0; m < N; m++) row[m] += l1 * df[m] + l2 * f[m];
                }
            }
    }
    for (int b = 0; b < B; b++)
        for (int c = b + 1; c < B; c++)
            for (int j = 0; j < N; j++)
                for (int m = 0; m < N; m++)
                    H[((long)c * N + m) * dof + (long)b * N + j] = H[((long)b * N + j) * dof + (long)c * N + m];
}

static void rhs(const Tables *t, const double *restrict y, double *restrict g, double *restrict work,
                double *restrict out) {
    int N = t->N, dof = t->B * N;
    gradient(t, y, g, work);
    for (int i = 0; i < dof; i++) out[i] = y[dof + i];
    for (int b = 0; b < t->B; b++) {
        double scale = t->omega0_2 * t->scale[b];
        for (int i = 0; i < N; i++) {
            double acc = 0.0;
            for (int j = 0; j < N; j++) acc += t->minv[(long)i * N + j] * g[(long)b * N + j];
            out[dof + b * N + i] = -scale * acc - t->damping * y[dof + b * N + i];
        }
    }
}

int main(int argc, char **argv) {
    if (argc != 11) {
        fprintf(stderr, "usage: %s TABLES_FILE N P T B Q_FILE REPEATS STEPS DT OUT_FILE\n", argv[0]);
        return 2;
    }
    Tables t;
    t.N = atoi(argv[2]);
    t.P = atoi(argv[3]);
    t.T = atoi(argv[4]);
    t.B = atoi(argv[5]);
    int repeats = atoi(argv[7]), steps = atoi(argv[8]), N = t.N, P = t.P, T = t.T, B = t.B;
    double dt = atof(argv[9]);
    long nt, nq;
    const double *x = read_doubles(argv[1], &nt);
    double *Q = read_doubles(argv[6], &nq);
    t.phi = x;
    t.dphi = t.phi + (long)P * N;
    t.s = t.dphi + (long)P * N;
    t.sw = t.s + P;
    t.w = t.sw + P;
    t.r0 = t.w + P;
    t.dr0 = t.r0 + P;
    t.minv = t.dr0 + P;
    t.scale = t.minv + (long)N * N;
    const double *field = t.scale + B;
    t.wave = field + B;
    t.cs = t.wave + B;
    t.sn = t.cs + (long)B * T;
    t.tw = t.sn + (long)B * T;
    const double *index = t.tw + T;
    t.vv = index + 4L * B;
    t.omega0_2 = t.vv[4L * B * T];
    t.damping = t.vv[4L * B * T + 1];
    t.field = malloc(sizeof(int) * B);
    t.vi = malloc(sizeof(long) * 4 * B);
    for (int b = 0; b < B; b++) t.field[b] = (int)field[b];
    for (int i = 0; i < 4 * B; i++) t.vi[i] = (long)index[i];
    int dof = B * N;
    long M = nq / dof;
    double *G = aligned_doubles(M * dof), *g = aligned_doubles(dof), *work = aligned_doubles(4L * B + 4L * B * B);
    double start = now();
    for (int r = 0; r < repeats; r++)
        for (long m = 0; m < M; m++) gradient(&t, Q + m * dof, G + m * dof, work);
    double force_ns = (now() - start) / ((double)repeats * M) * 1e9;
    int n = 2 * dof;
    double *y = aligned_doubles(n), *stage = aligned_doubles(n), *k = aligned_doubles(4L * n);
    for (int i = 0; i < n; i++) y[i] = i < dof ? Q[i] : 0.0;
    static const double offset[4] = {0.0, 0.5, 0.5, 1.0}, weight[4] = {1.0, 2.0, 2.0, 1.0};
    start = now();
    for (int step = 0; step < steps; step++) {
        for (int i = 0; i < 4; i++) {
            for (int j = 0; j < n; j++) stage[j] = i == 0 ? y[j] : y[j] + offset[i] * dt * k[(long)(i - 1) * n + j];
            rhs(&t, stage, g, work, k + (long)i * n);
        }
        for (int j = 0; j < n; j++)
            y[j] += dt / 6.0 * (weight[0] * k[j] + weight[1] * k[n + j] + weight[2] * k[2L * n + j] + weight[3] * k[3L * n + j]);
    }
    double step_ns = (now() - start) / (double)steps * 1e9;
    double *Hs = aligned_doubles(M * dof * dof);
    start = now();
    for (int r = 0; r < repeats; r++)
        for (long m = 0; m < M; m++) hessian(&t, Q + m * dof, Hs + m * dof * dof, work);
    double hessian_ns = (now() - start) / ((double)repeats * M) * 1e9;
    FILE *f = fopen(argv[10], "wb");
    if (!f) { perror(argv[10]); return 2; }
    fwrite(G, sizeof(double), M * dof, f);
    fwrite(y, sizeof(double), n, f);
    fwrite(Hs, sizeof(double), M * dof * dof, f);
    fclose(f);
    printf("%.3f %.3f %.3f\n", force_ns, step_ns, hessian_ns);
    return 0;
}
