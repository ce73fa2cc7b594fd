/* Benchmark peer (not library code): Boost.Math's incomplete elliptic integral of
 * the first kind in double precision, on the inputs of bench_elliptic.py's ellipf
 * row.  Compiled by bench_elliptic.py at benchmark time (c++ -O2; skipped without a
 * C++ compiler or the Boost headers).
 *
 *   ellipf_boost_peer N REPEAT  ->  prints "best_cpu_seconds checksum"
 *
 * Inputs: phi ~ U(-pi/2, pi/2), m ~ U(0, 1) (a fixed LCG, not numpy's generator:
 * the speed does not depend on the draw); Boost takes the modulus k = sqrt(m).
 * Policy promote_double<false>: the arithmetic in double, as pendula's (Boost's
 * default would carry it in long double).
 */
#include <boost/math/special_functions/ellint_1.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <vector>

using policy = boost::math::policies::policy<boost::math::policies::promote_double<false>>;

static double cpu_now()
{
    timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

int main(int argc, char **argv)
{
    const int n = argc > 1 ? std::atoi(argv[1]) : 1000000;
    const int repeat = argc > 2 ? std::atoi(argv[2]) : 5;
    std::vector<double> phi(n), k(n), f(n);
    unsigned long long s = 12345;
    auto uniform = [&s]() {
        s = s * 6364136223846793005ULL + 1442695040888963407ULL;
        return (s >> 11) * (1.0 / 9007199254740992.0);
    };
    const double half_pi = 1.5707963267948966;
    for (int i = 0; i < n; i++) {
        phi[i] = (2 * uniform() - 1) * half_pi;
        k[i] = std::sqrt(uniform());
    }
    double best = 1e300, sum = 0;
    for (int r = 0; r < repeat; r++) {
        const double t0 = cpu_now();
        for (int i = 0; i < n; i++)
            f[i] = boost::math::ellint_1(k[i], phi[i], policy());
        const double t = cpu_now() - t0;
        if (t < best)
            best = t;
        sum = 0;
        for (int i = 0; i < n; i++)
            sum += f[i];
    }
    std::printf("%.9g %.17g\n", best, sum);
    return 0;
}
