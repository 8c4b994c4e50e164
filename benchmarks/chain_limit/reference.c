/* The bare RK4 stencil over n contiguous sliding blocks: the C twin of
 * benchmarks/chain_limit/src/reference.rs (same arithmetic in the same order), built by
 * that benchmark with cc -O3 -march=native.
 *   u_tt = (u[i-1] + u[i+1] - 2 u[i]) / dx^2 - u[i] + 2 gamma (v - u_t[i])
 * (the engine's sliding forward branch, Coulomb friction with beta = inf), the ends held
 * by stuck neighbours (v = 0: fixed).
 * usage: reference N STEPS DX GAMMA STEP  -> prints "cpu_seconds checksum" (CPU time of
 * the loop: the machine is shared, wall time counts the other jobs too)
 *
 * The replay (the twin of src/replay.rs): the same stencil over a recorded sequence of
 * steps, each a list of runs of sliding blocks: the runs of a step one after another, one
 * held block between two runs (and one at each end), each run's held neighbours first
 * copied into the other buffers, then its four stage passes.
 * usage: reference replay FILE PASSES DX GAMMA STEP  -> prints "cpu_seconds checksum";
 * FILE: u32 (native order) steps, runs, counts[steps], lens[runs]. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <math.h>
#include <stdint.h>

static void stage(int n, const double *restrict su, const double *restrict sw,
                  const double *restrict u0, const double *restrict w0,
                  double *restrict uo, double *restrict wo, double *restrict nu,
                  double *restrict nw, double k, double g2, double v, double wt, double cn) {
    for (int i = 1; i <= n; i++) {
        double a = (su[i - 1] + su[i + 1] - 2.0 * su[i]) * k - su[i] + g2 * (v - sw[i]);
        uo[i] += wt * sw[i];
        wo[i] += wt * a;
        nu[i] = u0[i] + cn * sw[i];
        nw[i] = w0[i] + cn * a;
    }
}

static uint32_t *read_u32(FILE *f, size_t n) {
    uint32_t *x = malloc((n ? n : 1) * sizeof(uint32_t));
    if (!x || fread(x, sizeof(uint32_t), n, f) != n) { fprintf(stderr, "bad replay file\n"); exit(2); }
    return x;
}

static int replay(int argc, char **argv) {
    if (argc < 7) { fprintf(stderr, "usage: reference replay FILE PASSES DX GAMMA STEP\n"); return 2; }
    FILE *f = fopen(argv[2], "rb");
    if (!f) { fprintf(stderr, "cannot open %s\n", argv[2]); return 2; }
    uint32_t *head = read_u32(f, 2);
    size_t n_steps = head[0], n_runs = head[1];
    uint32_t *counts = read_u32(f, n_steps), *lens = read_u32(f, n_runs);
    fclose(f);
    long passes = atol(argv[3]);
    double dx = atof(argv[4]), gamma = atof(argv[5]), step = atof(argv[6]);
    double k = 1.0 / (dx * dx), h = step * dx, g2 = 2.0 * gamma, v = 0.0;
    /* the widest step's runs, each followed by one held block, plus the first */
    size_t len = 0;
    for (size_t s = 0, r = 0; s < n_steps; r += counts[s], s++) {
        size_t wd = 0;
        for (size_t j = r; j < r + counts[s]; j++) wd += (size_t)lens[j] + 1;
        if (wd > len) len = wd;
    }
    len += 1;
    double *b[8];
    for (int j = 0; j < 8; j++) {
        b[j] = malloc(len * sizeof(double));
        for (size_t i = 0; i < len; i++)
            b[j][i] = j % 2 == 0 ? 0.6 - 1e-3 * sin(0.1 * (double)i) : -1e-2 * cos(0.1 * (double)i);
    }
    double *u = b[0], *w = b[1], *uo = b[2], *wo = b[3], *s1u = b[4], *s1w = b[5],
           *s2u = b[6], *s2w = b[7];
    double h2 = 0.5 * h, h6 = h / 6.0, h3 = h / 3.0;
    struct timespec t0, t1;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t0);
    for (long p = 0; p < passes; p++) {
        size_t r = 0;
        for (size_t s = 0; s < n_steps; s++) {
            size_t a = 0; /* the run's left held block */
            for (size_t j = r; j < r + counts[s]; j++) {
                int n = (int)lens[j];
                size_t e = a + (size_t)n + 1; /* its right held block */
                uo[a] = s1u[a] = s2u[a] = u[a];
                wo[a] = s1w[a] = s2w[a] = w[a];
                uo[e] = s1u[e] = s2u[e] = u[e];
                wo[e] = s1w[e] = s2w[e] = w[e];
                memcpy(uo + a + 1, u + a + 1, n * sizeof(double));
                memcpy(wo + a + 1, w + a + 1, n * sizeof(double));
                stage(n, u + a, w + a, u + a, w + a, uo + a, wo + a, s1u + a, s1w + a, k, g2, v, h6, h2);
                stage(n, s1u + a, s1w + a, u + a, w + a, uo + a, wo + a, s2u + a, s2w + a, k, g2, v, h3, h2);
                stage(n, s2u + a, s2w + a, u + a, w + a, uo + a, wo + a, s1u + a, s1w + a, k, g2, v, h3, h);
                stage(n, s1u + a, s1w + a, u + a, w + a, uo + a, wo + a, s2u + a, s2w + a, k, g2, v, h6, 0.0);
                a = e;
            }
            r += counts[s];
            double *t = u; u = uo; uo = t;
            t = w; w = wo; wo = t;
        }
    }
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t1);
    double sec = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    double chk = 0.0;
    for (size_t i = 0; i < len; i++) chk += u[i] + w[i];
    printf("%.9f %.17g\n", sec, chk);
    return 0;
}

