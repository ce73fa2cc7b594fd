/* Runtime dispatch of pendula's hot kernels: which compiled variant runs.
 *
 * The batch RK4 kernel (pendula_rk4_lanes.F90), the Taylor batch's series
 * kernel (pendula_taylor_series_lanes.F90), the block kernel of the K and
 * E array forms (special/pendula_elliptic_ke_lanes.F90), the compensated AGM
 * of K for a block (special/pendula_elliptic_k_lanes.F90), the core of the
 * Jacobi array forms (special/pendula_jacobi_lanes.F90), the librations of
 * undamped_states (undamped/pendula_undamped_lanes.F90) and the elliptic parameter
 * of a block of undamped states (undamped/pendula_undamped_parameter_lanes.F90) are compiled for baseline
 * x86-64 (SSE2), x86-64-v3 (AVX2, FMA, BMI2) and x86-64-v4 (AVX-512 F, BW,
 * CD, DQ, VL) when meson builds for x86_64 (PENDULA_KERNEL_VARIANTS), and
 * only in its portable form elsewhere.  The path is chosen once, when the
 * library is loaded (a constructor), from the CPU's features as libgcc reads
 * them (cpuid, with the OS's XSAVE support of the wider registers), as NumPy
 * and OpenBLAS do.  The environment variable PENDULA_KERNEL = baseline, v3
 * or v4 asks for one path (for reproducibility and for the tests); a path
 * the CPU cannot run gives the best one it can below it, and any other value
 * (or none, or "auto") the best one.  Fortran asks pendula_kernel_path()
 * which path runs and calls pendula_rk4_lanes(),
 * pendula_taylor_series_lanes(), pendula_ke_block(), pendula_k_dd_block(),
 * pendula_jacobi_core_block(), pendula_libration_block() and
 * pendula_parameter_block(), which forward to them.
 * The choice is written once, before any call can read it.
 */
#include <stdlib.h>
#include <string.h>

enum { PATH_BASELINE = 0, PATH_V3 = 1, PATH_V4 = 2 };

#define LANES_ARGS void *, void *, void *, void *, void *, void *, void *, void *, void *, void *, \
    void *, void *, void *, void *, void *, void *, void *, void *, void *, void *
typedef void lanes_fn(LANES_ARGS);
typedef int width_fn(void);

extern lanes_fn pendula_rk4_lanes_baseline;
extern width_fn pendula_rk4_lanes_baseline_width;
#ifdef PENDULA_KERNEL_VARIANTS
extern lanes_fn pendula_rk4_lanes_v3;
extern lanes_fn pendula_rk4_lanes_v4;
extern width_fn pendula_rk4_lanes_v3_width;
extern width_fn pendula_rk4_lanes_v4_width;
#endif

typedef void series_fn(void *, void *, void *, void *, void *, void *, void *, void *);
extern series_fn pendula_taylor_series_lanes_baseline;
#ifdef PENDULA_KERNEL_VARIANTS
extern series_fn pendula_taylor_series_lanes_v3;
extern series_fn pendula_taylor_series_lanes_v4;
#endif

typedef void ke_fn(void *, void *, void *, void *, void *);
extern ke_fn pendula_ke_block_baseline;
#ifdef PENDULA_KERNEL_VARIANTS
extern ke_fn pendula_ke_block_v3;
extern ke_fn pendula_ke_block_v4;
#endif

typedef void kdd_fn(void *, void *, void *, void *, void *, void *, void *);
extern kdd_fn pendula_k_dd_block_baseline;
#ifdef PENDULA_KERNEL_VARIANTS
extern kdd_fn pendula_k_dd_block_v3;
extern kdd_fn pendula_k_dd_block_v4;
#endif

typedef void jcore_fn(void *, void *, void *, void *, void *, void *, void *);
extern jcore_fn pendula_jacobi_core_block_baseline;
#ifdef PENDULA_KERNEL_VARIANTS
extern jcore_fn pendula_jacobi_core_block_v3;
extern jcore_fn pendula_jacobi_core_block_v4;
#endif

typedef void libr_fn(void *, void *, void *, void *, void *, void *, void *, void *, void *, void *, void *,
    void *, void *);
extern libr_fn pendula_libration_block_baseline;
#ifdef PENDULA_KERNEL_VARIANTS
extern libr_fn pendula_libration_block_v3;
extern libr_fn pendula_libration_block_v4;
#endif

typedef void param_fn(void *, void *, void *, void *, void *, void *, void *, void *, void *, void *, void *);
extern param_fn pendula_parameter_block_baseline;
#ifdef PENDULA_KERNEL_VARIANTS
extern param_fn pendula_parameter_block_v3;
extern param_fn pendula_parameter_block_v4;
#endif

static int kernel_path = PATH_BASELINE;
static lanes_fn *rk4_lanes_impl = pendula_rk4_lanes_baseline;
static width_fn *rk4_lanes_width_impl = pendula_rk4_lanes_baseline_width;
static series_fn *taylor_series_impl = pendula_taylor_series_lanes_baseline;
static ke_fn *ke_block_impl = pendula_ke_block_baseline;
static kdd_fn *k_dd_block_impl = pendula_k_dd_block_baseline;
static jcore_fn *jacobi_core_impl = pendula_jacobi_core_block_baseline;
static libr_fn *libration_impl = pendula_libration_block_baseline;
static param_fn *parameter_impl = pendula_parameter_block_baseline;

