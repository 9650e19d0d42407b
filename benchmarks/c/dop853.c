/* DOP853 of the ROM in C: the hardware reference of benchmarks/bench_integrators.py
 * (compiled there with -O3 -march=native -ffast-math, the freedom the numba force
 * kernels' fastmath has).
 *
 * Same algorithm as model.dopri.solve with one output time: the explicit Dormand-Prince
 * 8(5,3) pair with the tableau of model.dopri (read from COEF, as the benchmark wrote it),
 * the first step 0.01 |y|/|f| in the scaled norm, error norm |h| e5 / sqrt((e5 + 0.01 e3) n),
 * step factor 0.9 err^(-1/8) within [0.2, 10], the last step shortened to land on T_END.
 * Right-hand side of model.rom.rhs: q'' = -c q' - k_force g(q) + P0 cos(Omega t) load with
 * g from the one-mode force table within its range (PIECES > 0) or else the quadrature
 * force of axisymmetric_force.h.  One trajectory at a time.
 * Usage: dop853 COEF TABLES K P PIECES Q_MAX STATES T_END RTOL ATOL C_DAMP P0 OMEGA OUT
 * COEF: A (12 x 12), B (12), C (12), E3 (13), E5 (13), float64.
 * TABLES: weight, inv_rho2, hoop2, radial2 (P each), B (K x P), k_force (K), load (K), then the
 * force table (PIECES x 8) when PIECES > 0, float64.
 * STATES: (M, 2K) float64 initial states; OUT receives the final states (NaN for a
 * trajectory that ran out of MAX_STEPS attempted steps).
 * Prints the time per right-hand side evaluation in ns and the evaluations made.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "axisymmetric_force.h"
#include "force_table.h"
#include "read_doubles.h"

#define NS 12
#define MAX_STEPS 50000000L /* attempted steps per trajectory, model.dopri.MAX_STEPS */

typedef struct {
    int K, P, pieces;
    double q_max, c_damp, p_load, omega;
    QuadratureTables tab;
    const double *table;
    double *a, *g;
} Model;

typedef struct { const double *A, *B, *C, *E3, *E5; } Tableau;

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static void rhs(double t, const double *y, const Model *m, double *out) {
    int K = m->K;
    if (m->pieces > 0 && fabs(y[0]) < m->q_max)
        m->g[0] = y[0] * table_row(m->table, m->pieces, m->q_max, fabs(y[0]));
    else
        force(y, K, m->P, m->tab.w, m->tab.inv_rho2, m->tab.hoop2, m->tab.radial2, m->tab.B, m->a, m->g);
    double pt = m->p_load * cos(m->omega * t);
    for (int k = 0; k < K; k++) {
        out[k] = y[K + k];
        out[K + k] = -m->c_damp * y[K + k] - m->tab.k_force[k] * m->g[k] + pt * m->tab.load[k];
    }
}

/* One step of size h from (t, y) with f0 = F(t, y): fills y_new, f_new and returns the
 * scaled error norm (model.dopri._step). */
static double step(double t, const double *y, const double *f0, double h, const Model *m, const Tableau *c,
                   double *kst, double *tmp, double *y_new, double *f_new, double rtol, double atol, int n) {
    for (int i = 0; i < n; i++) kst[i] = f0[i];
    for (int s = 1; s < NS; s++) {
        for (int i = 0; i < n; i++) {
            double acc = 0.0;
            for (int j = 0; j < s; j++) acc += c->A[s * NS + j] * kst[j * n + i];
            tmp[i] = y[i] + h * acc;
        }
        rhs(t + c->C[s] * h, tmp, m, kst + s * n);
    }
    for (int i = 0; i < n; i++) {
        double acc = 0.0;
        for (int j = 0; j < NS; j++) acc += c->B[j] * kst[j * n + i];
        y_new[i] = y[i] + h * acc;
    }
    rhs(t + h, y_new, m, f_new);
    for (int i = 0; i < n; i++) kst[NS * n + i] = f_new[i];
    double e5 = 0.0, e3 = 0.0;
    for (int i = 0; i < n; i++) {
        double sc = atol + rtol * fmax(fabs(y[i]), fabs(y_new[i])), a5 = 0.0, a3 = 0.0;
        for (int j = 0; j < NS + 1; j++) {
            a5 += c->E5[j] * kst[j * n + i];
            a3 += c->E3[j] * kst[j * n + i];
        }
        e5 += (a5 / sc) * (a5 / sc);
        e3 += (a3 / sc) * (a3 / sc);
    }
    if (e5 == 0.0 && e3 == 0.0) return 0.0;
    return fabs(h) * e5 / sqrt((e5 + 0.01 * e3) * n);
}