int main(int argc, char **argv) {
    if (argc > 1 && strcmp(argv[1], "replay") == 0) return replay(argc, argv);
    if (argc < 6) { fprintf(stderr, "usage: reference N STEPS DX GAMMA STEP\n"); return 2; }
    int n = atoi(argv[1]);
    long steps = atol(argv[2]);
    double dx = atof(argv[3]), gamma = atof(argv[4]), step = atof(argv[5]);
    double k = 1.0 / (dx * dx), h = step * dx, g2 = 2.0 * gamma, v = 0.0;
    size_t len = (size_t)n + 2;
    double *b[8];
    for (int j = 0; j < 8; j++) b[j] = calloc(len, sizeof(double));
    double *u = b[0], *w = b[1], *uo = b[2], *wo = b[3], *s1u = b[4], *s1w = b[5],
           *s2u = b[6], *s2w = b[7];
    for (size_t i = 0; i < len; i++) {
        u[i] = 0.6 - 1e-3 * sin(0.1 * (double)i);
        w[i] = -1e-2 * cos(0.1 * (double)i);
    }
    /* the held ends */
    for (int j = 2; j < 8; j += 2) { b[j][0] = u[0]; b[j][len - 1] = u[len - 1]; }
    for (int j = 3; j < 8; j += 2) { b[j][0] = w[0]; b[j][len - 1] = w[len - 1]; }
    double h2 = 0.5 * h, h6 = h / 6.0, h3 = h / 3.0;
    struct timespec t0, t1;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t0);
    for (long s = 0; s < steps; s++) {
        memcpy(uo + 1, u + 1, n * sizeof(double));
        memcpy(wo + 1, w + 1, n * sizeof(double));
        stage(n, u, w, u, w, uo, wo, s1u, s1w, k, g2, v, h6, h2);
        stage(n, s1u, s1w, u, w, uo, wo, s2u, s2w, k, g2, v, h3, h2);
        stage(n, s2u, s2w, u, w, uo, wo, s1u, s1w, k, g2, v, h3, h);
        stage(n, s1u, s1w, u, w, uo, wo, s2u, s2w, k, g2, v, h6, 0.0);
        double *t = u; u = uo; uo = t;
        t = w; w = wo; wo = t;
    }
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t1);
    double sec = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    double chk = 0.0;
    for (int i = 1; i <= n; i++) chk += u[i] + w[i];
    printf("%.9f %.17g\n", sec, chk);
    return 0;
}
