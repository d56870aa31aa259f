/*
 * batch_kernel.c - the vectorised kernel of rps3_inverse_batch: a block of
 * points of the closed-form Lagrange pipeline as one straight-line loop
 * body, structure of arrays in and out, which the compiler vectorises
 * (`#pragma omp simd`, built with -fopenmp-simd -fno-math-errno
 * -ffp-contract=off; with GCC or clang on x86-64 the loop is also compiled
 * for AVX2 and AVX-512 and the widest one the CPU runs is picked at load
 * time).
 *
 * The formulas are those of the scalar stages, in the same order where it
 * matters: (2)-(7) and (39) as in ik.c, the rates as in velocity.c; the
 * Lagrange loads (src/loads.h), the energy-rate certificate and the force
 * transmission (src/power.h) are the stages' own text.  What differs, all
 * at the level of rounding:
 *   - sin and cos of alpha and beta / 2 by the polynomial ksincos
 *     (batch_trig.h, the lean pass's too; within 3 ulp of libm), sin and
 *     cos of beta from the half angle; theta by katan2 (within 4 ulp of
 *     libm's atan2);
 *   - the lambda system (df/dtheta)^T solved by its adjugate (the matrix
 *     has two non-zeros a row), and its 1-norm condition number from the
 *     same inverse;
 *   - the force transmission's link rates per unit link rate from that
 *     inverse (the stages' from the LU of the lambda system).
 * Without theta asked for and without the certificate, a second instance
 * of the loop leaves both out (the forces need the link directions only).
 * A point is certified (ok) only when everything it reports is finite, its
 * links are reachable, and its condition number and transmission are below
 * min(warn, max) by a relative margin far above the rounding differences
 * (the scalar path would then also return RPS3_OK without a warning): all
 * else (non-finite or out-of-range input, unreachable, near a threshold)
 * is the scalar path's, point by point.
 */
#include <float.h>
#include <string.h>

#include "batch_kernel.h"
#include "batch_kmech.h"

/* a loop the compiler could not vectorise (e.g. at -O1 under the
   sanitizers) is slower, not wrong: not a warning */
#if defined(__clang__)
#pragma clang diagnostic ignored "-Wpass-failed"
#endif

/* the kernel's relative margin to the condition and transmission
   thresholds: the scalar path's values differ from the kernel's by a few
   cond * eps (<= 1e6 * 1.1e-16 = 1.1e-10 below cond_warn) */
#define KMARGIN 1e-6

void rps3_ksincos(double x, double *s, double *c) {
  ksc r = ksincos(x, 0);
  *s = r.s;
  *c = r.c;
}
double rps3_katan2(double y, double x) { return katan2(y, x); }
void rps3_ksincos_e(double x, int fu, double *s, double *c) {
  ksc r = fu ? ksincos(x, 1) : ksincos(x, 0);
  *s = r.s;
  *c = r.c;
}

void rps3_kout_of_block(rps3_kout *o, rps3_kblock *kb) {
  int c, e;
  for (c = 0; c < 3; c++) {
    o->l[c] = kb->l[c];
    o->theta[c] = kb->theta[c];
    o->F[c] = kb->F[c];
    o->lambda[c] = kb->lambda[c];
    o->dl[c] = kb->dl[c];
    o->ddl[c] = kb->ddl[c];
    for (e = 0; e < RPS3_KNEFF; e++) o->Fe[e][c] = kb->Fe[e][c];
  }
  o->c[0] = kb->c[0];
  o->c[1] = kb->c[1];
  o->cond = kb->cond;
  o->trans = kb->trans;
  o->eres = kb->eres;
  o->scale = kb->scale;
  o->mode = kb->mode;
  o->ok = kb->ok;
  o->d = NULL;
}

/* what an instance of the loop body computes besides l, F, lambda, the
   rates, cond, trans, mode and ok: each bit one thing, a constant of
   each instance below (KLOOP, KONE), so that what is left out is not
   compiled in */
