/* Shared by the C reference programs of benchmarks/: arrays of float64 on 64-byte
 * boundaries (a cache line, an AVX-512 vector: the timings then do not depend on where the
 * heap happens to place an array; one more work array once moved a lock-step time by a
 * fifth), and reading a whole file of float64 into one. */
#ifndef READ_DOUBLES_H
#define READ_DOUBLES_H
#include <stdio.h>
#include <stdlib.h>

static inline double *aligned_doubles(long count) {
    double *p = aligned_alloc(64, ((count * (long)sizeof(double) + 63) / 64) * 64);
    if (!p) { perror("aligned_alloc"); exit(2); }
    return p;
}

static inline double *read_doubles(const char *path, long *count) {
    FILE *f = fopen(path, "rb");
    if (!f) { perror(path); exit(2); }
    fseek(f, 0, SEEK_END);
    long bytes = ftell(f);
    fseek(f, 0, SEEK_SET);
    double *data = aligned_doubles(bytes / (long)sizeof(double) + 1); /* + 1: never a zero-size allocation */
    if (fread(data, 1, bytes, f) != (size_t)bytes) { perror(path); exit(2); }
    fclose(f);
    *count = bytes / (long)sizeof(double);
    return data;
}

#endif
