/* The bare RK4 stencil over n contiguous sliding blocks: the C twin of
 * benchmarks/chain_limit/src/reference.rs (same arithmetic in the same order), built by
 * that benchmark with cc -O3 -march=native.
 *   u_tt = (u[i-1] + u[i+1] - 2 u[i]) / dx^2 - u[i] + 2 gamma (v - u_t[i])
 * (the engine's sliding forward branch, Coulomb friction with beta = inf), the ends held
 * by stuck neighbours (v = 0: fixed).
 * usage: reference N STEPS DX GAMMA STEP  -> prints "cpu_seconds checksum" (CPU time of
 * the loop: the machine is shared, wall time counts the other jobs too) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <math.h>

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

int main(int argc, char **argv) {
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
