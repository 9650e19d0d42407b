/* RK4 of the ROM with the quadrature force, in C: the hardware reference of
 * benchmarks/bench_rk4_quadrature.py (compiled there with -O3 -march=native -ffast-math,
 * the freedom the numba kernels' fastmath has).
 *
 * Same algorithm as the numba kernels: y = (q, q'), four stages per step, at each stage the
 * slope a_p = sum_k q_k B_kp at every quadrature point, the determinant of the in-plane
 * metric delta = hoop2 (radial2 + a^2), g_k = sum_p 2 a (1 - hoop2 / delta^2) w B_kp for
 * axisymmetric mode sets (the neo-Hookean law); with w_theta terms (tables with T = b_theta)
 * the slopes b_p = sum_k q_k T_kp too, delta = hoop2 (radial2 + a^2) + radial2 b^2 inv_rho2
 * and g_k = sum_p 2 a (1 - hoop2 / delta^2) w B_kp + 2 b inv_rho2 (1 - radial2 / delta^2)
 * w T_kp (model.rom.general_force and the general branch of the lock-step kernel); and
 *   q'' = -c q' - k_force g + P0 cos(Omega t) load.
 *   mode 0, "scalar":   one trajectory at a time (model.integrate._rk4_quadrature with
 *                       model.rom.axisymmetric_force or general_force: the force
 *                       vectorises over the points);
 *   mode 1, "lockstep": blocks of WIDTH trajectories, one per column, every inner loop over
 *                       the block (model.integrate.rk4_quadrature_lockstep), restrict pointers.
 * Compiled with -DFIXED_K=<K>, the lock-step force is one loop over the block per quadrature
 * point with the K modes unrolled (slope, force and its K shares in registers): the same
 * arithmetic for one mode count only, a bound on what the loops of mode 1 can reach.
 * Usage: rk4_quadrature MODE WIDTH TABLES K P STATES STEPS PERIODS H C_DAMP P0 OMEGA OUT
 * TABLES: weight, inv_rho2, hoop2, radial2 (P each), B (K x P), k_force (K), load (K), and for the
 * general kernels T (K x P), float64 (the file's size says which; not with FIXED_K).
 * STATES: (M, 2K) float64 initial states; OUT receives the final states.
 * Prints the time per step and trajectory in ns.
 */
#include <math.h>
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

typedef struct {
    int K, P;
    QuadratureTables tab;
    const double *T; /* b_theta (K x P), NULL for an axisymmetric set */
    double h, c_damp, p_load, omega;
} Model;

static void scalar(double *y, const Model *m, int steps, double *a, double *b, double *g, double *tmp,
                   double *stages) {
    int K = m->K, n = 2 * K;
    double t = 0.0;
    for (int step = 0; step < steps; step++) {
        for (int s = 0; s < 4; s++) {
            double f = s == 0 ? 0.0 : (s == 3 ? m->h : 0.5 * m->h);
            for (int i = 0; i < n; i++) tmp[i] = s == 0 ? y[i] : y[i] + f * stages[(s - 1) * n + i];
            if (m->T)
                general_force(tmp, K, m->P, m->tab.w, m->tab.inv_rho2, m->tab.hoop2, m->tab.radial2, m->tab.B, m->T, a, b, g);
            else
                force(tmp, K, m->P, m->tab.w, m->tab.inv_rho2, m->tab.hoop2, m->tab.radial2, m->tab.B, a, g);
            double pt = m->p_load * cos(m->omega * (t + f));
            for (int i = 0; i < K; i++) {
                stages[s * n + i] = tmp[K + i];
                stages[s * n + K + i] = -m->c_damp * tmp[K + i] - m->tab.k_force[i] * g[i] + pt * m->tab.load[i];
            }
        }
        for (int i = 0; i < n; i++)
            y[i] += m->h / 6.0 * (stages[i] + 2.0 * stages[n + i] + 2.0 * stages[2 * n + i] + stages[3 * n + i]);
        t += m->h;
    }
}

#ifndef FIXED_K
/* acc[k, b] += the general quadrature force (w_theta terms) of column b of ys (the
 * general branch of lockstep); sa, sb: (W) work. */