#define KF_THETA 1   /* theta (39) into o->theta */
#define KF_CERTIFY 2 /* the energy-rate certificate (power, scale) */
/* each effect's load solved on its own, F_effect into o->Fe; without it
   the summed load is solved once, as the scalar path does without
   RPS3_OUT_EFFECTS */
#define KF_SHARES 4
/* the stages' positions, rates and the certificate's terms into o->d (the
   one-point instances) */
#define KF_DATA 8

/* point p of the block: the loop body, with flags a constant (KF_*) */
KINLINE void kpoint(const kconst *K, const double *restrict pa,
                    const double *restrict pb, const double *restrict pz,
                    const double *restrict va, const double *restrict vb,
                    const double *restrict vz, const double *restrict aa,
                    const double *restrict ab, const double *restrict az, int p,
                    const rps3_kout *restrict o, int flags) {
  {
    double alpha = pa[p], beta = pb[p];
    double da = va[p], db = vb[p], dda = aa[p], ddb = ab[p];
    double det, idet, cond, trans, fin;
    double pw, sc, dT, dP, v1, v2, g1, i1, s1, s2, s3, s4, eres;
    kv3 rx, ry, rz, c, w, vc, dw, ac, cdd, lc, le, ta, tb, r0, r1, r2;
    kv3 wl[RPS3_KNEFF], wt[RPS3_KNEFF], lam[RPS3_KNEFF], Fe[RPS3_KNEFF];
    kv3 F, lamt;
    klink L0, L1, L2;
    krow j0, j1, j2;
    /* the frame, its twist and the twist's rate; an angle the
       reduction does not serve is no point of the kernel's: it is left
       to the scalar path */
    const kpose P =
        kpose_eval(K->r, alpha, beta, pz[p], da, db, vz[p], dda, ddb, az[p], 0);
    const double in_range = P.in_range;
    rx = P.rx;
    ry = P.ry;
    rz = P.rz;
    c = P.c;
    w = P.w;
    vc = P.vc;
    dw = P.dw;
    ac = P.ac;
    L0 = link_pos(K, 0, rx, ry, c, (flags & KF_THETA) != 0);
    L1 = link_pos(K, 1, rx, ry, c, (flags & KF_THETA) != 0);
    L2 = link_pos(K, 2, rx, ry, c, (flags & KF_THETA) != 0);

    L0 = link_rates(L0, w, vc, dw, ac);
    L1 = link_rates(L1, w, vc, dw, ac);
    L2 = link_rates(L2, w, vc, dw, ac);
    /* the one-point instances: the stages' positions and rates into the
       data now, while they are at hand */
    if (flags & KF_DATA)
      kdata(o->d, rx, ry, rz, L0, L1, L2, w, vc, dw, ac, K->rates != 0.0);
    cdd = kadd(kadd(kscale(1.0 / 3.0, L0.bdd), kscale(1.0 / 3.0, L1.bdd)),
               kscale(1.0 / 3.0, L2.bdd));

    /* constraint Jacobian; Jt = [ta.x tb.x 0; 0 ta.y tb.y; tb.z 0 ta.z]
       inverted by its adjugate (rows r0, r1, r2) */
    j0 = jac_row(L0, L1);
    j1 = jac_row(L1, L2);
    j2 = jac_row(L2, L0);
    lc = kv(j0.lc, j1.lc, j2.lc);
    le = kv(j0.le, j1.le, j2.le);
    ta = kv(j0.ta, j1.ta, j2.ta);
    tb = kv(j0.tb, j1.tb, j2.tb);
    det = ta.x * ta.y * ta.z + tb.x * tb.y * tb.z;
    idet = 1.0 / (det != 0.0 ? det : HUGE_VAL);
    r0 = kscale(idet, kv(ta.y * ta.z, -tb.x * ta.z, tb.x * tb.y));
    r1 = kscale(idet, kv(tb.y * tb.z, ta.x * ta.z, -ta.x * tb.y));
    r2 = kscale(idet, kv(-ta.y * tb.z, tb.x * tb.z, ta.x * ta.y));
    /* 1-norm condition of the lambda system A = Jt^T: column sums of |A|
       are the row sums of |Jt|, those of |A^-1| the row sums of |Jt^-1| */
    {
      double an = fabs(ta.x) + fabs(tb.x), a1 = fabs(ta.y) + fabs(tb.y);
      double a2 = fabs(ta.z) + fabs(tb.z), in0 = knorm1(r0);
      double in1 = knorm1(r1), in2 = knorm1(r2);
      an = a1 > an ? a1 : an;
      an = a2 > an ? a2 : an;
      in0 = in1 > in0 ? in1 : in0;
      in0 = in2 > in0 ? in2 : in0;
      cond = det != 0.0 ? an * in0 : HUGE_VAL;
    }

    /* force transmission, row by row: x = -Jt^-1 (column e of Jl) */
    {
      kv3 c0 = kv(r0.x, r1.x, r2.x), c1 = kv(r0.y, r1.y, r2.y);
      kv3 c2 = kv(r0.z, r1.z, r2.z);
      kv3 Q0 = kcross(L0.rho, L0.dphi), Q1 = kcross(L1.rho, L1.dphi);
      kv3 Q2 = kcross(L2.rho, L2.dphi);
      double t0, t1, t2;
      /* column 0 of Jl: lc.x in row 0, le.z in row 2; and so on */
      t0 = trans_row(K, L0, L1, L2, Q0, Q1, Q2,
                     kscale(-1.0, kadd(kscale(lc.x, c0), kscale(le.z, c2))),
                     L0.phi, kcross(L0.rho, L0.phi), rz);
      t1 = trans_row(K, L0, L1, L2, Q0, Q1, Q2,
                     kscale(-1.0, kadd(kscale(le.x, c0), kscale(lc.y, c1))),
                     L1.phi, kcross(L1.rho, L1.phi), rz);
      t2 = trans_row(K, L0, L1, L2, Q0, Q1, Q2,
                     kscale(-1.0, kadd(kscale(le.y, c1), kscale(lc.z, c2))),
                     L2.phi, kcross(L2.rho, L2.phi), rz);
      trans = t1 > t0 ? t1 : t0;
      trans = t2 > trans ? t2 : trans;
    }

    /* loads of the four effects, wl on l_i and wt on theta_i: each
       link's of src/loads.h (as lagrange_effect of invdyn.c), times the
       selection */
    RPS3_LOAD_PLATFORM_GRAVITY(K->Mg3, L0.phi.z, L0.dphi.z, L0.l, wl[0].x,
                               wt[0].x);
    RPS3_LOAD_PLATFORM_GRAVITY(K->Mg3, L1.phi.z, L1.dphi.z, L1.l, wl[0].y,
                               wt[0].y);
    RPS3_LOAD_PLATFORM_GRAVITY(K->Mg3, L2.phi.z, L2.dphi.z, L2.l, wl[0].z,
                               wt[0].z);
    wl[0] = kscale(K->sel[0], wl[0]);
    wt[0] = kscale(K->sel[0], wt[0]);
    wl[1] = kv(0.0, 0.0, 0.0);
    RPS3_LOAD_LINK_GRAVITY(K->sel[1] * K->mgd, L0.dphi.z, wt[1].x);
    RPS3_LOAD_LINK_GRAVITY(K->sel[1] * K->mgd, L1.dphi.z, wt[1].y);
    RPS3_LOAD_LINK_GRAVITY(K->sel[1] * K->mgd, L2.dphi.z, wt[1].z);
    RPS3_LOAD_PLATFORM_INERTIA(KC, K->M6, cdd, L0.bdd, L0.phi, L0.dphi, L0.l,
                               wl[2].x, wt[2].x);
    RPS3_LOAD_PLATFORM_INERTIA(KC, K->M6, cdd, L1.bdd, L1.phi, L1.dphi, L1.l,
                               wl[2].y, wt[2].y);
    RPS3_LOAD_PLATFORM_INERTIA(KC, K->M6, cdd, L2.bdd, L2.phi, L2.dphi, L2.l,
                               wl[2].z, wt[2].z);
    wl[2] = kscale(K->sel[2], wl[2]);
    wt[2] = kscale(K->sel[2], wt[2]);
    wl[3] = kv(0.0, 0.0, 0.0);
    RPS3_LOAD_LINK_INERTIA(K->sel[3] * K->Jlink, L0.ddth, wt[3].x);
    RPS3_LOAD_LINK_INERTIA(K->sel[3] * K->Jlink, L1.ddth, wt[3].y);
    RPS3_LOAD_LINK_INERTIA(K->sel[3] * K->Jlink, L2.ddth, wt[3].z);

    /* (df/dtheta)^T lambda = -wt per effect, then (34); F and lambda
       are the sums of the effects' (without shares the scalar path
       solves the summed load once: the same to rounding) */
    if (!(flags & KF_SHARES)) {
      /* no shares asked for: the summed load solved once, as the
         scalar path does without RPS3_OUT_EFFECTS */
      lamt = klambda(r0, r1, r2, kadd(kadd(kadd(wt[0], wt[1]), wt[2]), wt[3]));
      F = kforces(kadd(kadd(kadd(wl[0], wl[1]), wl[2]), wl[3]), lamt, lc, le);
    } else {
      lam[0] = klambda(r0, r1, r2, wt[0]);
      lam[1] = klambda(r0, r1, r2, wt[1]);
      lam[2] = klambda(r0, r1, r2, wt[2]);
      lam[3] = klambda(r0, r1, r2, wt[3]);
      Fe[0] = kforces(wl[0], lam[0], lc, le);
      Fe[1] = kforces(wl[1], lam[1], lc, le);
      Fe[2] = kforces(wl[2], lam[2], lc, le);
      Fe[3] = kforces(wl[3], lam[3], lc, le);
      F = kadd(kadd(kadd(Fe[0], Fe[1]), Fe[2]), Fe[3]);
      lamt = kadd(kadd(kadd(lam[0], lam[1]), lam[2]), lam[3]);
    }

    /* energy-rate certificate (certify of invdyn.c): power = dT/dt +
       dP/dt, each effect's term and its share of the scale those of
       src/power.h, the selection folded into their coefficients */
    pw = sc = dT = dP = 0.0;
    if (flags & KF_CERTIFY) {
      const kv3 cz = kv(L0.dphi.z, L1.dphi.z, L2.dphi.z);
      const kv3 dth = kv(L0.dth, L1.dth, L2.dth);
      const kv3 ddth = kv(L0.ddth, L1.ddth, L2.ddth);
      RPS3_POWER_ACTUATORS(KC, F, kv(L0.dl, L1.dl, L2.dl), pw, sc);
      RPS3_POWER_BODY_GRAVITY(K->sel[0] * K->M * K->g, vc.z, v1, s1);
      RPS3_POWER_BODY_INERTIA(KC, K->sel[2] * K->M, K->sel[2], K->Ip, rx, ry,
                              rz, vc, ac, w, dw, v2, s2);
      RPS3_POWER_LINK_GRAVITY(KC, K->sel[1] * K->mgd, cz, dth, g1, s3);
      RPS3_POWER_LINK_INERTIA(KC, K->sel[3] * K->Jlink, dth, ddth, i1, s4);
      dP = v1 + g1;
      dT = v2 + i1;
      sc += s1 + s2 + s3 + s4;
    }

    /* the outputs, and whether the point is the kernel's: finite, in
       reach, below the thresholds */
    kst(o->l, p, kv(L0.l, L1.l, L2.l));
    if (flags & KF_THETA) kst(o->theta, p, kv(L0.th, L1.th, L2.th));
    kst(o->F, p, F);
    kst(o->lambda, p, lamt);
    if (flags & KF_SHARES) {
      kst(o->Fe[0], p, Fe[0]);
      kst(o->Fe[1], p, Fe[1]);
      kst(o->Fe[2], p, Fe[2]);
      kst(o->Fe[3], p, Fe[3]);
    }
    kst(o->dl, p, kv(L0.dl, L1.dl, L2.dl));
    kst(o->ddl, p, kv(L0.ddl, L1.ddl, L2.ddl));
    o->c[0][p] = c.x;
    o->c[1][p] = c.y;
    o->cond[p] = cond;
    o->trans[p] = trans;
    o->mode[p] = (det > 0.0) ? 1.0 : (det < 0.0) ? -1.0 : 0.0;
    eres = K->certify != 0.0 ? RPS3_POWER_RESIDUAL(pw, dT, dP) : 0.0;
    o->eres[p] = eres;
    o->scale[p] = K->certify != 0.0 ? sc : 0.0;
    /* every quantity the scalar path checks for overflow reaches F,
       lambda or the certificate here (the loads of unselected effects
       are multiplied by 0, which keeps a NaN, and nothing divides by a
       rate), and a non-finite input makes them non-finite */
    fin =
        sc + fabs(eres) + knorm1(F) + knorm1(lamt) + L0.l + L1.l + L2.l + trans;
    /* & rather than &&: no branch in the loop body */
    o->ok[p] = ((in_range * L0.ok * L1.ok * L2.ok != 0.0) & (fin <= DBL_MAX) &
                (cond <= K->cond_lim) & (trans <= K->trans_lim))
                   ? 1.0
                   : 0.0;
    if (flags & KF_DATA) {
      /* the certificate's terms, zero without it (rps3_invdyn) */
      o->d->power = K->certify != 0.0 ? pw : 0.0;
      o->d->dTdt = K->certify != 0.0 ? dT : 0.0;
      o->d->dPdt = K->certify != 0.0 ? dP : 0.0;
      o->d->friction_power = 0.0;
    }
  }
}

