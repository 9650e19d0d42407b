/* Shared by the C reference programs of benchmarks/: read a whole file of float64. */
#ifndef READ_DOUBLES_H
#define READ_DOUBLES_H
#include <stdio.h>
#include <stdlib.h>

static double *read_doubles(const char *path, long *count) {
    FILE *f = fopen(path, "rb");
    if (!f) { perror(path); exit(2); }
    fseek(f, 0, SEEK_END);
    long bytes = ftell(f);
    fseek(f, 0, SEEK_SET);
    double *data = malloc(bytes);
    if (fread(data, 1, bytes, f) != (size_t)bytes) { perror(path); exit(2); }
    fclose(f);
    *count = bytes / (long)sizeof(double);
    return data;
}

#endif