static void general_forces(const double *restrict ys, int W, const Model *m, double *restrict acc,
                           double *restrict sa, double *restrict sb) {
    int K = m->K, P = m->P;
    const double *restrict B = m->tab.B, *restrict T = m->T;
    for (int p = 0; p < P; p++) {
        for (int b = 0; b < W; b++) {
            sa[b] = ys[b] * B[p];
            sb[b] = ys[b] * T[p];
        }
        for (int k = 1; k < K; k++) {
            double bk = B[(long)k * P + p], tk = T[(long)k * P + p];
            for (int b = 0; b < W; b++) {
                sa[b] += ys[k * W + b] * bk;
                sb[b] += ys[k * W + b] * tk;
            }
        }
        double w2 = 2.0 * m->tab.w[p], hoop2 = m->tab.hoop2[p], radial2 = m->tab.radial2[p];
        double inv_rho2 = m->tab.inv_rho2[p];
        for (int b = 0; b < W; b++) {
            double a = sa[b], c = sb[b], ct = c * inv_rho2, e = 1.0 / (hoop2 * (radial2 + a * a) + radial2 * c * ct);
            sa[b] = w2 * a * (1.0 - e * e * hoop2);
            sb[b] = w2 * ct * (1.0 - e * e * radial2);
        }
        for (int k = 0; k < K; k++) {
            double bk = B[(long)k * P + p], tk = T[(long)k * P + p];
            for (int b = 0; b < W; b++) acc[k * W + b] += sa[b] * bk + sb[b] * tk;
        }
    }
}

#endif

/* y: (2K, W) one trajectory per column; ys, dy: (2K, W), acc: (K, W), sa, sb: (W) work. */
static void lockstep(double *restrict y, int W, const Model *m, int steps, double *restrict ys,
                     double *restrict acc, double *restrict dy, double *restrict sa, double *restrict sb) {
    int K = m->K, n = 2 * K, P = m->P;
    const double *restrict B = m->tab.B;
    double h = m->h;
    for (int i = 0; i < steps; i++) {
        double t = i * h;
        for (int s = 0; s < 4; s++) {
            double f = s == 0 ? 0.0 : (s == 3 ? h : 0.5 * h);
            double ct = cos(m->omega * (t + f));
            if (s == 0) {
                for (int k = 0; k < n; k++)
                    for (int b = 0; b < W; b++) ys[k * W + b] = y[k * W + b];
            } else {
                for (int k = 0; k < K; k++)
                    for (int b = 0; b < W; b++) {
                        ys[k * W + b] = y[k * W + b] + f * ys[(K + k) * W + b];
                        ys[(K + k) * W + b] = y[(K + k) * W + b] + f * acc[k * W + b];
                    }
            }
            for (int k = 0; k < K; k++)
                for (int b = 0; b < W; b++) acc[k * W + b] = 0.0;
#ifdef FIXED_K
            (void)sa; /* the modes in registers: no work columns */
            (void)sb;
            for (int p = 0; p < P; p++) {
                double bk[FIXED_K];
                for (int k = 0; k < FIXED_K; k++) bk[k] = B[(long)k * P + p];
                double w2 = 2.0 * m->tab.w[p], hoop2 = m->tab.hoop2[p], radial2 = m->tab.radial2[p];
                for (int b = 0; b < W; b++) {
                    double a = 0.0;
                    for (int k = 0; k < FIXED_K; k++) a += ys[k * W + b] * bk[k];
                    double e = 1.0 / (hoop2 * (radial2 + a * a)), g = w2 * a * (1.0 - e * e * hoop2);
                    for (int k = 0; k < FIXED_K; k++) acc[k * W + b] += g * bk[k];
                }
            }
#else
            if (m->T) general_forces(ys, W, m, acc, sa, sb);
            else for (int p = 0; p < P; p++) {
                for (int b = 0; b < W; b++) sa[b] = ys[b] * B[p];
                for (int k = 1; k < K; k++) {
                    double bk = B[(long)k * P + p];
                    for (int b = 0; b < W; b++) sa[b] += ys[k * W + b] * bk;
                }
                double w2 = 2.0 * m->tab.w[p], hoop2 = m->tab.hoop2[p], radial2 = m->tab.radial2[p];
                for (int b = 0; b < W; b++) {
                    double a = sa[b], e = 1.0 / (hoop2 * (radial2 + a * a));
                    sa[b] = w2 * a * (1.0 - e * e * hoop2);
                }
                for (int k = 0; k < K; k++) {
                    double bk = B[(long)k * P + p];
                    for (int b = 0; b < W; b++) acc[k * W + b] += sa[b] * bk;
                }
            }
#endif
            double pt = m->p_load * ct;
            for (int k = 0; k < K; k++) {
                double kf = m->tab.k_force[k], lk = pt * m->tab.load[k];
                for (int b = 0; b < W; b++)
                    acc[k * W + b] = -m->c_damp * ys[(K + k) * W + b] - kf * acc[k * W + b] + lk;
            }
            double wt = (s == 0 || s == 3) ? 1.0 : 2.0;
            for (int k = 0; k < K; k++)
                for (int b = 0; b < W; b++) {
                    if (s == 0) {
                        dy[k * W + b] = ys[(K + k) * W + b];
                        dy[(K + k) * W + b] = acc[k * W + b];
                    } else {
                        dy[k * W + b] += wt * ys[(K + k) * W + b];
                        dy[(K + k) * W + b] += wt * acc[k * W + b];
                    }
                }
        }
        for (int k = 0; k < n; k++)
            for (int b = 0; b < W; b++) y[k * W + b] += h / 6.0 * dy[k * W + b];
    }
}

