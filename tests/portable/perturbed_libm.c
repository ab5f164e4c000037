/* A stand-in for another platform's maths library, loaded with LD_PRELOAD by
 * tests/integration/portable_maths.rs.
 *
 * Each function returns what the system's (glibc's) returns, moved by one unit in the last place when the
 * low bit of its first argument's representation is set: a library that is still accurate to within one
 * ulp, as glibc, macOS and Windows are, but rounds some results differently from glibc, as they do. A
 * program that calls the system maths library anywhere its results matter changes its output under it.
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

static int oddf(float x) { uint32_t b; memcpy(&b, &x, sizeof b); return (int)(b & 1u); }
static int odd(double x) { uint64_t b; memcpy(&b, &x, sizeof b); return (int)(b & 1u); }
static float nudgef(float r, float x) { return (oddf(x) && isfinite(r)) ? nextafterf(r, INFINITY) : r; }
static double nudge(double r, double x) { return (odd(x) && isfinite(r)) ? nextafter(r, INFINITY) : r; }

#define F1(name) \
    float name(float x) { \
        static float (*real)(float); \
        if (!real) real = (float (*)(float))dlsym(RTLD_NEXT, #name); \
        return nudgef(real(x), x); \
    }
#define F2(name) \
    float name(float y, float x) { \
        static float (*real)(float, float); \
        if (!real) real = (float (*)(float, float))dlsym(RTLD_NEXT, #name); \
        return nudgef(real(y, x), y); \
    }
#define D1(name) \
    double name(double x) { \
        static double (*real)(double); \
        if (!real) real = (double (*)(double))dlsym(RTLD_NEXT, #name); \
        return nudge(real(x), x); \
    }
#define D2(name) \
    double name(double y, double x) { \
        static double (*real)(double, double); \
        if (!real) real = (double (*)(double, double))dlsym(RTLD_NEXT, #name); \
        return nudge(real(y, x), y); \
    }

F1(sinf) F1(cosf) F1(tanf) F1(asinf) F1(acosf) F1(atanf) F1(expf) F1(exp2f) F1(logf) F1(log2f) F1(log10f)
F1(sinhf) F1(coshf) F1(tanhf) F1(cbrtf) F2(atan2f) F2(powf) F2(hypotf)
D1(sin) D1(cos) D1(tan) D1(asin) D1(acos) D1(atan) D1(exp) D1(exp2) D1(log) D1(log2) D1(log10)
D1(sinh) D1(cosh) D1(tanh) D1(cbrt) D2(atan2) D2(pow) D2(hypot)

/* Written through the real sincos, not as sin and cos: a compiler may turn that pair back into a sincos call. */
void sincosf(float x, float *s, float *c) {
    static void (*real)(float, float *, float *);
    if (!real) real = (void (*)(float, float *, float *))dlsym(RTLD_NEXT, "sincosf");
    real(x, s, c);
    *s = nudgef(*s, x);
    *c = nudgef(*c, x);
}
void sincos(double x, double *s, double *c) {
    static void (*real)(double, double *, double *);
    if (!real) real = (void (*)(double, double *, double *))dlsym(RTLD_NEXT, "sincos");
    real(x, s, c);
    *s = nudge(*s, x);
    *c = nudge(*c, x);
}
