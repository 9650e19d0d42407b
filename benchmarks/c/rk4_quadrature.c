/* RK4 of the ROM with the quadrature force for axisymmetric mode sets, in C: the hardware
 * reference of benchmarks/bench_rk4_quadrature.py (compiled there with -O3 -march=native
 * -ffast-math, the freedom the numba kernels' fastmath has).
 *
 * Same algorithm as model.integrate._rk4_quadrature with model.rom.axisymmetric_force:
 * y = (q, q'), four stages per step, at each stage the slope a_p = sum_k q_k B_kp at every
 * quadrature point, D = r2 (dr2 + a^2), g_k = sum_p 2 a (1 - rho2 r2 / D^2) w B_kp, and
 *   q'' = -c q' - k_force g + P0 cos(Omega t) load.
 * One trajectory at a time (the force vectorises over the quadrature points).
 * Usage: rk4_quadrature TABLES K P STATES STEPS PERIODS H C_DAMP P0 OMEGA OUT
 * TABLES: weight, rho2, r2, dr2 (P each), B (K x P), k_force (K), load (K), float64.
 * STATES: (M, 2K) float64 initial states; OUT receives the final states.
 * Prints the time per step and trajectory in ns.
 */
#include <math.h>
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

int main(int argc, char **argv) {
    if (argc != 12) {
        fprintf(stderr, "usage: %s TABLES K P STATES STEPS PERIODS H C_DAMP P0 OMEGA OUT\n", argv[0]);
        return 2;
    }
    long n_tab, n_states;
    double *tables = read_doubles(argv[1], &n_tab);
    int K = atoi(argv[2]), P = atoi(argv[3]), steps = atoi(argv[5]), periods = atoi(argv[6]);
    double h = atof(argv[7]), c_damp = atof(argv[8]), p_load = atof(argv[9]), omega = atof(argv[10]);
    double *w = tables, *rho2 = tables + P, *r2 = tables + 2 * P, *dr2 = tables + 3 * P, *B = tables + 4 * P;
    double *k_force = B + (long)K * P, *load = k_force + K;
    double *Y = read_doubles(argv[4], &n_states);
    int n = 2 * K;
    long M = n_states / n;
    double *a = malloc(P * sizeof(double)), *g = malloc(K * sizeof(double));
    double *tmp = malloc(n * sizeof(double)), *stages = malloc(4 * n * sizeof(double));
    double t0 = now();
    for (long m = 0; m < M; m++) {
        double *y = Y + m * n;
        for (int period = 0; period < periods; period++) {
            double t = 0.0;
            for (int step = 0; step < steps; step++) {
                for (int s = 0; s < 4; s++) {
                    double f = s == 0 ? 0.0 : (s == 3 ? h : 0.5 * h);
                    for (int i = 0; i < n; i++) tmp[i] = s == 0 ? y[i] : y[i] + f * stages[(s - 1) * n + i];
                    force(tmp, K, P, w, rho2, r2, dr2, B, a, g);
                    double pt = p_load * cos(omega * (t + f));
                    for (int i = 0; i < K; i++) {
                        stages[s * n + i] = tmp[K + i];
                        stages[s * n + K + i] = -c_damp * tmp[K + i] - k_force[i] * g[i] + pt * load[i];
                    }
                }
                for (int i = 0; i < n; i++)
                    y[i] += h / 6.0 * (stages[i] + 2.0 * stages[n + i] + 2.0 * stages[2 * n + i] + stages[3 * n + i]);
                t += h;
            }
        }
    }
    double t1 = now();
    FILE *out = fopen(argv[11], "wb");
    if (!out) { perror(argv[11]); return 2; }
    fwrite(Y, sizeof(double), M * n, out);
    fclose(out);
    printf("%.3f\n", (t1 - t0) / ((double)M * periods * steps) * 1e9);
    return 0;
}
