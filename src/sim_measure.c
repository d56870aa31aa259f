/*
 * sim_measure.c - the simulated plant's sensors and actuators: measured
 * lengths and rates with seeded Gaussian noise (splitmix64 + Box-Muller,
 * reproducible from opt.seed) and quantisation, and the actuators'
 * saturation at opt.fmax.  Called once a control tick by src/sim.c.
 */
#include "sim.h"

/* ------------------------------------------------------------ noise */

/* splitmix64: a full-period 64-bit generator with one word of state */
static unsigned long long next_u64(unsigned long long *s) {
  unsigned long long z = (*s += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

/* uniform in (0, 1): 53 random bits, never 0 */
static double next_open01(unsigned long long *s) {
  return ((double)(next_u64(s) >> 11) + 0.5) * (1.0 / 9007199254740992.0);
}

/* standard normal deviate, Box-Muller; the second deviate is kept */
static double next_normal(rps3_sim *s) {
  double u1, u2, r;
  if (!isnan(s->spare)) {
    r = s->spare;
    s->spare = (double)NAN;
    return r;
  }
  u1 = next_open01(&s->rng);
  u2 = next_open01(&s->rng);
  r = sqrt(-2.0 * log(u1));
  s->spare = r * sin(2.0 * RPS3_PI * u2);
  return r * cos(2.0 * RPS3_PI * u2);
}

/* x as the sensor reads it: Gaussian noise of deviation sigma, then the
   quantum q (either 0: none) */
double rps3_sim_measure(rps3_sim *s, double x, double sigma, double q) {
  if (sigma > 0.0) x += sigma * next_normal(s);
  if (q > 0.0) x = q * nearbyint(x / q);
  return x;
}

/* clamp to the actuators' limit; returns 1 when one saturated */
int rps3_sim_saturate(const rps3_sim *s, const double Fc[3], double F[3]) {
  int i, sat = 0;
  for (i = 0; i < 3; i++) {
    F[i] = Fc[i];
    if (s->opt.fmax > 0.0 && fabs(F[i]) > s->opt.fmax) {
      F[i] = copysign(s->opt.fmax, F[i]);
      sat = 1;
    }
  }
  return sat;
}
