/* The force of the membrane on the two-dimensional finite-element mesh (model/fe_kernels.py), in C:
 * the hardware reference of benchmarks/bench_fe_motion.py (compiled there with -O3 -march=native
 * -ffast-math, the freedom the numba kernel's fastmath has).
 *
 * Neo-Hookean law in the trace T and determinant D of the metric: W_T = 1, W_D = -1/D^2.
 * Per element e and quadrature point p, with the element's L nodes n_k and the derivatives
 * gx_k, gy_k of their basis functions:
 *   a1 = e_x + sum_k gx_k D[:, n_k],  a2 = e_y + sum_k gy_k D[:, n_k],
 *   n1 = |a1|^2, n2 = |a2|^2, c = a1.a2, D = n1 n2 - c^2,
 *   P1 = w (2 (W_T + W_D n2) a1 - 2 W_D c a2),  P2 = w (2 (W_T + W_D n1) a2 - 2 W_D c a1),
 *   f[:, n_k] += P1 gx_k + P2 gy_k.
 * Usage: fe_force TABLES_FILE E P L NODES D_FILE REPEATS OUT_FILE
 * TABLES_FILE: element dofs (E x L, as float64), gx (E x P x L), gy (E x P x L), weights (E x P).
 * D_FILE: (M, 3, NODES) float64 displacements.  OUT_FILE receives the forces (M, 3, NODES).
 * Prints the time per call in ns.
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

static void force(const int *restrict dofs, const double *restrict gx, const double *restrict gy,
                  const double *restrict weights, int E, int P, int L, long nodes, const double *restrict D,
                  double *restrict f) {
    const double *dx = D, *dy = D + nodes, *dz = D + 2 * nodes;
    double *fx = f, *fy = f + nodes, *fz = f + 2 * nodes;
    for (long i = 0; i < 3 * nodes; i++) f[i] = 0.0;
    for (int e = 0; e < E; e++) {
        const int *n = dofs + (long)e * L;
        for (int p = 0; p < P; p++) {
            const double *bx = gx + ((long)e * P + p) * L, *by = gy + ((long)e * P + p) * L;
            double a10 = 1.0, a11 = 0.0, a12 = 0.0, a20 = 0.0, a21 = 1.0, a22 = 0.0;
            for (int k = 0; k < L; k++) {
                a10 += bx[k] * dx[n[k]];
                a11 += bx[k] * dy[n[k]];
                a12 += bx[k] * dz[n[k]];
                a20 += by[k] * dx[n[k]];
                a21 += by[k] * dy[n[k]];
                a22 += by[k] * dz[n[k]];
            }
            double n1 = a10 * a10 + a11 * a11 + a12 * a12, n2 = a20 * a20 + a21 * a21 + a22 * a22;
            double c = a10 * a20 + a11 * a21 + a12 * a22, det = n1 * n2 - c * c, inv = 1.0 / det;
            double w_t = 1.0, w_d = -inv * inv, w = weights[(long)e * P + p];
            double f11 = 2.0 * (w_t + w_d * n2) * w, f12 = -2.0 * w_d * c * w, f22 = 2.0 * (w_t + w_d * n1) * w;
            double p10 = f11 * a10 + f12 * a20, p11 = f11 * a11 + f12 * a21, p12 = f11 * a12 + f12 * a22;
            double p20 = f22 * a20 + f12 * a10, p21 = f22 * a21 + f12 * a11, p22 = f22 * a22 + f12 * a12;
            for (int k = 0; k < L; k++) {
                fx[n[k]] += p10 * bx[k] + p20 * by[k];
                fy[n[k]] += p11 * bx[k] + p21 * by[k];
                fz[n[k]] += p12 * bx[k] + p22 * by[k];
            }
        }
    }
}

int main(int argc, char **argv) {
    if (argc != 9) {
        fprintf(stderr, "usage: %s TABLES_FILE E P L NODES D_FILE REPEATS OUT_FILE\n", argv[0]);
        return 2;
    }
    int E = atoi(argv[2]), P = atoi(argv[3]), L = atoi(argv[4]), repeats = atoi(argv[7]);
    long nodes = atol(argv[5]), nt, nd;
    double *t = read_doubles(argv[1], &nt), *D = read_doubles(argv[6], &nd);
    int *dofs = malloc(sizeof(int) * (size_t)E * L);
    for (long i = 0; i < (long)E * L; i++) dofs[i] = (int)t[i];
    const double *gx = t + (long)E * L, *gy = gx + (long)E * P * L, *weights = gy + (long)E * P * L;
    long M = nd / (3 * nodes);
    double *F = aligned_doubles(M * 3 * nodes);
    double start = now();
    for (int r = 0; r < repeats; r++)
        for (long m = 0; m < M; m++) force(dofs, gx, gy, weights, E, P, L, nodes, D + m * 3 * nodes, F + m * 3 * nodes);
    double ns = (now() - start) / ((double)repeats * M) * 1e9;
    FILE *f = fopen(argv[8], "wb");
    if (!f) { perror(argv[8]); return 2; }
    fwrite(F, sizeof(double), M * 3 * nodes, f);
    fclose(f);
    printf("%.3f\n", ns);
    return 0;
}