/* the block kernels: every output; the shares without theta and the
   certificate; the forces alone */
#define KLOOP(name, flags)                                               \
  KCLONES                                                                \
  static void name(const kconst *K, const double *restrict pa,           \
                   const double *restrict pb, const double *restrict pz, \
                   const double *restrict va, const double *restrict vb, \
                   const double *restrict vz, const double *restrict aa, \
                   const double *restrict ab, const double *restrict az, \
                   int nb, const rps3_kout *restrict o) {                \
    int p;                                                               \
    _Pragma("omp simd") for (p = 0; p < nb; p++)                         \
        kpoint(K, pa, pb, pz, va, vb, vz, aa, ab, az, p, o, flags);      \
  }
KLOOP(kloop_full, KF_THETA | KF_CERTIFY | KF_SHARES)
KLOOP(kloop_lean, KF_SHARES)
KLOOP(kloop_forces, 0)

/* one point and the stages' data, scalar code for rps3_inverse: every
   output, or F without shares on the controller's path */
#define KONE(name, flags)                                                \
  KCLONES                                                                \
  static void name(const kconst *K, const double *pa, const double *pb,  \
                   const double *pz, const double *va, const double *vb, \
                   const double *vz, const double *aa, const double *ab, \
                   const double *az, int nb, const rps3_kout *o) {       \
    (void)nb;                                                            \
    kpoint(K, pa, pb, pz, va, vb, vz, aa, ab, az, 0, o, flags);          \
  }
