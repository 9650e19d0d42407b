/* The one-mode RK4 of model/integrate.py in C: the hardware reference of
 * benchmarks/bench_rk4.py (compiled there with -O3 -march=native).
 *
 * Same algorithm as the numba kernels: classical RK4 with `steps` steps per call, the
 * force g(q) = q T(|q|) from a piecewise Chebyshev table T of degree 7 (Clenshaw sums),
 * forcing p_load cos(omega t) load, damping c_damp.
 *   mode 0, "scalar":   one trajectory at a time (model.integrate.rk4_one_mode);
 *   mode 1, "lockstep": blocks of `width` trajectories, each stage one loop over the block
 *                       (model.integrate.rk4_one_mode_lockstep), restrict pointers.
 * Usage: rk4_one_mode MODE WIDTH TABLE_FILE PIECES Q_MAX K_FORCE LOAD C_DAMP P_LOAD OMEGA
 *                     H STEPS PERIODS STATES_IN STATES_OUT
 * TABLE_FILE: (pieces, 8) float64, row-major (mode 0) or (8, pieces) (mode 1).
 * STATES_*: (N, 2) float64.  Prints the kernel time in ns per trajectory and RK4 step.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "force_table.h"
#include "read_doubles.h"

static void scalar(double *y, const double *coef, int pieces, double q_max, double kf, double load,
                   double cd, double pl, double om, double h, int steps) {
    double q = y[0], v = y[1];
    double c0 = cos(om * 0.0);
    for (int i = 0; i < steps; i++) {
        double t = i * h;
        double ch = cos(om * (t + 0.5 * h)), ce = cos(om * (t + h));
        double a1 = -cd * v - kf * q * table_row(coef, pieces, q_max, fabs(q)) + pl * c0 * load;
        double q2 = q + 0.5 * h * v, v2 = v + 0.5 * h * a1;
        double a2 = -cd * v2 - kf * q2 * table_row(coef, pieces, q_max, fabs(q2)) + pl * ch * load;
        double q3 = q + 0.5 * h * v2, v3 = v + 0.5 * h * a2;
        double a3 = -cd * v3 - kf * q3 * table_row(coef, pieces, q_max, fabs(q3)) + pl * ch * load;
        double q4 = q + h * v3, v4 = v + h * a3;
        double a4 = -cd * v4 - kf * q4 * table_row(coef, pieces, q_max, fabs(q4)) + pl * ce * load;
        q += h / 6.0 * (v + 2.0 * v2 + 2.0 * v3 + v4);
        v += h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
        c0 = ce;
    }
    y[0] = q;
    y[1] = v;
}

static void lockstep(int B, double *restrict q, double *restrict v, const double *restrict coef_t,
                     int pieces, double q_max, double kf, double load, double cd, double pl, double om,
                     double h, int steps, double *restrict qs, double *restrict vs, double *restrict acc,
                     double *restrict dq, double *restrict dv) {
    double inv_width = pieces / q_max, last = pieces - 0.5;
    for (int i = 0; i < steps; i++) {
        double t = i * h;
        for (int s = 0; s < 4; s++) {
            double f = s == 0 ? 0.0 : (s == 3 ? h : 0.5 * h);
            double ct = cos(om * (t + f));
            if (s == 0) {
                for (int b = 0; b < B; b++) { qs[b] = q[b]; vs[b] = v[b]; }
            } else {
                for (int b = 0; b < B; b++) { qs[b] = q[b] + f * vs[b]; vs[b] = v[b] + f * acc[b]; }
            }
            for (int b = 0; b < B; b++) {
                double u = fabs(qs[b]) * inv_width;
                if (u > last) u = last;
                long j = (long)u;
                double tc = 2.0 * (u - j) - 1.0;
                double b1 = coef_t[(long)(NCOEF - 1) * pieces + j], b2 = 0.0;
                for (int k = NCOEF - 2; k > 0; k--) {
                    double bn = 2.0 * tc * b1 - b2 + coef_t[(long)k * pieces + j];
                    b2 = b1;
                    b1 = bn;
                }
                double stiff = tc * b1 - b2 + coef_t[j];
                acc[b] = -cd * vs[b] - kf * qs[b] * stiff + pl * ct * load;
            }
            double w = (s == 0 || s == 3) ? 1.0 : 2.0;
            if (s == 0) {
                for (int b = 0; b < B; b++) { dq[b] = vs[b]; dv[b] = acc[b]; }
            } else {
                for (int b = 0; b < B; b++) { dq[b] += w * vs[b]; dv[b] += w * acc[b]; }
            }
        }
        for (int b = 0; b < B; b++) { q[b] += h / 6.0 * dq[b]; v[b] += h / 6.0 * dv[b]; }
    }
}

int main(int argc, char **argv) {
    if (argc != 16) { fprintf(stderr, "usage: see the header of rk4_one_mode.c\n"); return 2; }
    int mode = atoi(argv[1]), width = atoi(argv[2]);
    long ncoef, nstate;
    double *coef = read_doubles(argv[3], &ncoef);
    int pieces = atoi(argv[4]);
    double q_max = atof(argv[5]), kf = atof(argv[6]), load = atof(argv[7]), cd = atof(argv[8]);
    double pl = atof(argv[9]), om = atof(argv[10]), h = atof(argv[11]);
    int steps = atoi(argv[12]), periods = atoi(argv[13]);
    double *y = read_doubles(argv[14], &nstate);
    long N = nstate / 2;
    double *q = aligned_doubles(N), *v = aligned_doubles(N);
    double *work = aligned_doubles(5L * width);
    for (long i = 0; i < N; i++) { q[i] = y[2 * i]; v[i] = y[2 * i + 1]; }
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    if (mode == 0) {
        for (long i = 0; i < N; i++)
            for (int p = 0; p < periods; p++)
                scalar(y + 2 * i, coef, pieces, q_max, kf, load, cd, pl, om, h, steps);
    } else {
        for (long s = 0; s < N; s += width) {
            int B = (int)(N - s < width ? N - s : width);
            for (int p = 0; p < periods; p++)
                lockstep(B, q + s, v + s, coef, pieces, q_max, kf, load, cd, pl, om, h, steps, work,
                         work + width, work + 2 * width, work + 3 * width, work + 4 * width);
        }
        for (long i = 0; i < N; i++) { y[2 * i] = q[i]; y[2 * i + 1] = v[i]; }
    }
    clock_gettime(CLOCK_MONOTONIC, &t1);
    double ns = (t1.tv_sec - t0.tv_sec) * 1e9 + (t1.tv_nsec - t0.tv_nsec);
    FILE *f = fopen(argv[15], "wb");
    fwrite(y, sizeof(double), 2 * N, f);
    fclose(f);
    printf("%.6f\n", ns / ((double)N * periods * steps));
    return 0;
}
