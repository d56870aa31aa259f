/*
 * batch_kernel.h - the vectorised kernel of rps3_inverse_batch (internal).
 *
 * The kernel computes a block of points of the closed-form Lagrange
 * pipeline (pose -> IK (39) -> rates -> forces of the paper's four effects,
 * condition number, transmission, certificate) as one straight-line loop
 * body over the points, which the compiler vectorises.  It certifies each
 * point it computed (ok = 1) or leaves it to the scalar path (ok = 0); see
 * batch_kernel.c for what it certifies.
 */
#ifndef RPS3_BATCH_KERNEL_H
#define RPS3_BATCH_KERNEL_H

#include "internal.h"

/* points per block: the outputs of a block live on the stack */
#define RPS3_KBLOCK 64
/* the effects the kernel computes: the paper's four, indices 0..3 */
#define RPS3_KNEFF 4

/* the outputs of one block, component-major [c][i]: scratch for the
   outputs a caller does not ask for, and the tests' view of a block */
typedef struct {
  double l[3][RPS3_KBLOCK];              /* link lengths [m] */
  double theta[3][RPS3_KBLOCK];          /* (39) [rad] */
  double F[3][RPS3_KBLOCK];              /* forces [N] */
  double Fe[RPS3_KNEFF][3][RPS3_KBLOCK]; /* share of effect k [N] */
  double lambda[3][RPS3_KBLOCK];         /* multipliers [N/m] */
  double cond[RPS3_KBLOCK];   /* 1-norm condition of the lambda system */
  double trans[RPS3_KBLOCK];  /* force transmission [-] */
  double eres[RPS3_KBLOCK];   /* energy-rate residual [W] */
  double scale[RPS3_KBLOCK];  /* its scale (energy_scale) [W] */
  double dl[3][RPS3_KBLOCK];  /* link rates [m/s] */
  double ddl[3][RPS3_KBLOCK]; /* link accelerations [m/s^2] */
  double c[2][RPS3_KBLOCK];   /* platform centre x, y (3)-(4) [m] */
  double mode[RPS3_KBLOCK];   /* assembly mode, sign of det(df/dtheta) */
  double ok[RPS3_KBLOCK];     /* 1: certified; 0: the scalar path's
                                 (a double: no int in the loop) */
} rps3_kblock;

/* where the kernel writes a block's results: component c of the block's
   point p at X[c][p] (the caller's arrays, or a rps3_kblock's) */
typedef struct {
  double *l[3], *theta[3], *F[3], *Fe[RPS3_KNEFF][3], *lambda[3];
  double *dl[3], *ddl[3], *c[2];
  double *cond, *trans, *eres, *scale, *mode, *ok;
  rps3_data *d; /* RPS3_KDATA: the stages' positions and rates go here */
} rps3_kout;

/* what a call of the kernel computes */
typedef enum {
  RPS3_KFORCES, /* as RPS3_KLEAN, and no shares: the summed load solved
                   once (o->Fe is not written); with o->d, one point and
                   the stages' positions and rates into it */
  RPS3_KLEAN,   /* neither theta nor the certificate (F alone is asked for) */
  RPS3_KFULL,   /* every output */
  RPS3_KDATA    /* one point, every output and the stages' positions, rates
                   and certificate terms into o->d (rps3_inverse) */
} rps3_kkind;

/* o pointing into every array of kb */
void rps3_kout_of_block(rps3_kout *o, rps3_kblock *kb);

/* 1 when the kernel serves model m: closed-form theta, Lagrange, the
   paper's bodies and only the paper's four effects */
static inline int rps3_kernel_covers(const rps3_model *m) {
  return m->opt.theta == RPS3_THETA_CLOSED_FORM &&
         m->opt.method == RPS3_LAGRANGE && m->bodies == RPS3_BODIES_PAPER &&
         (m->opt.effects & ~RPS3_EFF_DEFAULT) == 0;
}

/* 1 when rps3_inverse and the batch solve the summed load once on the
   kernel's route (RPS3_KFORCES): no shares, no theta and no certificate
   asked for (rps3.h, enum rps3_output) */
static inline int rps3_kernel_summed(const rps3_model *m) {
  return !(m->opt.outputs &
           (RPS3_OUT_EFFECTS | RPS3_OUT_THETA | RPS3_OUT_CERTIFY));
}

/* points i0 .. i0 + nb - 1 (nb <= RPS3_KBLOCK; 1 for RPS3_KDATA) of the
   batch into *o; the rates are read when rates is 1, else taken as zero;
   RPS3_KLEAN computes neither theta nor the certificate (o->theta is then
   not written, and the residual is 0: for a model without the
   certificate) */
void rps3_kernel_block(const rps3_model *m, const rps3_batch_in *in, size_t i0,
                       int nb, int rates, rps3_kkind kind, const rps3_kout *o);

/* rps3_inverse on the kernel's configurations: the point d->pose (rates
   d->dpose, d->ddpose) by the kernel.  Returns 1 when the kernel certified
   it and d holds its results -- everything the stages would leave in d
   -- or 0 when the point is the stages' (nothing of d is then
   meaningful: the caller computes it by the stages).  With
   rps3_kernel_summed, the pass without theta and shares (the summed load
   solved once) */
int rps3_inverse_kernel_point(const rps3_model *m, rps3_data *d);

/* outputs = RPS3_OUT_FORCES: the leanest pass over points i0 .. i0 + nb - 1 of
   the batch: F (into F[c][p]), cond and ok (1: the pass's point, 0: the
   stages'); the rates read when rates is 1, else taken as zero */
void rps3_kernel_block_bare(const rps3_model *m, const rps3_batch_in *in,
                            size_t i0, int nb, int rates, double *const F[3],
                            double *cond, double *ok);

/* rps3_inverse with outputs = RPS3_OUT_FORCES on the kernel's
   configurations: the leanest pass on d->pose (d->dpose, d->ddpose when
   an effect needs them).  Returns 1 when the pass kept the point (d->F,
   d->cond written, the other results NaN, d->stage 0, warn 0), or 0 when
   the point is the stages' (d untouched) */
int rps3_inverse_lean_point(const rps3_model *m, rps3_data *d);

/* the same without fused multiply-adds whatever the CPU, as a CPU without
   FMA computes it (for the tests) */
int rps3_inverse_lean_point_unfused(const rps3_model *m, rps3_data *d);

/* rps3_inverse by the stages alone (the kernel's fallback) */
int rps3_inverse_stages(const rps3_model *m, rps3_data *d);

/* the vector code's sine and cosine (batch_trig.h's ksincos without
   fused multiply-adds), and its atan2 for y > 0, one value at a time (for
   the tests: the accuracy against libm) */
void rps3_ksincos(double x, double *s, double *c);
double rps3_katan2(double y, double x);
/* the same sine and cosine with fu as the lean pass picks it (1: fused
   multiply-adds), for the same tests */
void rps3_ksincos_e(double x, int fu, double *s, double *c);

/* the leanest pass's upper bound of the force transmission at a pose (for
   the tests: against the stages' transmission) */
double rps3_lean_trans_bound(const rps3_model *m, const double pose[3]);

/* the largest |angle| the kernel's range reduction serves [rad] */
#define RPS3_KANGLE_MAX 1.0e5

#endif /* RPS3_BATCH_KERNEL_H */
