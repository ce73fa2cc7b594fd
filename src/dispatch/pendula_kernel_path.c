/* Runtime dispatch of pendula's hot kernels: which compiled variant runs.
 *
 * Each kernel of PENDULA_KERNELS below is a leaf (src/dispatch/meson.build's
 * kernel_leaves names its source) compiled for baseline x86-64 (SSE2),
 * x86-64-v3 (AVX2, FMA, BMI2) and x86-64-v4 (AVX-512 F, BW, CD, DQ, VL) when
 * meson builds for x86_64 (PENDULA_KERNEL_VARIANTS), as pendula_<name>_baseline,
 * _v3 and _v4, and only in its portable form elsewhere.  The path is chosen
 * once, when the library is loaded (a constructor), from the CPU's features
 * as libgcc reads them (cpuid, with the OS's XSAVE support of the wider
 * registers), as NumPy and OpenBLAS do.  The environment variable
 * PENDULA_KERNEL = baseline, v3 or v4 asks for one path (for reproducibility
 * and for the tests); a path the CPU cannot run gives the best one it can
 * below it, and any other value (or none, or "auto") the best one.  Fortran
 * asks pendula_kernel_path() which path runs and calls pendula_<name>(), the
 * forwarders at the end of this file.  The choice is written once, before
 * any call can read it.
 */
#include <stdlib.h>
#include <string.h>

enum { PATH_BASELINE = 0, PATH_V3 = 1, PATH_V4 = 2 };

/* The kernels' signatures (all arguments by reference: see each leaf). */
#define ARGS7 void *, void *, void *, void *, void *, void *, void *
typedef void lanes_fn(ARGS7, ARGS7, void *, void *, void *, void *, void *, void *);
typedef int width_fn(void);
typedef void series_fn(ARGS7, void *);
typedef void ke_fn(void *, void *, void *, void *, void *);
typedef void kdd_fn(ARGS7);
typedef void jcore_fn(ARGS7);
typedef void libr_fn(ARGS7, void *, void *, void *, void *, void *, void *);
typedef void param_fn(ARGS7, void *, void *, void *, void *);

/* Every dispatched kernel, X(name, type): the one list of them here. */
#define PENDULA_KERNELS(X) \
    X(rk4_lanes, lanes_fn) \
    X(rk4_lanes_width, width_fn) \
    X(taylor_series_lanes, series_fn) \
    X(ke_block, ke_fn) \
    X(k_dd_block, kdd_fn) \
    X(jacobi_core_block, jcore_fn) \
    X(libration_block, libr_fn) \
    X(parameter_block, param_fn)

#ifdef PENDULA_KERNEL_VARIANTS
#define DECLARE(name, type) \
    extern type pendula_##name##_baseline, pendula_##name##_v3, pendula_##name##_v4;
#else
#define DECLARE(name, type) extern type pendula_##name##_baseline;
#endif
PENDULA_KERNELS(DECLARE)

#define IMPL(name, type) static type *name##_impl = pendula_##name##_baseline;
PENDULA_KERNELS(IMPL)

static int kernel_path = PATH_BASELINE;

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
#define PICK(name, type) \
    name##_impl = p == PATH_V4 ? pendula_##name##_v4 : p == PATH_V3 ? pendula_##name##_v3 : name##_impl;
    PENDULA_KERNELS(PICK)
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
    taylor_series_lanes_impl(a1, a2, a3, a4, a5, a6, a7, a8);
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
    jacobi_core_block_impl(nb, v, m, mc, s, c, d);
}

/* The librations of undamped_states of the chosen path (arguments: see
 * undamped/pendula_undamped_lanes.F90, all by reference). */
void pendula_libration_block(void *n, void *q, void *ch, void *sh, void *w0, void *sa, void *ca, void *da,
    void *hp, void *hp_lo, void *atanp, void *theta, void *omega)
{
    libration_block_impl(n, q, ch, sh, w0, sa, ca, da, hp, hp_lo, atanp, theta, omega);
}

/* The elliptic parameter of a block of undamped states of the chosen path (arguments:
 * see undamped/pendula_undamped_parameter_lanes.F90, all by reference). */
void pendula_parameter_block(void *n, void *th, void *om, void *w, void *fast, void *hp, void *hp_lo,
    void *sh, void *ch, void *q, void *mc)
{
    parameter_block_impl(n, th, om, w, fast, hp, hp_lo, sh, ch, q, mc);
}