KONE(kone_data, KF_THETA | KF_CERTIFY | KF_SHARES | KF_DATA)
KONE(kone_forces_data, KF_DATA)

void rps3_kernel_block(const rps3_model *m, const rps3_batch_in *in, size_t i0,
                       int nb, int rates, rps3_kkind kind, const rps3_kout *o) {
  void (*kloop)(const kconst *, const double *, const double *, const double *,
                const double *, const double *, const double *, const double *,
                const double *, const double *, int, const rps3_kout *) =
      kind == RPS3_KFORCES ? (o->d != NULL ? kone_forces_data : kloop_forces)
      : kind == RPS3_KLEAN ? kloop_lean
      : kind == RPS3_KFULL ? kloop_full
                           : kone_data;
  static const double zero[RPS3_KBLOCK];
  const size_t n = in->n;
  const double *pose = in->pose + i0;
  kconst K;
  int i, e;
  K.r = m->r;
  K.R = m->R;
  K.M = m->M;
  K.g = m->g;
  K.Mg3 = RPS3_PLATFORM_BALL_WEIGHT(m->M, m->g);
  K.M6 = RPS3_DISC_BALL_MASS(m->M);
  K.mgd = RPS3_LINK_WEIGHT_MOMENT(m->m, m->g, m->d);
  K.Jlink = m->Jlink;
  K.w_scale = 2.0 / (3.0 * m->r * m->r);
  for (i = 0; i < 3; i++) {
    K.Ip[i] = m->Ip[i];
    K.pin[i][0] = m->pin[i][0];
    K.pin[i][1] = m->pin[i][1];
    K.u[i][0] = m->radial[i][0];
    K.u[i][1] = m->radial[i][1];
    K.body[i][0] = m->body[i][0];
    K.body[i][1] = m->body[i][1];
  }
  for (e = 0; e < RPS3_KNEFF; e++)
    K.sel[e] = (m->opt.effects & (1 << e)) ? 1.0 : 0.0;
  K.certify = (m->opt.outputs & RPS3_OUT_CERTIFY) ? 1.0 : 0.0;
  K.rates = rates ? 1.0 : 0.0;
  rps3_sing_certify_limits(m, KMARGIN, &K.cond_lim, &K.trans_lim);
  if (rates)
    kloop(&K, pose, pose + n, pose + 2 * n, in->dpose + i0, in->dpose + n + i0,
          in->dpose + 2 * n + i0, in->ddpose + i0, in->ddpose + n + i0,
          in->ddpose + 2 * n + i0, nb, o);
  else
    kloop(&K, pose, pose + n, pose + 2 * n, zero, zero, zero, zero, zero, zero,
          nb, o);
}

