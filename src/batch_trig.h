/*
 * batch_trig.h - the elementary functions of the batch kernel
 * (batch_kernel.c): sine, cosine and atan2 without a libm call, a branch
 * or a table, so that a loop calling them vectorises.  Accuracy against
 * libm: tests/test_batch_kernel.c.  Internal; included through
 * batch_kmech.h by batch_kernel.c only.
 */
#ifndef RPS3_BATCH_TRIG_H
#define RPS3_BATCH_TRIG_H

#include <math.h>

/* the helpers of the loop body must be inlined into it to be vectorised */
#if defined(__GNUC__)
#define KINLINE static inline __attribute__((always_inline))
#else
#define KINLINE static inline
#endif

/* pi/2 in three parts, 30 + 30 + 53 bits: k * P1 and k * P2 are exact for
   |k| < 2^23, so that x - k pi/2 loses nothing for |x| <= RPS3_KANGLE_MAX */
#define P1 0x1.921fb548p+0
#define P2 (-0x1.de973dc8p-31)
#define P3 (-0x1.9d9cceba3f91fp-62)
#define TWO_OVER_PI 0x1.45f306dc9c883p-1
/* pi and pi/2 as double + remainder */
#define PI_HI 0x1.921fb54442d18p+1
#define PI_LO 0x1.1a62633145c07p-53
#define PIO2_HI 0x1.921fb54442d18p+0
#define PIO2_LO 0x1.1a62633145c07p-54
/* atan(j / 4), j = 1 .. 4, correctly rounded */
#define ATAN_1_4 0x1.f5b75f92c80ddp-3
#define ATAN_2_4 0x1.dac670561bb4fp-2
#define ATAN_3_4 0x1.4978fa3269ee1p-1
#define ATAN_4_4 0x1.921fb54442d18p-1
/* x + SHIFT - SHIFT rounds x to an integer, |x| < 2^51 */
#define SHIFT 0x1.8p52

/*
 * sin x and cos x for |x| <= RPS3_KANGLE_MAX, without a branch or a table:
 * the one sine and cosine of the vector code (the batch kernel and the
 * lean pass; libm everywhere else).  x = k pi/2 + r with |r| <= pi/4
 * (Cody-Waite reduction), the Taylor series of sin r to r^17 and of cos r
 * to r^16 (truncation below 1e-19 on |r| <= pi/4, so the error is the
 * rounding of the evaluation), and the quadrant k mod 4 by selects.  The
 * series are evaluated by Estrin's scheme: the terms grouped in pairs and
 * powers of r^4 and r^8, so that the longest chain of dependent operations
 * is about half as long as Horner's (every quantity of a point depends on
 * the pose's sines).  With fu = 1 each pair a + b r^2 is one fused
 * multiply-add (fma: the CPU's instruction where the lean pass uses it).
 * Within 3 ulp of libm either way (tests/test_batch_kernel.c).  A NaN
 * gives NaN; beyond the range the result is wrong, and the kernel leaves
 * such points to the scalar path.
 */
typedef struct {
  double s, c;
} ksc;

KINLINE double kmaf(double a, double b, double c, int fu) {
  return fu ? fma(a, b, c) : a * b + c;
}

KINLINE ksc ksincos(double x, int fu) {
  ksc out;
  double k = (x * TWO_OVER_PI + SHIFT) - SHIFT;
  double r = ((x - k * P1) - k * P2) - k * P3;
  double r2 = r * r, r4 = r2 * r2, r8 = r4 * r4;
  double ps = kmaf(
      r * r2,
      kmaf(r4, kmaf(r2, 1.0 / 362880.0, -1.0 / 5040.0, fu),
           kmaf(r2, 1.0 / 120.0, -1.0 / 6.0, fu), fu) +
          r8 * kmaf(r4,
                    kmaf(r2, 1.0 / 355687428096000.0, -1.0 / 1307674368000.0,
                         fu),
                    kmaf(r2, 1.0 / 6227020800.0, -1.0 / 39916800.0, fu), fu),
      r, fu);
  double pc = kmaf(
      r4,
      kmaf(r4, kmaf(r2, -1.0 / 3628800.0, 1.0 / 40320.0, fu),
           kmaf(r2, -1.0 / 720.0, 1.0 / 24.0, fu), fu) +
          r8 * kmaf(r4, 1.0 / 20922789888000.0,
                    kmaf(r2, -1.0 / 87178291200.0, 1.0 / 479001600.0, fu), fu),
      1.0 - 0.5 * r2, fu);
  /* the quadrant k mod 4 as q = k - 4 round(k / 4) in {-2, ..., 2}, in
     floating point: no conversion to an integer (undefined for a NaN) */
  double q = k - 4.0 * ((0.25 * k + SHIFT) - SHIFT);
  double sn = ((q == 1.0) | (q == -1.0)) ? pc : ps;
  double cs = ((q == 1.0) | (q == -1.0)) ? ps : pc;
  out.s = ((q >= 2.0) | (q <= -1.0)) ? -sn : sn; /* k mod 4 = 2, 3 */
  out.c = ((q >= 1.0) | (q <= -2.0)) ? -cs : cs; /* k mod 4 = 1, 2 */
  return out;
}

/*
 * atan2(y, x) for y > 0, so in (0, pi): with a = num / den = min(|x|, y) /
 * max(|x|, y) in [0, 1], atan a = atan(j/4) + atan u for j/4 the quarter
 * nearest to a (chosen by comparisons) and u = (a - j/4) / (1 + a j/4) =
 * (num - c den) / (den + c num), |u| <= 1/8 up to rounding, in one
 * division; atan u by its Taylor series to u^19 (truncation below 2^-63
 * |u|); then the octant by selects.
 */
KINLINE double katan2(double y, double x) {
  double ax = fabs(x);
  double num = ax > y ? y : ax, den = ax > y ? ax : y, j, c, u, u2, at, off;
  den = den > 0.0 ? den : 1.0; /* x = y = 0 is no point of the kernel's */
  j = (8.0 * num > den ? 1.0 : 0.0) + (8.0 * num > 3.0 * den ? 1.0 : 0.0) +
      (8.0 * num > 5.0 * den ? 1.0 : 0.0) + (8.0 * num > 7.0 * den ? 1.0 : 0.0);
  c = 0.25 * j;
  u = (num - c * den) / (den + c * num);
  u2 = u * u;
  at =
      u +
      u * u2 *
          (-1.0 / 3.0 +
           u2 * (1.0 / 5.0 +
                 u2 * (-1.0 / 7.0 +
                       u2 * (1.0 / 9.0 +
                             u2 * (-1.0 / 11.0 +
                                   u2 * (1.0 / 13.0 +
                                         u2 * (-1.0 / 15.0 +
                                               u2 * (1.0 / 17.0 +
                                                     u2 * (-1.0 / 19.0)))))))));
  off = j == 1.0   ? ATAN_1_4
        : j == 2.0 ? ATAN_2_4
        : j == 3.0 ? ATAN_3_4
        : j == 4.0 ? ATAN_4_4
                   : 0.0;
  at = off + at;
  /* from the x axis when |x| > y, else from the y axis; then x < 0 */
  at = ax > y ? at : (PIO2_HI - at) + PIO2_LO;
  return x < 0.0 ? (PI_HI - at) + PI_LO : at;
}

#endif /* RPS3_BATCH_TRIG_H */