/* 1 when this build has path p and this CPU (and OS) can run it. */
int pendula_kernel_available(const int *p)
{
    switch (*p) {
    case PATH_BASELINE:
        return 1;
#ifdef PENDULA_KERNEL_VARIANTS
    case PATH_V3:
        __builtin_cpu_init();
        return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")
            && __builtin_cpu_supports("bmi2");
    case PATH_V4:
        __builtin_cpu_init();
        return pendula_kernel_available(&(int){PATH_V3}) && __builtin_cpu_supports("avx512f")
            && __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512cd")
            && __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl");
#endif
    default:
        return 0;
    }
}

__attribute__((constructor)) static void choose_path(void)
{
    const char *want = getenv("PENDULA_KERNEL");
    int p = PATH_V4;
    if (want != NULL && strcmp(want, "baseline") == 0)
        p = PATH_BASELINE;
    else if (want != NULL && strcmp(want, "v3") == 0)
        p = PATH_V3;
    while (p > PATH_BASELINE && !pendula_kernel_available(&p))
        --p;
    kernel_path = p;
#ifdef PENDULA_KERNEL_VARIANTS
    if (p == PATH_V3) {
        rk4_lanes_impl = pendula_rk4_lanes_v3;
        rk4_lanes_width_impl = pendula_rk4_lanes_v3_width;
        taylor_series_impl = pendula_taylor_series_lanes_v3;
        ke_block_impl = pendula_ke_block_v3;
        k_dd_block_impl = pendula_k_dd_block_v3;
        jacobi_core_impl = pendula_jacobi_core_block_v3;
        libration_impl = pendula_libration_block_v3;
        parameter_impl = pendula_parameter_block_v3;
    } else if (p == PATH_V4) {
        rk4_lanes_impl = pendula_rk4_lanes_v4;
        rk4_lanes_width_impl = pendula_rk4_lanes_v4_width;
        taylor_series_impl = pendula_taylor_series_lanes_v4;
        ke_block_impl = pendula_ke_block_v4;
        k_dd_block_impl = pendula_k_dd_block_v4;
        jacobi_core_impl = pendula_jacobi_core_block_v4;
        libration_impl = pendula_libration_block_v4;
        parameter_impl = pendula_parameter_block_v4;
    }
#endif
}

/* The path the kernels run: 0 baseline, 1 x86-64-v3, 2 x86-64-v4. */
int pendula_kernel_path(void)
{
    return kernel_path;
}

/* The states per block (lanes) that the chosen path's kernel takes. */
int pendula_rk4_lanes_width(void)
{
    return rk4_lanes_width_impl();
}

/* The batch RK4 block kernel of the chosen path (arguments: see
 * pendula_rk4_lanes.F90, all by reference). */
void pendula_rk4_lanes(void *a1, void *a2, void *a3, void *a4, void *a5, void *a6, void *a7, void *a8,
    void *a9, void *a10, void *a11, void *a12, void *a13, void *a14, void *a15, void *a16, void *a17,
    void *a18, void *a19, void *a20)
{
    rk4_lanes_impl(a1, a2, a3, a4, a5, a6, a7, a8, a9, a10, a11, a12, a13, a14, a15, a16, a17, a18, a19,
        a20);
}

/* The Taylor batch's series kernel of the chosen path (arguments: see
 * pendula_taylor_series_lanes.F90, all by reference). */
void pendula_taylor_series_lanes(void *a1, void *a2, void *a3, void *a4, void *a5, void *a6, void *a7, void *a8)
{
    taylor_series_impl(a1, a2, a3, a4, a5, a6, a7, a8);
}

/* The block kernel of the K and E array forms of the chosen path (arguments:
 * see special/pendula_elliptic_ke_lanes.F90, all by reference). */
void pendula_ke_block(void *n, void *m, void *mc, void *second, void *x)
{
    ke_block_impl(n, m, mc, second, x);
}

/* The compensated AGM of K for a block of the chosen path (arguments: see
 * special/pendula_elliptic_k_lanes.F90, all by reference). */
void pendula_k_dd_block(void *nb, void *mch, void *mcl, void *hp, void *hp_lo, void *khi, void *klo)
{
    k_dd_block_impl(nb, mch, mcl, hp, hp_lo, khi, klo);
}

/* The core of the Jacobi array forms of the chosen path (arguments: see
 * special/pendula_jacobi_lanes.F90, all by reference). */
void pendula_jacobi_core_block(void *nb, void *v, void *m, void *mc, void *s, void *c, void *d)
{
    jacobi_core_impl(nb, v, m, mc, s, c, d);
}

/* The librations of undamped_states of the chosen path (arguments: see
 * undamped/pendula_undamped_lanes.F90, all by reference). */
void pendula_libration_block(void *n, void *q, void *ch, void *sh, void *w0, void *sa, void *ca, void *da,
    void *hp, void *hp_lo, void *atanp, void *theta, void *omega)
{
    libration_impl(n, q, ch, sh, w0, sa, ca, da, hp, hp_lo, atanp, theta, omega);
}

/* The elliptic parameter of a block of undamped states of the chosen path (arguments:
 * see undamped/pendula_undamped_parameter_lanes.F90, all by reference). */
void pendula_parameter_block(void *n, void *th, void *om, void *w, void *fast, void *hp, void *hp_lo,
    void *sh, void *ch, void *q, void *mc)
{
    parameter_impl(n, th, om, w, fast, hp, hp_lo, sh, ch, q, mc);
}