/* The leanest pass (outputs = RPS3_OUT_FORCES) fuses the multiply-adds of its
   dot and cross products (kma) where the CPU has FMA: about a fifth fewer
   instructions.  The choice is made once a call, by the CPU, for the
   block loop and the one-point function alike, so that the batch is the
   loop of rps3_inverse bit for bit on one machine; on a CPU without FMA
   the lean F differ from those with it by rounding
   (tests/test_batch_kernel.c holds both to the default path's F).  The
   rest of the file fuses nothing (-ffp-contract=off): the kernel's
   results are the same bits on every CPU. */
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define KFMA() __builtin_cpu_supports("fma")
#elif defined(FP_FAST_FMA)
#define KFMA() 1
#else
#define KFMA() 0
#endif

/* the rates of a static selection: zero, as rps3_inverse leaves them
   unread */
static const double kzero3[3] = {0.0, 0.0, 0.0};

/* the results the leanest pass does not compute (F_effect's size) */
#define KNAN ((double)NAN)
static const double knan[RPS3_NEFFECT * 3] = {
    KNAN, KNAN, KNAN, KNAN, KNAN, KNAN, KNAN, KNAN, KNAN, KNAN, KNAN,
    KNAN, KNAN, KNAN, KNAN, KNAN, KNAN, KNAN, KNAN, KNAN, KNAN};