static double new_size(double h, double err) {
    if (err == 0.0) return h * 10.0;
    return h * fmin(10.0, fmax(0.2, 0.9 * pow(err, -1.0 / 8.0)));
}

static double initial_step(const double *y, const double *f, double rtol, double atol, int n) {
    double d0 = 0.0, d1 = 0.0;
    for (int i = 0; i < n; i++) {
        double sc = atol + rtol * fabs(y[i]);
        d0 += (y[i] / sc) * (y[i] / sc);
        d1 += (f[i] / sc) * (f[i] / sc);
    }
    if (d0 < 1e-10 || d1 < 1e-10) return 1e-6;
    return 0.01 * sqrt(d0 / d1);
}

int main(int argc, char **argv) {
    if (argc != 15) {
        fprintf(stderr, "usage: %s COEF TABLES K P PIECES Q_MAX STATES T_END RTOL ATOL C_DAMP P0 OMEGA OUT\n",
                argv[0]);
        return 2;
    }
    long n_coef, n_tab, n_states;
    double *coef = read_doubles(argv[1], &n_coef);
    double *tables = read_doubles(argv[2], &n_tab);
    Model m;
    m.K = atoi(argv[3]);
    m.P = atoi(argv[4]);
    m.pieces = atoi(argv[5]);
    m.q_max = atof(argv[6]);
    double *Y = read_doubles(argv[7], &n_states);
    double t_end = atof(argv[8]), rtol = atof(argv[9]), atol = atof(argv[10]);
    m.c_damp = atof(argv[11]);
    m.p_load = atof(argv[12]);
    m.omega = atof(argv[13]);
    int K = m.K, P = m.P, n = 2 * K;
    if (n_coef != NS * NS + 2 * NS + 2 * (NS + 1) || n_tab != 4L * P + (long)K * P + 2L * K + 8L * m.pieces) {
        fprintf(stderr, "COEF or TABLES has the wrong size\n");
        return 2;
    }
    Tableau c = {coef, coef + NS * NS, coef + NS * NS + NS, coef + NS * NS + 2 * NS, coef + NS * NS + 3 * NS + 1};
    m.tab = quadrature_tables(tables, K, P);
    m.table = m.tab.load + K;
    m.a = aligned_doubles(P);
    m.g = aligned_doubles(K);
    double *kst = aligned_doubles((long)(NS + 1) * n), *tmp = aligned_doubles(n);
    double *f = aligned_doubles(n), *y_new = aligned_doubles(n), *f_new = aligned_doubles(n);
    long M = n_states / n, evals = 0;
    double t0 = now();
    for (long traj = 0; traj < M; traj++) {
        double *y = Y + traj * n, t = 0.0;
        rhs(t, y, &m, f);
        double h = initial_step(y, f, rtol, atol, n);
        long attempts = 0;
        evals += 1;
        while (t < t_end && attempts++ < MAX_STEPS) {
            int clipped = t + h >= t_end;
            double hs = clipped ? t_end - t : h;
            double err = step(t, y, f, hs, &m, &c, kst, tmp, y_new, f_new, rtol, atol, n);
            evals += NS;
            if (err <= 1.0) {
                t = clipped ? t_end : t + hs;
                for (int i = 0; i < n; i++) { y[i] = y_new[i]; f[i] = f_new[i]; }
                h = clipped ? fmax(h, new_size(hs, err)) : new_size(hs, err);
            } else {
                h = new_size(hs, err);
            }
        }
        if (t < t_end)
            for (int i = 0; i < n; i++) y[i] = NAN; /* out of steps, as model.dopri.solve */
    }
    double t1 = now();
    FILE *out = fopen(argv[14], "wb");
    if (!out) { perror(argv[14]); return 2; }
    fwrite(Y, sizeof(double), M * n, out);
    fclose(out);
    printf("%.3f %ld\n", (t1 - t0) / evals * 1e9, evals);
    return 0;
}
