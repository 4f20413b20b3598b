/*
 * stream_probe: the memory bandwidth one thread sees, in the manner of
 * McCalpin's STREAM (copy a = b and triad a = b + s c over arrays of
 * doubles, best of several passes, bytes counted as the kernel names them:
 * 16 per element for copy, 24 for triad, write-allocate traffic not
 * counted).  bench/bench_roofline.sh uses it as the limit the solver
 * kernels are measured against: bytes a kernel must move per step divided
 * by this bandwidth is the shortest time the step could take.
 *
 *   usage: stream_probe MIB_PER_ARRAY [PASSES]
 *   prints: copy_gbs triad_gbs   (10^9 bytes per second)
 *
 * Our own code, built by the bench script with the release flags.
 */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* noinline: the compiler must not merge passes or drop a pass whose result
 * the next one overwrites */
__attribute__((noinline)) static void copy(double *restrict a, const double *restrict b, long n)
{
    for (long i = 0; i < n; i++)
        a[i] = b[i];
}

__attribute__((noinline)) static void triad(double *restrict a, const double *restrict b,
                                            const double *restrict c, double s, long n)
{
    for (long i = 0; i < n; i++)
        a[i] = b[i] + s * c[i];
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: stream_probe MIB_PER_ARRAY [PASSES]\n");
        return 2;
    }
    long mib = strtol(argv[1], NULL, 10);
    int passes = argc > 2 ? (int)strtol(argv[2], NULL, 10) : 10;
    if (mib < 1 || mib > 4096 || passes < 1 || passes > 1000) {
        fprintf(stderr, "stream_probe: MIB_PER_ARRAY in 1..4096, PASSES in 1..1000\n");
        return 2;
    }
    long n = mib * 1048576 / (long)sizeof(double);
    double *a = malloc((size_t)n * sizeof *a), *b = malloc((size_t)n * sizeof *b),
           *c = malloc((size_t)n * sizeof *c);
    if (!a || !b || !c) {
        fprintf(stderr, "stream_probe: out of memory for 3 x %ld MiB\n", mib);
        free(a);
        free(b);
        free(c);
        return 1;
    }
    for (long i = 0; i < n; i++) {   /* touch every page before timing */
        a[i] = 0;
        b[i] = 1.0 + (double)(i & 7);
        c[i] = 0.5;
    }
    double best_copy = 1e300, best_triad = 1e300;
    for (int k = 0; k < passes; k++) {
        double t0 = now_s();
        copy(a, b, n);
        double t1 = now_s();
        triad(c, a, b, 0.25, n);
        double t2 = now_s();
        if (t1 - t0 < best_copy)
            best_copy = t1 - t0;
        if (t2 - t1 < best_triad)
            best_triad = t2 - t1;
    }
    double check = a[n / 2] + c[n / 3];   /* keeps the passes observable */
    printf("%.2f %.2f\n", 16.0 * (double)n / best_copy * 1e-9, 24.0 * (double)n / best_triad * 1e-9);
    free(a);
    free(b);
    free(c);
    return check != check;   /* never NaN; used so the stores are live */
}
