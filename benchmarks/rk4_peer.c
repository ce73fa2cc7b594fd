/* Benchmark peer (not library code): the ensemble scene of bench_ensembles.py
 * as a plain C loop vectorised ACROSS states, the way a C programmer would
 * write it for speed: compiled by bench_kernels.py at benchmark time with
 * -O3 -march=native -ffast-math, so gcc calls glibc's vector sin (libmvec)
 * for a whole vector of states at once.
 *
 *   rk4_peer N REPEAT  ->  prints "best_cpu_seconds max_abs_theta_checksum"
 *
 * Scene: w0**2 = 2, gamma = 0.1, h = 0.025 s, 601 outputs over 30 s (two
 * steps per output), theta0 ~ U(-0.1, 0.1), Omega0 ~ U(1.9, 2.1) (a fixed
 * LCG, not numpy's generator: the speed does not depend on the draw).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#define NT 601

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static void run(int n, const double *th0, const double *om0, double *y, double *u, double *out)
{
    const double w0sq = 2.0, gamma = 0.1, h = 0.025, half = h / 2, c6 = h * h / 6, sixth = h / 6;
    for (int s = 0; s < n; s++) {
        y[s] = th0[s];
        u[s] = om0[s];
        out[s] = y[s];
    }
    for (int j = 1; j < NT; j++) {
        for (int sub = 0; sub < 2; sub++) {
            for (int s = 0; s < n; s++) {
                double ys = y[s], us = u[s];
                double k1 = -gamma * us - w0sq * sin(ys);
                double m2 = us + half * k1;
                double k2 = -gamma * m2 - w0sq * sin(ys + half * us);
                double m3 = us + half * k2;
                double k3 = -gamma * m3 - w0sq * sin(ys + half * m2);
                double k4 = -gamma * (us + h * k3) - w0sq * sin(ys + h * m3);
                y[s] = ys + h * us + c6 * (k1 + k2 + k3);
                u[s] = us + sixth * (k1 + 2 * (k2 + k3) + k4);
            }
        }
        for (int s = 0; s < n; s++)
            out[(size_t)j * n + s] = y[s];
    }
}

int main(int argc, char **argv)
{
    int n = argc > 1 ? atoi(argv[1]) : 10000, repeat = argc > 2 ? atoi(argv[2]) : 3;
    double *th0 = malloc(n * sizeof *th0), *om0 = malloc(n * sizeof *om0);
    double *y = malloc(n * sizeof *y), *u = malloc(n * sizeof *u);
    double *out = malloc((size_t)NT * n * sizeof *out);
    unsigned long long state = 2024;
    for (int s = 0; s < n; s++) {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        th0[s] = -0.1 + 0.2 * (double)(state >> 11) / 9007199254740992.0;
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        om0[s] = 1.9 + 0.2 * (double)(state >> 11) / 9007199254740992.0;
    }
    double best = 1e300, check = 0;
    for (int r = 0; r < repeat; r++) {
        double t0 = cpu_now();
        run(n, th0, om0, y, u, out);
        double dt = cpu_now() - t0;
        if (dt < best)
            best = dt;
    }
    for (size_t i = 0; i < (size_t)NT * n; i++)
        check = fmax(check, fabs(out[i]));
    printf("%.6e %.6e\n", best, check);
    return 0;
}