/* the lean pass over a block: F, cond and ok only */
KCLONES
static void kloop_bare(const rps3_model *m, const double *restrict pa,
                       const double *restrict pb, const double *restrict pz,
                       const double *restrict va, const double *restrict vb,
                       const double *restrict vz, const double *restrict aa,
                       const double *restrict ab, const double *restrict az,
                       int nb, double *restrict F0, double *restrict F1,
                       double *restrict F2, double *restrict cond,
                       double *restrict ok) {
  kbconst K;
  int p;
  kbconst_set(&K, m, KMARGIN);
  if (KFMA()) {
    _Pragma("omp simd") for (p = 0; p < nb; p++) {
      kbout r = kbare(&K, pa[p], pb[p], pz[p], va[p], vb[p], vz[p], aa[p],
                      ab[p], az[p], 1);
      F0[p] = r.F.x;
      F1[p] = r.F.y;
      F2[p] = r.F.z;
      cond[p] = r.cond;
      ok[p] = r.ok;
    }
  } else {
    _Pragma("omp simd") for (p = 0; p < nb; p++) {
      kbout r = kbare(&K, pa[p], pb[p], pz[p], va[p], vb[p], vz[p], aa[p],
                      ab[p], az[p], 0);
      F0[p] = r.F.x;
      F1[p] = r.F.y;
      F2[p] = r.F.z;
      cond[p] = r.cond;
      ok[p] = r.ok;
    }
  }
}