int main(int argc, char **argv) {
    if (argc != 14) {
        fprintf(stderr, "usage: %s MODE WIDTH TABLES K P STATES STEPS PERIODS H C_DAMP P0 OMEGA OUT\n", argv[0]);
        return 2;
    }
    int mode = atoi(argv[1]), width = atoi(argv[2]);
    long n_tab, n_states;
    double *tables = read_doubles(argv[3], &n_tab);
    Model m;
    m.K = atoi(argv[4]);
    m.P = atoi(argv[5]);
    int steps = atoi(argv[7]), periods = atoi(argv[8]);
    m.h = atof(argv[9]);
    m.c_damp = atof(argv[10]);
    m.p_load = atof(argv[11]);
    m.omega = atof(argv[12]);
    int K = m.K, P = m.P, n = 2 * K;
    long axisymmetric_size = 4L * P + (long)K * P + 2L * K;
    if (n_tab != axisymmetric_size && n_tab != axisymmetric_size + (long)K * P) {
        fprintf(stderr, "%s: %ld values for K = %d, P = %d\n", argv[3], n_tab, K, P);
        return 2;
    }
    m.tab = quadrature_tables(tables, K, P);
    m.T = n_tab == axisymmetric_size ? NULL : tables + axisymmetric_size;
#ifdef FIXED_K
    if (K != FIXED_K || m.T) {
        fprintf(stderr, "compiled for K = %d axisymmetric modes, got %d%s\n", FIXED_K, K, m.T ? " with w_theta" : "");
        return 2;
    }
#endif
    double *Y = read_doubles(argv[6], &n_states);
    long M = n_states / n;
    double *a = aligned_doubles(P), *b = aligned_doubles(P), *g = aligned_doubles(K), *tmp = aligned_doubles(n);
    double *stages = aligned_doubles(4L * n), *cols = aligned_doubles((long)n * width);
    double *ys = aligned_doubles((long)n * width), *dy = aligned_doubles((long)n * width);
    double *acc = aligned_doubles((long)K * width), *sa = aligned_doubles(width), *sb = aligned_doubles(width);
    double t0 = now();
    if (mode == 0) {
        for (long j = 0; j < M; j++)
            for (int period = 0; period < periods; period++) scalar(Y + j * n, &m, steps, a, b, g, tmp, stages);
    } else {
        for (long s0 = 0; s0 < M; s0 += width) {
            int W = M - s0 < width ? (int)(M - s0) : width;
            for (int b = 0; b < W; b++)
                for (int k = 0; k < n; k++) cols[k * W + b] = Y[(s0 + b) * n + k];
            for (int period = 0; period < periods; period++) lockstep(cols, W, &m, steps, ys, acc, dy, sa, sb);
            for (int b = 0; b < W; b++)
                for (int k = 0; k < n; k++) Y[(s0 + b) * n + k] = cols[k * W + b];
        }
    }
    double t1 = now();
    FILE *out = fopen(argv[13], "wb");
    if (!out) { perror(argv[13]); return 2; }
    fwrite(Y, sizeof(double), M * n, out);
    fclose(out);
    printf("%.3f\n", (t1 - t0) / ((double)M * periods * steps) * 1e9);
    return 0;
}