void rps3_kernel_block_bare(const rps3_model *m, const rps3_batch_in *in,
                            size_t i0, int nb, int rates, double *const F[3],
                            double *cond, double *ok) {
  static const double zero[RPS3_KBLOCK];
  const size_t n = in->n;
  const double *pose = in->pose + i0;
  if (rates)
    kloop_bare(m, pose, pose + n, pose + 2 * n, in->dpose + i0,
               in->dpose + n + i0, in->dpose + 2 * n + i0, in->ddpose + i0,
               in->ddpose + n + i0, in->ddpose + 2 * n + i0, nb, F[0], F[1],
               F[2], cond, ok);
  else
    kloop_bare(m, pose, pose + n, pose + 2 * n, zero, zero, zero, zero, zero,
               zero, nb, F[0], F[1], F[2], cond, ok);
}

/* the lean pass on d's point, the same body as the block's: F and cond
   into d, or 0 for a point the pass leaves to the stages */
KINLINE int lean_point(const rps3_model *m, rps3_data *d, int fu) {
  kbconst K;
  kbout r;
  const int rates = (m->opt.effects & RPS3_EFF_DYNAMIC) != 0;
  const double *dp = rates ? d->dpose : kzero3;
  const double *ddp = rates ? d->ddpose : kzero3;
  kbconst_set(&K, m, KMARGIN);
  if (fu)
    r = kbare(&K, d->pose[0], d->pose[1], d->pose[2], dp[0], dp[1], dp[2],
              ddp[0], ddp[1], ddp[2], 1);
  else
    r = kbare(&K, d->pose[0], d->pose[1], d->pose[2], dp[0], dp[1], dp[2],
              ddp[0], ddp[1], ddp[2], 0);
  if (r.ok == 0.0) return 0;
  /* nothing but F and cond is this point's (rps3.h, enum rps3_output):
     every other result NaN; the kinematics (positions, rates, mode) are
     not this point's, which d->stage 0 says */
  d->F[0] = r.F.x;
  d->F[1] = r.F.y;
  d->F[2] = r.F.z;
  d->cond = r.cond;
  /* the NaNs once: a data the last call left from this pass (stage 0)
     and whose results are still NaN needs no second fill.  Every other
     writer of these results writes each group whole (rps3_invdyn, the
     kernel's point, the position stages' theta), its first component
     included, so a NaN there stands for the group */
  if (!(d->stage == 0 && d->F_effect[0][0] != d->F_effect[0][0] &&
        d->theta[0] != d->theta[0] && d->lambda[0] != d->lambda[0] &&
        d->transmission != d->transmission &&
        d->energy_scale != d->energy_scale)) {
    memcpy(d->F_effect, knan, sizeof(d->F_effect));
    memcpy(d->theta, knan, sizeof(d->theta));
    memcpy(d->lambda, knan, sizeof(d->lambda));
    d->transmission = d->power = d->dTdt = d->dPdt = d->friction_power =
        d->energy_residual = d->energy_scale = (double)NAN;
  }
  d->warn = 0;
  d->stage = 0;
  d->have_theta = 0;
  d->has_lambda = 0;
  return 1;
}

/* cloned like the loops: 32 registers and FMA where the CPU has them
   (static: clang names an external clone's dispatcher apart) */
KCLONES
static int lean_point_clone(const rps3_model *m, rps3_data *d) {
  return lean_point(m, d, KFMA() ? 1 : 0);
}

int rps3_inverse_lean_point(const rps3_model *m, rps3_data *d) {
  return lean_point_clone(m, d);
}

int rps3_inverse_lean_point_unfused(const rps3_model *m, rps3_data *d) {
  return lean_point(m, d, 0);
}

double rps3_lean_trans_bound(const rps3_model *m, const double pose[3]) {
  kbconst K;
  kbout r;
  kbconst_set(&K, m, KMARGIN);
  r = kbare(&K, pose[0], pose[1], pose[2], 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0);
  return r.tbound;
}
