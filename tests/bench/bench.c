/*
 * bench.c - rps3-bench: how long one call of each stage takes.
 *
 *   rps3-bench [-o out/bench.h5] [-n BATCHES] [-c CALLS] [-k CASE]
 *
 * Every case loops over points of the paper's helix (Table II) sampled at
 * 1 kHz, the rate of a control loop.  Cases that start from a pose (ik, the
 * theta solve, the whole pipeline) walk the trajectory point after point, so
 * that a warm-started theta solve starts from the previous sample, exactly
 * as in a control loop or a sweep; the walk turns back at the ends instead
 * of jumping.  Cases that need the earlier stages done (rates, dynamics)
 * cycle over RING snapshots taken along the trajectory, so that the timed
 * call is the stage alone.
 *
 * One batch is CALLS calls timed together with CLOCK_MONOTONIC; the batches
 * of all cases are interleaved round-robin, so that a noisy spell of the
 * (shared) machine hits every case alike.  The table gives the median over
 * the batches of the per-call time, the 10th-90th percentile spread, and
 * the ratio to the goal where docs/performance.md sets one.  Nothing is
 * asserted: the numbers are what the machine did.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <gsl/gsl_errno.h>

#include "anchor_gen.h"
#include "batch_kernel.h" /* rps3_inverse_stages: the stages alone */
#include "bench.h"
#include "rps3.h"
#include "user_law.h"

#define RING 16         /* snapshots the stage-only cases cycle over */
#define RATE_HZ 1000.0  /* sampling of the trajectory */
/* the goals of docs/performance.md, "Goals and today's numbers" */
#define TARGET_INVDYN_NS 250.0   /* closed-form theta, full scene */
#define TARGET_PIPELINE_NS 1500.0 /* warm multiroot pipeline */
#define TARGET_WARM_PAPER_NS 800.0 /* the same, paper's effects */
#define FWDDYN_PER_INVERSE 3.0   /* rps3_fwddyn <= 3 rps3_inverse */
#define TARGET_SIM_NS 1000.0     /* >= 1000x real time, i.e. one
                                    simulated 1 ms control period in 1 us */
#define TARGET_DESIGN_NS 1000.0  /* a design on a 1000-pose grid with every
                                    index in 1 ms: 1 us a pose */

/* the points every case loops over */
typedef struct {
  int n;
  double (*pose)[3], (*dpose)[3], (*ddpose)[3];
  double (*l)[3];  /* link lengths by rps3_ik, input of the theta solve */
  /* the same points in chunks of BATCH_N as structures of arrays (chunk
     k: component c of point i at [(3 k + c) BATCH_N + i]), for the batch
     entry point */
  int nchunk;
  double *soa_pose, *soa_dpose, *soa_ddpose;
  double (*dl)[3]; /* link rates and forces of the full scene by */
  double (*F)[3];  /* rps3_inverse: inputs of rps3_fwddyn */
} points;

/* points per rps3_inverse_batch call */
#define BATCH_N 1000

typedef enum {
  K_IK,       /* rps3_ik along the trajectory */
  K_THETA,    /* rps3_theta_solve along the trajectory */
  K_INVERSE,  /* rps3_inverse along the trajectory */
  K_VEL,      /* rps3_velocity on the ring */
  K_ACC,      /* rps3_acceleration on the ring */
  K_JVEL,     /* rps3_joint_velocity on the ring */
  K_JACC,     /* rps3_joint_acceleration on the ring */
  K_INVDYN,   /* rps3_invdyn on the ring */
  K_ANCHOR,   /* the SymPy-generated forces along the trajectory */
  K_ANCHOR_BATCH, /* the same generated code in a vectorised loop over
                     BATCH_N points at a time (rps3_anchor_forces_batch) */
  K_CONSISTENT, /* rps3_ident_consistent: one fit a batch (time per fit)
                   of CFIT_N points' standard regressor (cfit_make) */
  K_BATCH,    /* rps3_inverse_batch over BATCH_N points at a time, F */
  K_BATCH_ALL, /* the same with every output the batch has (status, warn,
                  l, theta, niter, F, F_effect, lambda, cond, residual:
                  what the Python package asks for) */
  K_FWDDYN,   /* rps3_fwddyn along the trajectory */
  K_SIM,      /* one 1 ms control period of a closed-loop simulation,
                 rps3_sim_advance called every period (a logging loop) */
  K_SIM_RUN,  /* the same periods, rps3_sim_advance called over the rest
                 of the helix at once (a run of it) */
  K_REGRESSOR, /* rps3_regressor along the trajectory */
  K_REGRESSOR_STD, /* rps3_regressor_std along the trajectory */
  K_REGRESSOR_BATCH, /* rps3_regressor_batch over BATCH_N points a call,
                        the chunks of K_BATCH */
  K_REGRESSOR_STD_BATCH, /* rps3_regressor_std_batch, the same */
  K_DESIGN    /* rps3_design_eval_grid: Table II's design on its default
                 10 x 10 x 10 grid, every per-pose output and the summary */
} case_kind;

typedef struct {
  const char *name;
  const char *doc;
  case_kind kind;
  rps3_model m;
  double target_ns;
  int count_iter;          /* report theta-solve iterations */
  int stages;              /* K_INVERSE through the per-point stages alone
                              (rps3_inverse_stages), not the kernel */
  /* state while running */
  rps3_data *d;            /* the walking data */
  rps3_data ring[RING];    /* snapshots for the stage-only cases */
  int cursor, dir;         /* position of the walk */
  long iter, solves, failures;
  double *per_call;        /* ns per call of each batch (wall) */
  double *cpu_call;        /* ns per call of each batch (thread CPU time) */
  /* rps3_inverse_batch buffers */
  int *b_status, *b_warn, *b_niter;
  double *b_F, *b_Fe, *b_l, *b_theta, *b_lambda, *b_cond, *b_eres;
  double *b_Y;             /* K_REGRESSOR*_BATCH: 3 RPS3_NSTD BATCH_N */
  rps3_sim *sim;           /* K_SIM: the plant ... */
  rps3_ctrl *ctrl;         /* ... its computed-torque controller */
  long tick;               /* ... and the control period it is in */
  int law;                 /* K_SIM: which binding of the law (sim_law) */
  user_law user;           /* ... the user's law (LAW_USER_PLANT) */
  rps3_design_ws *dws;     /* K_DESIGN: the workspace, */
  rps3_design_out dout;    /* ... its outputs (BATCH_N poses) */
  struct cfit_bench *cf;   /* K_CONSISTENT: its data and fit */
} bench_case;

static double clock_ns(clockid_t id) {
  struct timespec ts;
  clock_gettime(id, &ts);
  return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

/* next point of the walk: 0, 1, ..., n-1, n-2, ..., 0, 1, ... */
static int walk(bench_case *c, int n) {
  int p = c->cursor;
  c->cursor += c->dir;
  if (c->cursor >= n) {
    c->cursor = n - 2;
    c->dir = -1;
  } else if (c->cursor < 0) {
    c->cursor = 1;
    c->dir = 1;
  }
  return p;
}

static void copy3(double dst[3], const double src[3]) {
  dst[0] = src[0];
  dst[1] = src[1];
  dst[2] = src[2];
}

/* K_SIM, K_SIM_RUN: how computed torque is bound */
enum {
  LAW_LIBRARY = 0,  /* the library's, rps3_ctrl_bind (offered the plant) */
  LAW_USER_PLANT,   /* the user's (user_law.h), RPS3_CTRL_USES_PLANT */
  LAW_WRAPPED       /* the library's as a plain callback (no caps: it
                       solves every measured state itself) */
};

static rps3_controller sim_law(bench_case *c) {
  rps3_controller ctl = {rps3_ctrl_update, NULL, RATE_HZ, 0u, NULL};
  if (c->law == LAW_USER_PLANT) return user_law_controller(&c->user, RATE_HZ);
  if (c->law == LAW_LIBRARY) return rps3_ctrl_bind(c->ctrl, RATE_HZ);
  ctl.state = c->ctrl;
  return ctl;
}

/* ------------------------------------------------------ consistent fit */

/* K_CONSISTENT: the general model's 76 parameters (the seven bodies' 70
   standard parameters and the pins' viscous and Coulomb coefficients)
   identified from 10 s of a sine trajectory at 1 kHz (CFIT_N points,
   30,000 rows) of the full scene's model written as general bodies: its
   links point masses (a pseudo-inertia of rank 1), its pistons massless
   (0), so the optimum lies on the boundary of the consistent set; the
   prismatic joints' friction, 0 in that scene, is left out.  The forces
   Y pi plus 1 % of their RMS of Gaussian noise, fixed seed. */
#define CFIT_N 10000
#define CFIT_P 76
#define TARGET_CFIT_NS 1e9 /* docs/identification.md: <= 1 s on one core */

typedef struct cfit_bench {
  double *Y, *F, theta[CFIT_P], body[10 * RPS3_NBODY];
  int col[RPS3_NBODY][10], kind[CFIT_P];
  rps3_ident_layout lay;
  rps3_ident_data dt;
} cfit_bench;

/* standard column of fit column j: the bodies', then the pins' */
static int cfit_std_col(int j) {
  return j < 10 * RPS3_NBODY ? j : j + 6;
}

/* a standard normal deviate of the xorshift64 state s (Box-Muller) */
static double cfit_normal(uint64_t *s) {
  double u[2];
  int k;
  for (k = 0; k < 2; k++) {
    *s ^= *s << 13;
    *s ^= *s >> 7;
    *s ^= *s << 17;
    u[k] = ((double)(*s >> 11) + 0.5) / 9007199254740992.0;
  }
  return sqrt(-2.0 * log(u[0])) * cos(6.283185307179586 * u[1]);
}

/* the case's data from c->m; 0, or -1 with a message */
static int cfit_make(bench_case *c) {
  cfit_bench *cf = calloc(1, sizeof(*cf));
  double *pose = malloc(3 * BATCH_N * sizeof(double));
  double *dpose = malloc(3 * BATCH_N * sizeof(double));
  double *ddpose = malloc(3 * BATCH_N * sizeof(double));
  double *Ys = malloc(3 * RPS3_NSTD * BATCH_N * sizeof(double));
  double pi[RPS3_NSTD], rms = 0.0;
  rps3_traj tr;
  uint64_t seed = 0x9e3779b97f4a7c15ull;
  size_t n = 3 * (size_t)CFIT_N, i, j, k0;
  int b, k, rc = -1;
  c->cf = cf;
  if (cf) {
    cf->Y = malloc(n * CFIT_P * sizeof(double));
    cf->F = malloc(n * sizeof(double));
  }
  if (!cf || !cf->Y || !cf->F || !pose || !dpose || !ddpose || !Ys) {
    fprintf(stderr, "rps3-bench: %s: out of memory\n", c->name);
    goto out;
  }
  memset(&tr, 0, sizeof(tr));
  tr.kind = RPS3_TRAJ_SINE;
  {
    static const double mean[3] = {0.0, 0.2, 0.29}, amp[3] = {1.2, 0.08, 0.04},
                        freq[3] = {0.37, 0.83, 1.31}, ph[3] = {0.0, 1.0, 2.0};
    for (k = 0; k < 3; k++) {
      tr.sine.mean[k] = mean[k];
      tr.sine.amp[k] = amp[k];
      tr.sine.freq[k] = freq[k];
      tr.sine.phase[k] = ph[k];
    }
    tr.sine.duration = (double)CFIT_N / RATE_HZ;
  }
  if (rps3_std_params(&c->m, pi) != RPS3_OK) goto out;
  for (k0 = 0; k0 < CFIT_N; k0 += BATCH_N) {
    rps3_batch_in in;
    rps3_batch_out bo;
    size_t p;
    for (p = 0; p < BATCH_N; p++) {
      double q[3], dq[3], ddq[3];
      if (rps3_traj_eval(&c->m, &tr, (double)(k0 + p) / RATE_HZ, q, dq,
                         ddq) != RPS3_OK)
        goto fail;
      for (k = 0; k < 3; k++) {
        pose[k * BATCH_N + p] = q[k];
        dpose[k * BATCH_N + p] = dq[k];
        ddpose[k * BATCH_N + p] = ddq[k];
      }
    }
    memset(&in, 0, sizeof(in));
    memset(&bo, 0, sizeof(bo));
    in.n = BATCH_N;
    in.pose = pose;
    in.dpose = dpose;
    in.ddpose = ddpose;
    bo.status = c->b_status;
    if (rps3_regressor_std_batch(&c->m, c->d, &in, Ys, &bo) != RPS3_OK ||
        bo.nfail != 0)
      goto fail;
    /* row 3 (k0 + p) + a, column j: Y[(a RPS3_NSTD + k) n + p] */
    for (p = 0; p < BATCH_N; p++)
      for (i = 0; i < 3; i++) {
        size_t r = 3 * (k0 + p) + i;
        double f = 0.0;
        for (j = 0; j < CFIT_P; j++) {
          int sk = cfit_std_col((int)j);
          double y = Ys[(i * RPS3_NSTD + (size_t)sk) * BATCH_N + p];
          cf->Y[r * CFIT_P + j] = y;
          f += y * pi[sk];
        }
        cf->F[r] = f;
        rms += f * f / (double)n;
      }
  }
  for (i = 0; i < n; i++) cf->F[i] += 0.01 * sqrt(rms) * cfit_normal(&seed);
  for (b = 0; b < RPS3_NBODY; b++)
    for (k = 0; k < 10; k++) cf->col[b][k] = 10 * b + k;
  for (j = 0; j < CFIT_P; j++)
    cf->kind[j] = j < 10 * RPS3_NBODY ? RPS3_IDENT_FREE : RPS3_IDENT_NONNEG;
  cf->lay.nbody = RPS3_NBODY;
  cf->lay.col = (const int(*)[10])cf->col;
  cf->lay.kind = cf->kind;
  cf->dt.n = n;
  cf->dt.p = CFIT_P;
  cf->dt.Y = cf->Y;
  cf->dt.F = cf->F;
  rc = 0;
  goto out;
fail:
  fprintf(stderr, "rps3-bench: %s: the regressor of the sine trajectory "
          "failed\n", c->name);
out:
  free(pose);
  free(dpose);
  free(ddpose);
  free(Ys);
  return rc;
}

static void cfit_free(cfit_bench *cf) {
  if (cf == NULL) return;
  free(cf->Y);
  free(cf->F);
  free(cf);
}

/* one fit: its iterations counted, a status other than RPS3_OK a failure */
static void cfit_run(bench_case *c) {
  rps3_ident_fit fit;
  memset(&fit, 0, sizeof(fit));
  fit.theta = c->cf->theta;
  fit.body = c->cf->body;
  if (rps3_ident_consistent(&c->cf->dt, &c->cf->lay, NULL, &fit, NULL) !=
      RPS3_OK)
    c->failures++;
  c->iter += fit.niter;
  c->solves++;
}

/* one batch of ncalls calls; the loop of each kind is kept tight */
static void run_batch(bench_case *c, const points *pt, long ncalls) {
  const rps3_model *m = &c->m;
  rps3_data *d = c->d;
  long i;
  int p;
  switch (c->kind) {
  case K_CONSISTENT:
    cfit_run(c); /* one fit, whatever ncalls: main times it alone */
    break;
  case K_IK:
    for (i = 0; i < ncalls; i++) {
      p = walk(c, pt->n);
      copy3(d->pose, pt->pose[p]);
      if (rps3_ik(m, d) != RPS3_OK) c->failures++;
    }
    break;
  case K_THETA:
    for (i = 0; i < ncalls; i++) {
      p = walk(c, pt->n);
      copy3(d->l, pt->l[p]);
      if (rps3_theta_solve(m, d) != RPS3_OK) c->failures++;
      c->iter += d->solve_niter;
    }
    c->solves += ncalls;
    break;
  case K_INVERSE:
    for (i = 0; i < ncalls; i++) {
      p = walk(c, pt->n);
      copy3(d->pose, pt->pose[p]);
      copy3(d->dpose, pt->dpose[p]);
      copy3(d->ddpose, pt->ddpose[p]);
      if ((c->stages ? rps3_inverse_stages(m, d) : rps3_inverse(m, d)) !=
          RPS3_OK)
        c->failures++;
      c->iter += d->solve_niter;
    }
    c->solves += ncalls;
    break;
  case K_VEL:
    for (i = 0; i < ncalls; i++)
      if (rps3_velocity(m, &c->ring[i % RING]) != RPS3_OK) c->failures++;
    break;
  case K_ACC:
    for (i = 0; i < ncalls; i++)
      if (rps3_acceleration(m, &c->ring[i % RING]) != RPS3_OK) c->failures++;
    break;
  case K_JVEL:
    for (i = 0; i < ncalls; i++)
      if (rps3_joint_velocity(m, &c->ring[i % RING]) != RPS3_OK)
        c->failures++;
    break;
  case K_JACC:
    for (i = 0; i < ncalls; i++)
      if (rps3_joint_acceleration(m, &c->ring[i % RING]) != RPS3_OK)
        c->failures++;
    break;
  case K_INVDYN:
    for (i = 0; i < ncalls; i++)
      if (rps3_invdyn(m, &c->ring[i % RING]) != RPS3_OK) c->failures++;
    break;
  case K_ANCHOR: {
    /* the generated code takes the mechanism's constants as arguments */
    const double par[6] = {m->R, m->rho, m->M, m->m, m->d, m->g};
    double F[3];
    for (i = 0; i < ncalls; i++) {
      p = walk(c, pt->n);
      if (rps3_anchor_forces(par, pt->pose[p], pt->dpose[p], pt->ddpose[p],
                             F) != 0)
        c->failures++;
    }
    break;
  }
  case K_ANCHOR_BATCH: {
    /* as K_BATCH: ncalls points, BATCH_N a call, the same chunks */
    const double par[6] = {m->R, m->rho, m->M, m->m, m->d, m->g};
    for (i = 0; i < ncalls; i += BATCH_N) {
      size_t k0 = (size_t)(c->cursor++ % pt->nchunk) * 3 * BATCH_N;
      rps3_anchor_forces_batch(par, BATCH_N, pt->soa_pose + k0,
                               pt->soa_dpose + k0, pt->soa_ddpose + k0,
                               c->b_F, c->b_status);
      for (p = 0; p < BATCH_N; p++) c->failures += c->b_status[p] != 0;
    }
    break;
  }
  case K_BATCH:
  case K_BATCH_ALL:
    /* ncalls points, BATCH_N per call, forward along the trajectory */
    for (i = 0; i < ncalls; i += BATCH_N) {
      rps3_batch_in in;
      rps3_batch_out out;
      size_t k0 = (size_t)(c->cursor++ % pt->nchunk) * 3 * BATCH_N;
      memset(&in, 0, sizeof(in));
      memset(&out, 0, sizeof(out));
      in.n = BATCH_N; /* main() keeps ncalls a multiple of BATCH_N */
      in.pose = pt->soa_pose + k0;
      in.dpose = pt->soa_dpose + k0;
      in.ddpose = pt->soa_ddpose + k0;
      out.status = c->b_status;
      out.F = c->b_F;
      if (c->kind == K_BATCH_ALL) {
        out.warn = c->b_warn;
        out.niter = c->b_niter;
        out.l = c->b_l;
        out.theta = c->b_theta;
        out.F_effect = c->b_Fe;
        out.lambda = c->b_lambda;
        out.cond = c->b_cond;
        out.energy_residual = c->b_eres;
      }
      if (rps3_inverse_batch(m, d, &in, &out) != RPS3_OK)
        c->failures += (long)in.n;
      c->failures += (long)out.nfail;
    }
    break;
  case K_FWDDYN:
    /* as in a simulation: theta warm from the previous evaluation */
    for (i = 0; i < ncalls; i++) {
      p = walk(c, pt->n);
      copy3(d->l, pt->l[p]);
      copy3(d->dl, pt->dl[p]);
      copy3(d->F, pt->F[p]);
      if (rps3_fwddyn(m, d) != RPS3_OK) c->failures++;
      c->iter += d->solve_niter;
    }
    c->solves += ncalls;
    break;
  case K_SIM:
    for (i = 0; i < ncalls; i++) {
      rps3_controller ctl = sim_law(c);
      if (c->tick == pt->n - 1 || rps3_sim_now(c->sim)->status != RPS3_OK) {
        /* the end of the helix: start it again */
        if (rps3_sim_now(c->sim)->status != RPS3_OK) c->failures++;
        rps3_sim_start(c->sim, 0.0, pt->pose[0], pt->dpose[0]);
        c->tick = 0;
      }
      c->tick++;
      rps3_sim_advance(c->sim, &ctl, (double)c->tick / RATE_HZ);
    }
    break;
  case K_REGRESSOR:
    for (i = 0; i < ncalls; i++) {
      double Y[3][RPS3_NPAPER];
      p = walk(c, pt->n);
      copy3(d->pose, pt->pose[p]);
      copy3(d->dpose, pt->dpose[p]);
      copy3(d->ddpose, pt->ddpose[p]);
      if (rps3_regressor(m, d, Y) != RPS3_OK) c->failures++;
    }
    break;
  case K_REGRESSOR_STD:
    for (i = 0; i < ncalls; i++) {
      double Y[3][RPS3_NSTD];
      p = walk(c, pt->n);
      copy3(d->pose, pt->pose[p]);
      copy3(d->dpose, pt->dpose[p]);
      copy3(d->ddpose, pt->ddpose[p]);
      if (rps3_regressor_std(m, d, Y) != RPS3_OK) c->failures++;
    }
    break;
  case K_REGRESSOR_BATCH:
  case K_REGRESSOR_STD_BATCH:
    /* as K_BATCH: ncalls points, BATCH_N a call, the same chunks */
    for (i = 0; i < ncalls; i += BATCH_N) {
      rps3_batch_in in;
      rps3_batch_out out;
      size_t k0 = (size_t)(c->cursor++ % pt->nchunk) * 3 * BATCH_N;
      int rc;
      memset(&in, 0, sizeof(in));
      memset(&out, 0, sizeof(out));
      in.n = BATCH_N;
      in.pose = pt->soa_pose + k0;
      in.dpose = pt->soa_dpose + k0;
      in.ddpose = pt->soa_ddpose + k0;
      out.status = c->b_status;
      rc = c->kind == K_REGRESSOR_BATCH
               ? rps3_regressor_batch(m, d, &in, c->b_Y, &out)
               : rps3_regressor_std_batch(m, d, &in, c->b_Y, &out);
      if (rc != RPS3_OK) c->failures += (long)in.n;
      c->failures += (long)out.nfail;
    }
    break;
  case K_DESIGN:
    /* ncalls poses, one grid of BATCH_N a call */
    for (i = 0; i < ncalls; i += BATCH_N) {
      rps3_design ds;
      rps3_design_grid gr;
      rps3_design_summary sum;
      rps3_design_default(&ds);
      rps3_design_grid_default(&ds, &gr);
      if (rps3_design_eval_grid(c->dws, &ds, NULL, &gr, &c->dout, &sum) !=
          RPS3_OK)
        c->failures += BATCH_N;
    }
    break;
  case K_SIM_RUN: {
    rps3_controller ctl = sim_law(c);
    long left = ncalls;
    while (left > 0) {
      long k;
      if (c->tick == pt->n - 1 || rps3_sim_now(c->sim)->status != RPS3_OK) {
        if (rps3_sim_now(c->sim)->status != RPS3_OK) c->failures++;
        rps3_sim_start(c->sim, 0.0, pt->pose[0], pt->dpose[0]);
        c->tick = 0;
      }
      /* the batch's periods, up to the end of the helix, in one call */
      k = pt->n - 1 - c->tick;
      if (k > left) k = left;
      c->tick += k;
      left -= k;
      rps3_sim_advance(c->sim, &ctl, (double)c->tick / RATE_HZ);
    }
    break;
  }
  }
}

/* ---------------------------------------------------------------- scenes */

typedef enum { SCENE_FULL, SCENE_GRAVITY, SCENE_PAPER, SCENE_GENERAL } scene;

static const char *const scene_full_doc =
    "every effect: platform and link gravity and inertia, a payload "
    "(0.05 kg at (0.01, -0.02, 0.03) m, moments (2e-5, 3e-5, 4e-5) kg m^2), "
    "pin friction (viscous 0.01 N m s, Coulomb 0.005 N m), prismatic "
    "friction selected with zero coefficients; certify on (the default) "
    "unless the row says otherwise";
static const char *const scene_general_doc =
    "general bodies (a platform of Table II's mass with its centre of mass "
    "off its centre and products of inertia, cylinders and pistons with "
    "full inertia tensors), every effect, friction in every pin and "
    "prismatic joint, no payload";
static const char *const scene_gravity_doc =
    "platform_gravity + link_gravity, certify off: a static scene, no rates";

/* the paper's mechanism (Table II) with a scene's effects */
static void make_model(rps3_model *m, scene s, rps3_method method,
                       rps3_theta_route theta, int warm, int certify) {
  rps3_check chk;
  rps3_model_default(m);
  if (s == SCENE_FULL) {
    m->opt.effects = RPS3_EFF_ALL;
    m->payload.mass = 0.05;
    m->payload.com[0] = 0.01;
    m->payload.com[1] = -0.02;
    m->payload.com[2] = 0.03;
    m->payload.inertia[0] = 2e-5;
    m->payload.inertia[1] = 3e-5;
    m->payload.inertia[2] = 4e-5;
    m->friction.viscous = 0.01;
    m->friction.coulomb = 0.005;
  } else if (s == SCENE_GENERAL) {
    static const rps3_body plat = {0.18, {0.004, -0.003, 0.012},
                                   {1.2e-3, 1e-5, -2e-5, 1.1e-3, 3e-5, 2.2e-3}};
    static const rps3_body cyl = {0.07, {0.09, 0.002, -0.004},
                                  {2e-5, 0.0, 1e-6, 6e-4, 0.0, 6e-4}};
    static const rps3_body pis = {0.03, {-0.05, 0.0, 0.001},
                                  {5e-6, 0.0, 0.0, 8e-5, 0.0, 8e-5}};
    int i;
    m->opt.effects = RPS3_EFF_ALL & ~RPS3_EFF_PAYLOAD;
    m->bodies = RPS3_BODIES_GENERAL;
    m->platform = plat;
    for (i = 0; i < 3; i++) {
      m->leg[i].cylinder = cyl;
      m->leg[i].piston = pis;
      m->leg[i].pin.viscous = 0.01;
      m->leg[i].pin.coulomb = 0.005;
      m->leg[i].prismatic.viscous = 0.5;
      m->leg[i].prismatic.coulomb = 0.05;
    }
  } else if (s == SCENE_PAPER) {
    m->opt.effects = RPS3_EFF_DEFAULT; /* the paper's: gravity and inertia */
  } else {
    m->opt.effects = RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_LINK_GRAVITY;
  }
  m->opt.method = method;
  m->opt.theta = theta;
  m->opt.warm_start = warm;
  m->opt.outputs = (certify) ? (m->opt.outputs | RPS3_OUT_CERTIFY)
      : (m->opt.outputs & ~RPS3_OUT_CERTIFY);
  if (rps3_model_init(m, &chk) != RPS3_OK) {
    fprintf(stderr, "rps3-bench: model: %s\n", chk.msg);
    exit(2);
  }
}

/* the paper's helix at RATE_HZ, with the link lengths of every point */
static void make_points(points *pt) {
  rps3_model m;
  rps3_traj tr;
  rps3_data *d = NULL;
  double T;
  int p;
  make_model(&m, SCENE_FULL, RPS3_LAGRANGE, RPS3_THETA_CLOSED_FORM, 1, 1);
  rps3_traj_default(&tr);
  T = rps3_traj_duration(&tr);
  pt->n = (int)floor(T * RATE_HZ + 0.5) + 1;
  pt->pose = malloc((size_t)pt->n * sizeof(*pt->pose));
  pt->dpose = malloc((size_t)pt->n * sizeof(*pt->dpose));
  pt->ddpose = malloc((size_t)pt->n * sizeof(*pt->ddpose));
  pt->l = malloc((size_t)pt->n * sizeof(*pt->l));
  pt->dl = malloc((size_t)pt->n * sizeof(*pt->dl));
  pt->F = malloc((size_t)pt->n * sizeof(*pt->F));
  if (!pt->pose || !pt->dpose || !pt->ddpose || !pt->l || !pt->dl || !pt->F ||
      rps3_data_alloc(&m, &d) != RPS3_OK) {
    fprintf(stderr, "rps3-bench: out of memory\n");
    exit(2);
  }
  for (p = 0; p < pt->n; p++) {
    double t = T * (double)p / (double)(pt->n - 1);
    if (rps3_traj_eval(&m, &tr, t, pt->pose[p], pt->dpose[p],
                       pt->ddpose[p]) != RPS3_OK) {
      fprintf(stderr, "rps3-bench: trajectory at t = %g\n", t);
      exit(2);
    }
    copy3(d->pose, pt->pose[p]);
    copy3(d->dpose, pt->dpose[p]);
    copy3(d->ddpose, pt->ddpose[p]);
    if (rps3_inverse(&m, d) != RPS3_OK) {
      fprintf(stderr, "rps3-bench: inverse at t = %g: %s\n", t, d->err.msg);
      exit(2);
    }
    copy3(pt->l[p], d->l);
    copy3(pt->dl[p], d->dl);
    copy3(pt->F[p], d->F);
  }
  rps3_data_free(d);
  /* the chunks for the batch entry point */
  pt->nchunk = pt->n / BATCH_N;
  pt->soa_pose = malloc((size_t)pt->nchunk * 3 * BATCH_N * sizeof(double));
  pt->soa_dpose = malloc((size_t)pt->nchunk * 3 * BATCH_N * sizeof(double));
  pt->soa_ddpose = malloc((size_t)pt->nchunk * 3 * BATCH_N * sizeof(double));
  if (!pt->soa_pose || !pt->soa_dpose || !pt->soa_ddpose) {
    fprintf(stderr, "rps3-bench: out of memory\n");
    exit(2);
  }
  for (p = 0; p < pt->nchunk * BATCH_N; p++) {
    int k = p / BATCH_N, i = p % BATCH_N, c;
    for (c = 0; c < 3; c++) {
      size_t at = (size_t)(3 * k + c) * BATCH_N + (size_t)i;
      pt->soa_pose[at] = pt->pose[p][c];
      pt->soa_dpose[at] = pt->dpose[p][c];
      pt->soa_ddpose[at] = pt->ddpose[p][c];
    }
  }
}

/* fill the ring with snapshots after the whole pipeline of c's model,
   evenly spaced along the trajectory */
static void fill_ring(bench_case *c, const points *pt) {
  int k;
  for (k = 0; k < RING; k++) {
    int p = (int)((long)k * (pt->n - 1) / (RING - 1));
    rps3_data_reset(c->d);
    copy3(c->d->pose, pt->pose[p]);
    copy3(c->d->dpose, pt->dpose[p]);
    copy3(c->d->ddpose, pt->ddpose[p]);
    if (rps3_inverse(&c->m, c->d) != RPS3_OK) {
      fprintf(stderr, "rps3-bench: %s: snapshot %d: %s\n", c->name, k,
              c->d->err.msg);
      exit(2);
    }
    c->ring[k] = *c->d;
  }
  rps3_data_reset(c->d);
}

/* ------------------------------------------------------------ statistics */

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* linear interpolation between order statistics of sorted x[0..n-1] */
static double quantile(const double *x, long n, double q) {
  double pos = q * (double)(n - 1);
  long i = (long)floor(pos);
  double f = pos - (double)i;
  if (i + 1 >= n) return x[n - 1];
  return x[i] + f * (x[i + 1] - x[i]);
}

static void summarize(bench_case *c, long calls, long batches, bench_row *r) {
  qsort(c->per_call, (size_t)batches, sizeof(double), cmp_double);
  qsort(c->cpu_call, (size_t)batches, sizeof(double), cmp_double);
  r->cpu_median_ns = quantile(c->cpu_call, batches, 0.5);
  r->name = c->name;
  r->doc = c->doc;
  r->median_ns = quantile(c->per_call, batches, 0.5);
  r->p10_ns = quantile(c->per_call, batches, 0.1);
  r->p90_ns = quantile(c->per_call, batches, 0.9);
  r->min_ns = c->per_call[0];
  r->max_ns = c->per_call[batches - 1];
  r->target_ns = c->target_ns;
  r->mean_iter = (c->count_iter && c->solves > 0)
                     ? (double)c->iter / (double)c->solves
                     : BENCH_NONE;
  r->calls = c->kind == K_CONSISTENT ? 1 : calls;
  r->batches = batches;
  r->failures = c->failures;
}

/* CPU model name, as lscpu prints it */
static void machine_name(char *buf, size_t sz) {
  FILE *f = fopen("/proc/cpuinfo", "r");
  char line[512];
  snprintf(buf, sz, "unknown");
  if (f == NULL) return;
  while (fgets(line, sizeof(line), f) != NULL) {
    if (strncmp(line, "model name", 10) == 0) {
      char *v = strchr(line, ':');
      if (v != NULL) {
        v++;
        while (*v == ' ' || *v == '\t') v++;
        v[strcspn(v, "\n")] = '\0';
        snprintf(buf, sz, "%s", v);
      }
      break;
    }
  }
  fclose(f);
}

/* ---------------------------------------------------------------- ratios */

/* Ratios taken round by round: the two cases' batches of one round ran
   back to back, so a noisy spell of the machine cancels out.  num / den
   for wall and for CPU time, median and min-max over the rounds. */
typedef struct {
  const char *num, *den, *doc;
  double wall[3], cpu[3]; /* median, min, max */
} bench_ratio;

static const struct {
  const char *num, *den, *doc;
} ratio_pairs[] = {
    {"pipeline_closed_lagrange_paper_nocert", "anchor_generated",
     "scalar rps3_inverse / generated code, the paper's four effects"},
    {"pipeline_closed_lagrange_paper_forces", "anchor_generated",
     "scalar rps3_inverse, F and the transmission / generated code"},
    {"pipeline_closed_lagrange_paper_lean", "anchor_generated",
     "scalar rps3_inverse, F alone (RPS3_OUT_FORCES) / generated code (goal <= 1)"},
    {"batch_closed_lagrange_paper_nocert", "anchor_generated",
     "rps3_inverse_batch per point / generated code, the same forces"},
    {"anchor_generated_batch", "anchor_generated",
     "batched generated code / the scalar generated code"},
    {"batch_closed_lagrange_paper_lean", "anchor_generated_batch",
     "rps3_inverse_batch, F alone / batched generated code (goal <= 1.2)"},
    {"stages_closed_lagrange_paper_nocert",
     "batch_closed_lagrange_paper_nocert",
     "per-point stages / rps3_inverse_batch per point (goal >= 10)"},
    {"stages_closed_lagrange_paper_nocert",
     "batch_closed_lagrange_paper_lean",
     "the same, F alone (RPS3_OUT_FORCES; goal >= 10)"},
    {"stages_closed_lagrange_paper", "batch_closed_lagrange_paper_all",
     "the same, certify on, every output (goal >= 10)"},
    {"stages_closed_lagrange_paper_nocert",
     "pipeline_closed_lagrange_paper_nocert",
     "per-point stages / scalar rps3_inverse (its one-point kernel)"},
    {"sim_helix_user_plant_1khz_rk4", "sim_helix_computed_torque_1khz_rk4",
     "sim period: user's law with the plant / library's (goal <= 1)"},
    {"sim_helix_run_user_plant_1khz_rk4",
     "sim_helix_run_computed_torque_1khz_rk4",
     "the same, the helix as one run (goal <= 1)"},
    {"sim_helix_wrapped_computed_torque_1khz_rk4",
     "sim_helix_computed_torque_1khz_rk4",
     "sim period: library's law without the plant / with it"},
    {"regressor_point", "pipeline_closed_lagrange_full_nocert",
     "regressor / rps3_inverse's forces at the same point (goal <= 2)"},
    {"regressor_std_point", "pipeline_closed_lagrange_general_nocert",
     "standard regressor / the general forces at the same point (goal <= 2)"},
    {"regressor_batch", "batch_closed_lagrange_full_nocert",
     "batched regressor / the batched forces of the same points (goal <= 2)"},
    {"regressor_std_batch", "batch_closed_lagrange_general_nocert",
     "batched standard regressor / the batched general forces (goal <= 2)"},
};
#define NRATIO_MAX ((int)(sizeof(ratio_pairs) / sizeof(ratio_pairs[0])))

/* the goals of docs/performance.md that are ratios of two rows of this
   run, as the rounds' median of num / den (wall time): "one formulation",
   the library's path for F no slower than the generated code, scalar and
   batched */
static const struct {
  const char *num, *den, *what;
  double max;
} ratio_goals[] = {
    {"pipeline_closed_lagrange_paper_lean", "anchor_generated",
     "F with every check (rps3_inverse, opt.outputs = RPS3_OUT_FORCES: "
     "transmission bound, assembly mode, finiteness) a point, against the "
     "generated anchor", 1.2},
    {"pipeline_closed_lagrange_paper_lean", "anchor_generated",
     "F alone (the same leanest pass) against the generated anchor", 1.0},
    {"batch_closed_lagrange_paper_lean", "anchor_generated_batch",
     "its batch (rps3_inverse_batch, RPS3_OUT_FORCES) a point, against the "
     "anchor's batched SIMD build", 1.2},
};
#define NGOAL ((int)(sizeof(ratio_goals) / sizeof(ratio_goals[0])))

/* one "goal: ... : met / NOT met" line per ratio goal; a goal whose rows
   -k left out says so */
static void print_ratio_goals(const bench_ratio *rat, int n) {
  int g, k;
  printf("\n");
  for (g = 0; g < NGOAL; g++) {
    const bench_ratio *r = NULL;
    for (k = 0; k < n; k++)
      if (strcmp(rat[k].num, ratio_goals[g].num) == 0 &&
          strcmp(rat[k].den, ratio_goals[g].den) == 0)
        r = &rat[k];
    if (r == NULL) {
      printf("goal: %s, <= %.1fx: not measured (-k left out %s or %s)\n",
             ratio_goals[g].what, ratio_goals[g].max, ratio_goals[g].num,
             ratio_goals[g].den);
      continue;
    }
    printf("goal: %s, <= %.1fx: median %.2fx [%.2f - %.2f] wall, %.2fx "
           "cpu, round by round: %s\n",
           ratio_goals[g].what, ratio_goals[g].max, r->wall[0], r->wall[1],
           r->wall[2], r->cpu[0],
           r->wall[0] <= ratio_goals[g].max ? "met" : "NOT met");
  }
}

/* The batched anchor gives the scalar anchor's forces on every chunk of
   the helix: the same generated assignments, the same operations in the
   same order (tests/bench/anchor_check.c holds it on random states too).
   Exits when not: a ratio against a wrong anchor means nothing. */
static void check_anchor_batch(const rps3_model *m, const points *pt) {
  const double par[6] = {m->R, m->rho, m->M, m->m, m->d, m->g};
  /* relative to the largest |F_i| of the point: the same bits with libm's
     scalar sines; glibc's vector ones (libmvec) are within 4 ulp of them,
     amplified where dl/dq is near singular (tests/bench/anchor_check.c's
     TOL_BATCH, measured 2.5e-13 at the workspace's edge) */
  const double tol = 1e-12;
  static double F[3 * BATCH_N];
  static int st[BATCH_N];
  int k, i, c;
  for (k = 0; k < pt->nchunk; k++) {
    size_t k0 = (size_t)k * 3 * BATCH_N;
    rps3_anchor_forces_batch(par, BATCH_N, pt->soa_pose + k0,
                             pt->soa_dpose + k0, pt->soa_ddpose + k0, F, st);
    for (i = 0; i < BATCH_N; i++) {
      int p = k * BATCH_N + i;
      double Fs[3], scale = 0.0;
      int s = rps3_anchor_forces(par, pt->pose[p], pt->dpose[p],
                                 pt->ddpose[p], Fs);
      for (c = 0; c < 3; c++)
        if (fabs(Fs[c]) > scale) scale = fabs(Fs[c]);
      for (c = 0; c < 3; c++)
        if (s != 0 || st[i] != 0 ||
            !(fabs(F[c * BATCH_N + i] - Fs[c]) <= tol * scale)) {
          fprintf(stderr, "rps3-bench: the batched anchor differs from the "
                  "scalar one at point %d: F[%d] = %.17g, not %.17g "
                  "(status %d, %d)\n", p, c, F[c * BATCH_N + i], Fs[c],
                  st[i], s);
          exit(2);
        }
    }
  }
}

/* -k: NAME contains one of the comma-separated parts of LIST */
static int name_matches(const char *name, const char *list) {
  char part[128];
  while (*list != '\0') {
    size_t n = strcspn(list, ",");
    if (n > 0 && n < sizeof(part)) {
      memcpy(part, list, n);
      part[n] = '\0';
      if (strstr(name, part) != NULL) return 1;
    }
    list += n + (list[n] == ',');
  }
  return 0;
}

static int find_case(bench_case *cases, int ncase, const char *name) {
  int i;
  for (i = 0; i < ncase; i++)
    if (strcmp(cases[i].name, name) == 0) return i;
  return -1;
}

static void ratio_stats(const double *a, const double *b, long n,
                        double out[3]) {
  double *r = malloc((size_t)n * sizeof(double));
  long k;
  if (r == NULL) {
    out[0] = out[1] = out[2] = BENCH_NONE;
    return;
  }
  for (k = 0; k < n; k++) r[k] = a[k] / b[k];
  qsort(r, (size_t)n, sizeof(double), cmp_double);
  out[0] = quantile(r, n, 0.5);
  out[1] = r[0];
  out[2] = r[n - 1];
  free(r);
}

static int ratios(bench_case *cases, int ncase, long batches,
                  bench_ratio *rat) {
  int k, n = 0;
  for (k = 0; k < NRATIO_MAX; k++) {
    int a = find_case(cases, ncase, ratio_pairs[k].num);
    int b = find_case(cases, ncase, ratio_pairs[k].den);
    if (a < 0 || b < 0) continue;
    rat[n].num = ratio_pairs[k].num;
    rat[n].den = ratio_pairs[k].den;
    rat[n].doc = ratio_pairs[k].doc;
    ratio_stats(cases[a].per_call, cases[b].per_call, batches, rat[n].wall);
    ratio_stats(cases[a].cpu_call, cases[b].cpu_call, batches, rat[n].cpu);
    n++;
  }
  return n;
}

static void print_ratios(const bench_ratio *rat, int n, long batches) {
  int k;
  if (n == 0) return;
  printf("\nratios, round by round over %ld interleaved rounds: median "
         "[min - max]\n", batches);
  printf("%-58s %22s %22s\n", "ratio", "wall", "cpu");
  for (k = 0; k < n; k++)
    printf("%-58s %6.2f [%5.2f - %5.2f] %6.2f [%5.2f - %5.2f]\n", rat[k].doc,
           rat[k].wall[0], rat[k].wall[1], rat[k].wall[2], rat[k].cpu[0],
           rat[k].cpu[1], rat[k].cpu[2]);
}

/* ------------------------------------------------------------------ main */

#define NCASE_MAX 48

static void usage(void) {
  fprintf(stderr,
          "usage: rps3-bench [-o FILE.h5] [-n BATCHES] [-c CALLS] [-k CASE]\n"
          "  -o  HDF5 output (default out/bench.h5; '-' for none)\n"
          "  -n  timed batches per case (default 101)\n"
          "  -c  calls per batch (default 2000, a multiple of 1000)\n"
          "  -k  run only the cases whose name contains CASE (profiling); "
          "CASE may list several, comma-separated\n");
}

int main(int argc, char **argv) {
  static bench_case cases[NCASE_MAX];
  static bench_row rows[NCASE_MAX];
  const char *out = "out/bench.h5", *only = NULL;
  long batches = 101, calls = 2000, b;
  int ncase = 0, i, fail = 0, nratio;
  static bench_ratio rat[NRATIO_MAX];
  points pt;
  char machine[256], trajdoc[256];
  bench_info info;

  for (i = 1; i < argc; i++) {
    if (strcmp(argv[i], "-o") == 0 && i + 1 < argc) {
      out = argv[++i];
    } else if (strcmp(argv[i], "-n") == 0 && i + 1 < argc) {
      batches = atol(argv[++i]);
    } else if (strcmp(argv[i], "-c") == 0 && i + 1 < argc) {
      calls = atol(argv[++i]);
    } else if (strcmp(argv[i], "-k") == 0 && i + 1 < argc) {
      only = argv[++i];
    } else {
      usage();
      return 2;
    }
  }
  if (batches < 1 || calls < 1 || calls % BATCH_N != 0) {
    usage();
    return 2;
  }
  gsl_set_error_handler_off();
  make_points(&pt);

  /* the cases, in the order of the table */
#define CASE(name_, doc_, kind_, scene_, method_, theta_, warm_, certify_,   \
             target_, iter_)                                                 \
  do {                                                                       \
    bench_case *c_ = &cases[ncase++];                                        \
    c_->name = name_;                                                        \
    c_->doc = doc_;                                                          \
    c_->kind = kind_;                                                        \
    make_model(&c_->m, scene_, method_, theta_, warm_, certify_);            \
    c_->target_ns = target_;                                                 \
    c_->count_iter = iter_;                                                  \
  } while (0)
  CASE("ik", "rps3_ik: pose -> rot, c, b, l and theta by the closed form "
       "(39), link directions", K_IK, SCENE_FULL, RPS3_LAGRANGE,
       RPS3_THETA_CLOSED_FORM, 1, 1, BENCH_NONE, 0);
  CASE("theta_multiroot_cold", "rps3_theta_solve from l, hybridsj, cold "
       "start (level-platform guess), tol 1e-12", K_THETA, SCENE_FULL,
       RPS3_LAGRANGE, RPS3_THETA_MULTIROOT, 0, 1, BENCH_NONE, 1);
  CASE("theta_multiroot_warm", "rps3_theta_solve from l, hybridsj, warm "
       "start from the previous 1 ms sample, tol 1e-12", K_THETA, SCENE_FULL,
       RPS3_LAGRANGE, RPS3_THETA_MULTIROOT, 1, 1, BENCH_NONE, 1);
  CASE("velocity", "rps3_velocity: pose rates -> vc, omega, dl, dtheta",
       K_VEL, SCENE_FULL, RPS3_LAGRANGE, RPS3_THETA_CLOSED_FORM, 1, 1, BENCH_NONE, 0);
  CASE("acceleration", "rps3_acceleration: pose accelerations -> ac, "
       "domega, ddl, ddtheta", K_ACC, SCENE_FULL, RPS3_LAGRANGE,
       RPS3_THETA_CLOSED_FORM, 1, 1, BENCH_NONE, 0);
  CASE("joint_velocity", "rps3_joint_velocity: dl -> dtheta, vc, omega, "
       "dpose (3x3 solve)", K_JVEL, SCENE_FULL, RPS3_LAGRANGE,
       RPS3_THETA_CLOSED_FORM, 1, 1, BENCH_NONE, 0);
  CASE("joint_acceleration", "rps3_joint_acceleration: ddl -> ddtheta, ac, "
       "domega, ddpose (3x3 solve)", K_JACC, SCENE_FULL, RPS3_LAGRANGE,
       RPS3_THETA_CLOSED_FORM, 1, 1, BENCH_NONE, 0);
  CASE("invdyn_lagrange_gravity", "rps3_invdyn, Lagrange, gravity-only "
       "scene (certify off)", K_INVDYN, SCENE_GRAVITY, RPS3_LAGRANGE,
       RPS3_THETA_CLOSED_FORM, 1, 0, BENCH_NONE, 0);
  CASE("invdyn_newton_euler_gravity", "rps3_invdyn, Newton-Euler, "
       "gravity-only scene (certify off)", K_INVDYN, SCENE_GRAVITY,
       RPS3_NEWTON_EULER, RPS3_THETA_CLOSED_FORM, 1, 0, BENCH_NONE, 0);
  CASE("invdyn_lagrange_full", "rps3_invdyn, Lagrange, full scene, certify "
       "on", K_INVDYN, SCENE_FULL, RPS3_LAGRANGE, RPS3_THETA_CLOSED_FORM, 1,
       1, BENCH_NONE, 0);
  CASE("invdyn_newton_euler_full", "rps3_invdyn, Newton-Euler, full scene, "
       "certify on", K_INVDYN, SCENE_FULL, RPS3_NEWTON_EULER,
       RPS3_THETA_CLOSED_FORM, 1, 1, BENCH_NONE, 0);
  CASE("invdyn_lagrange_full_nocert", "rps3_invdyn, Lagrange, full scene, "
       "certify off", K_INVDYN, SCENE_FULL, RPS3_LAGRANGE,
       RPS3_THETA_CLOSED_FORM, 1, 0, BENCH_NONE, 0);
  CASE("invdyn_newton_euler_full_nocert", "rps3_invdyn, Newton-Euler, full "
       "scene, certify off", K_INVDYN, SCENE_FULL, RPS3_NEWTON_EULER,
       RPS3_THETA_CLOSED_FORM, 1, 0, BENCH_NONE, 0);
  CASE("pipeline_closed_gravity", "rps3_inverse, closed-form theta, "
       "gravity-only scene (no rates), Lagrange", K_INVERSE, SCENE_GRAVITY,
       RPS3_LAGRANGE, RPS3_THETA_CLOSED_FORM, 1, 0, BENCH_NONE, 0);
  CASE("pipeline_closed_lagrange_full", "rps3_inverse, closed-form theta, "
       "full scene, Lagrange: ik + velocity + acceleration + invdyn",
       K_INVERSE, SCENE_FULL, RPS3_LAGRANGE, RPS3_THETA_CLOSED_FORM, 1, 1,
       TARGET_INVDYN_NS, 0);
  CASE("pipeline_closed_lagrange_full_nocert", "rps3_inverse, closed-form "
       "theta, full scene, Lagrange, certify off (a controller's setting)",
       K_INVERSE, SCENE_FULL, RPS3_LAGRANGE, RPS3_THETA_CLOSED_FORM, 1, 0,
       TARGET_INVDYN_NS, 0);
  CASE("pipeline_closed_lagrange_paper_nocert", "rps3_inverse, closed-form "
       "theta, the paper's effects (gravity and inertia of platform and "
       "links), Lagrange, certify off", K_INVERSE, SCENE_PAPER, RPS3_LAGRANGE,
       RPS3_THETA_CLOSED_FORM, 1, 0, TARGET_INVDYN_NS, 0);
  CASE("stages_closed_lagrange_paper_nocert", "the per-point stages alone "
       "(ik, velocity, acceleration, invdyn: rps3_inverse_stages, the "
       "path of every configuration outside the one-point kernel and "
       "of the points it does not certify), closed-form theta, the "
       "paper's effects, Lagrange, certify off",
       K_INVERSE, SCENE_PAPER, RPS3_LAGRANGE, RPS3_THETA_CLOSED_FORM, 1, 0,
       BENCH_NONE, 0);
  cases[ncase - 1].stages = 1;
  CASE("stages_closed_lagrange_paper", "the per-point stages alone, the "
       "paper's effects, Lagrange, certify on", K_INVERSE, SCENE_PAPER,
       RPS3_LAGRANGE, RPS3_THETA_CLOSED_FORM, 1, 1, BENCH_NONE, 0);
  cases[ncase - 1].stages = 1;
  CASE("pipeline_closed_lagrange_paper_forces", "rps3_inverse, closed-form "
       "theta, the paper's effects, Lagrange, opt.outputs = RPS3_OUT_FORCES | "
       "RPS3_OUT_TRANSMISSION (F and the transmission)",
       K_INVERSE, SCENE_PAPER, RPS3_LAGRANGE, RPS3_THETA_CLOSED_FORM, 1, 0,
       BENCH_NONE, 0);
  cases[ncase - 1].m.opt.outputs = RPS3_OUT_FORCES | RPS3_OUT_TRANSMISSION;
  CASE("pipeline_closed_lagrange_paper_lean", "rps3_inverse, closed-form "
       "theta, the paper's effects, Lagrange, opt.outputs = RPS3_OUT_FORCES "
       "(F alone, the leanest pass, every check; the "
       "outputs of the generated code)", K_INVERSE, SCENE_PAPER,
       RPS3_LAGRANGE, RPS3_THETA_CLOSED_FORM, 1, 0, BENCH_NONE, 0);
  cases[ncase - 1].m.opt.outputs = RPS3_OUT_FORCES;
  CASE("anchor_generated", "SymPy-generated CSE'd C (tests/bench/"
       "gen_anchor.py): pose, rates, accelerations -> F, the paper's four "
       "effects", K_ANCHOR, SCENE_PAPER, RPS3_LAGRANGE,
       RPS3_THETA_CLOSED_FORM, 1, 0, BENCH_NONE, 0);
  CASE("anchor_generated_batch", "the generated code of anchor_generated "
       "in a loop over 1000 points a call as structures of arrays (time per "
       "point; rps3_anchor_forces_batch): the sines and cosines of a block "
       "of 64 points (glibc's vector ones where libmvec links, else libm's), "
       "then a #pragma omp simd loop, built with the batch kernel's flags "
       "and target clones", K_ANCHOR_BATCH, SCENE_PAPER,
       RPS3_LAGRANGE, RPS3_THETA_CLOSED_FORM, 1, 0, BENCH_NONE, 0);
  CASE("batch_closed_lagrange_paper_nocert", "rps3_inverse_batch, 1000 "
       "points a call (time per point), closed-form theta, the paper's "
       "effects, Lagrange, certify off, F only", K_BATCH, SCENE_PAPER,
       RPS3_LAGRANGE, RPS3_THETA_CLOSED_FORM, 1, 0, BENCH_NONE, 0);
  CASE("batch_closed_lagrange_paper_lean", "rps3_inverse_batch, 1000 "
       "points a call (time per point), closed-form theta, the paper's "
       "effects, Lagrange, F only, opt.outputs = RPS3_OUT_FORCES (the "
       "leanest pass)", K_BATCH, SCENE_PAPER,
       RPS3_LAGRANGE, RPS3_THETA_CLOSED_FORM, 1, 0, BENCH_NONE, 0);
  cases[ncase - 1].m.opt.outputs = RPS3_OUT_FORCES;
  CASE("pipeline_closed_lagrange_paper", "rps3_inverse, closed-form theta, "
       "the paper's effects, Lagrange, certify on (the default)", K_INVERSE,
       SCENE_PAPER, RPS3_LAGRANGE, RPS3_THETA_CLOSED_FORM, 1, 1, BENCH_NONE,
       0);
  CASE("batch_closed_lagrange_paper_all", "rps3_inverse_batch, 1000 points "
       "a call (time per point), closed-form theta, the paper's effects, "
       "Lagrange, certify on, every output (F, shares, lambda, cond, "
       "residual, l, theta, status, warn, niter)", K_BATCH_ALL, SCENE_PAPER,
       RPS3_LAGRANGE, RPS3_THETA_CLOSED_FORM, 1, 1, BENCH_NONE, 0);
  CASE("pipeline_closed_newton_euler_full", "rps3_inverse, closed-form "
       "theta, full scene, Newton-Euler", K_INVERSE, SCENE_FULL,
       RPS3_NEWTON_EULER, RPS3_THETA_CLOSED_FORM, 1, 1, TARGET_INVDYN_NS, 0);
  CASE("pipeline_warm_lagrange_full", "rps3_inverse, multiroot theta "
       "(hybridsj) warm from the previous sample, full scene, Lagrange",
       K_INVERSE, SCENE_FULL, RPS3_LAGRANGE, RPS3_THETA_MULTIROOT, 1, 1,
       TARGET_PIPELINE_NS, 1);
  CASE("pipeline_warm_newton_euler_full", "rps3_inverse, multiroot theta "
       "(hybridsj) warm from the previous sample, full scene, Newton-Euler",
       K_INVERSE, SCENE_FULL, RPS3_NEWTON_EULER, RPS3_THETA_MULTIROOT, 1, 1,
       TARGET_PIPELINE_NS, 1);
  CASE("pipeline_warm_lagrange_paper", "rps3_inverse, multiroot theta "
       "(hybridsj) warm from the previous sample, the paper's effects, "
       "Lagrange, certify on (the default)", K_INVERSE, SCENE_PAPER,
       RPS3_LAGRANGE, RPS3_THETA_MULTIROOT, 1, 1, TARGET_WARM_PAPER_NS, 1);
  CASE("fwddyn_full", "rps3_fwddyn: (l, dl, F) -> ddl and every rate, full "
       "scene, theta warm from the previous 1 ms sample; target 3x "
       "pipeline_closed_lagrange_full_nocert of this run", K_FWDDYN,
       SCENE_FULL, RPS3_LAGRANGE, RPS3_THETA_CLOSED_FORM, 1, 0, BENCH_NONE, 1);
  CASE("sim_helix_computed_torque_1khz_rk4", "one 1 ms control period of "
       "the paper's helix under computed torque (kp 400, kd 40, its own "
       "exact model), the paper's effects, RK4 at the control rate (the "
       "controller's tick; 4 stages, the first reusing the state evaluated "
       "at the end of the last period; the state at the period's end); "
       "1000 ns = 1000x real time", K_SIM, SCENE_PAPER, RPS3_LAGRANGE,
       RPS3_THETA_CLOSED_FORM, 1, 0, TARGET_SIM_NS, 0);
  CASE("sim_helix_run_computed_torque_1khz_rk4", "the same control "
       "period, rps3_sim_advance called once over a batch's periods (up "
       "to the helix's end; the state reported at the call's end alone): "
       "the 10 s helix as one run", K_SIM_RUN, SCENE_PAPER, RPS3_LAGRANGE,
       RPS3_THETA_CLOSED_FORM, 1, 0, TARGET_SIM_NS, 0);
  CASE("sim_helix_user_plant_1khz_rk4", "the control period of "
       "sim_helix_computed_torque_1khz_rk4 under the same law written by "
       "the user (tests/bench/user_law.h: public API, desired motion by "
       "rps3_link_motion), declaring "
       "RPS3_CTRL_USES_PLANT: the plant's Mq and hq offered at the tick; "
       "1000 ns = 1000x real time", K_SIM, SCENE_PAPER, RPS3_LAGRANGE,
       RPS3_THETA_CLOSED_FORM, 1, 0, TARGET_SIM_NS, 0);
  cases[ncase - 1].law = LAW_USER_PLANT;
  CASE("sim_helix_run_user_plant_1khz_rk4", "the periods of "
       "sim_helix_run_computed_torque_1khz_rk4 (the helix as one run) "
       "under the user's law of sim_helix_user_plant_1khz_rk4",
       K_SIM_RUN, SCENE_PAPER, RPS3_LAGRANGE, RPS3_THETA_CLOSED_FORM, 1, 0,
       TARGET_SIM_NS, 0);
  cases[ncase - 1].law = LAW_USER_PLANT;
  CASE("sim_helix_wrapped_computed_torque_1khz_rk4", "the control period "
       "of sim_helix_computed_torque_1khz_rk4, the library's law bound as "
       "a plain callback {rps3_ctrl_update, ctrl, rate} (no capability: "
       "it solves every measured state itself)", K_SIM, SCENE_PAPER,
       RPS3_LAGRANGE, RPS3_THETA_CLOSED_FORM, 1, 0, TARGET_SIM_NS, 0);
  cases[ncase - 1].law = LAW_WRAPPED;
  CASE("design_grid_1000_all", "rps3_design_eval_grid (time per pose): "
       "Table II's design on its default 10 x 10 x 10 pose grid, every "
       "index (reach flags, lengths, angles, clearance, LTI, OTI, CTI, "
       "cond_h, transmission, centre, spin) and the summary; target 1 ms "
       "the grid", K_DESIGN, SCENE_PAPER, RPS3_LAGRANGE,
       RPS3_THETA_CLOSED_FORM, 1, 0, TARGET_DESIGN_NS, 0);
  CASE("consistent_fit_general_76", "rps3_ident_consistent (time per "
       "fit): the general model's 76 parameters (7 bodies, the pins' "
       "friction) from 30,000 rows, 10 s of a sine trajectory at 1 kHz, "
       "1 % noise, the full scene's bodies (point-mass links, massless "
       "pistons: the optimum on the boundary of the consistent set); "
       "iter: the fit's iterations; target 1 s", K_CONSISTENT, SCENE_FULL, RPS3_LAGRANGE,
       RPS3_THETA_CLOSED_FORM, 1, 0, TARGET_CFIT_NS, 1);
  CASE("pipeline_closed_lagrange_general_nocert", "rps3_inverse, "
       "closed-form theta, general bodies, Lagrange, certify off",
       K_INVERSE, SCENE_GENERAL, RPS3_LAGRANGE, RPS3_THETA_CLOSED_FORM, 1, 0,
       BENCH_NONE, 0);
  CASE("regressor_std_point", "rps3_regressor_std: the 3 x 82 regressor of "
       "the standard parameters at a point, closed-form theta, general "
       "bodies, Lagrange",
       K_REGRESSOR_STD, SCENE_GENERAL, RPS3_LAGRANGE, RPS3_THETA_CLOSED_FORM,
       1, 0, BENCH_NONE, 0);
  CASE("regressor_point", "rps3_regressor: the paper model's 3 x 12 "
       "regressor at a point, closed-form theta, full scene, Lagrange",
       K_REGRESSOR, SCENE_FULL, RPS3_LAGRANGE, RPS3_THETA_CLOSED_FORM, 1, 0,
       BENCH_NONE, 0);
  CASE("batch_closed_lagrange_full_nocert", "rps3_inverse_batch, 1000 "
       "points a call (time per point), closed-form theta, full scene, "
       "Lagrange, certify off, F only", K_BATCH, SCENE_FULL, RPS3_LAGRANGE,
       RPS3_THETA_CLOSED_FORM, 1, 0, BENCH_NONE, 0);
  CASE("regressor_batch", "rps3_regressor_batch, 1000 points a call (time "
       "per point): the paper model's regressor of "
       "batch_closed_lagrange_full_nocert's points", K_REGRESSOR_BATCH,
       SCENE_FULL, RPS3_LAGRANGE, RPS3_THETA_CLOSED_FORM, 1, 0, BENCH_NONE,
       0);
  CASE("batch_closed_lagrange_general_nocert", "rps3_inverse_batch, 1000 "
       "points a call (time per point), closed-form theta, general bodies, "
       "Lagrange, certify off, F only", K_BATCH, SCENE_GENERAL, RPS3_LAGRANGE,
       RPS3_THETA_CLOSED_FORM, 1, 0, BENCH_NONE, 0);
  CASE("regressor_std_batch", "rps3_regressor_std_batch, 1000 points a "
       "call (time per point): the 3 x 82 regressor of "
       "batch_closed_lagrange_general_nocert's points", K_REGRESSOR_STD_BATCH,
       SCENE_GENERAL, RPS3_LAGRANGE, RPS3_THETA_CLOSED_FORM, 1, 0, BENCH_NONE,
       0);
#undef CASE

  /* -k: keep the matching cases only */
  if (only != NULL) {
    int kept = 0;
    for (i = 0; i < ncase; i++)
      if (name_matches(cases[i].name, only)) cases[kept++] = cases[i];
    ncase = kept;
    if (ncase == 0) {
      fprintf(stderr, "rps3-bench: no case matches '%s'\n", only);
      return 2;
    }
  }

  /* the batched anchor checked against the scalar one */
  for (i = 0; i < ncase; i++)
    if (cases[i].kind == K_ANCHOR_BATCH) check_anchor_batch(&cases[i].m, &pt);

  /* workspaces, snapshots and the batch-time arrays */
  for (i = 0; i < ncase; i++) {
    bench_case *c = &cases[i];
    c->per_call = malloc((size_t)batches * sizeof(double));
    c->cpu_call = malloc((size_t)batches * sizeof(double));
    c->b_status = malloc(BATCH_N * sizeof(int));
    c->b_warn = malloc(BATCH_N * sizeof(int));
    c->b_niter = malloc(BATCH_N * sizeof(int));
    c->b_F = malloc(3 * BATCH_N * sizeof(double));
    c->b_Fe = malloc(3 * RPS3_NEFFECT * BATCH_N * sizeof(double));
    c->b_l = malloc(3 * BATCH_N * sizeof(double));
    c->b_theta = malloc(3 * BATCH_N * sizeof(double));
    c->b_lambda = malloc(3 * BATCH_N * sizeof(double));
    c->b_cond = malloc(BATCH_N * sizeof(double));
    c->b_eres = malloc(BATCH_N * sizeof(double));
    c->b_Y = c->kind == K_REGRESSOR_BATCH || c->kind == K_REGRESSOR_STD_BATCH
                 ? malloc(3 * RPS3_NSTD * BATCH_N * sizeof(double))
                 : NULL;
    if (c->per_call == NULL || c->cpu_call == NULL || c->b_status == NULL ||
        c->b_warn == NULL || c->b_niter == NULL || c->b_F == NULL ||
        c->b_Fe == NULL || c->b_l == NULL || c->b_theta == NULL ||
        c->b_lambda == NULL || c->b_cond == NULL || c->b_eres == NULL ||
        ((c->kind == K_REGRESSOR_BATCH || c->kind == K_REGRESSOR_STD_BATCH) &&
         c->b_Y == NULL) ||
        rps3_data_alloc(&c->m, &c->d) != RPS3_OK) {
      fprintf(stderr, "rps3-bench: out of memory\n");
      return 2;
    }
    fill_ring(c, &pt);
    c->dir = 1;
    if (c->kind == K_SIM || c->kind == K_SIM_RUN) {
      rps3_traj tr;
      rps3_traj_default(&tr);
      if (rps3_sim_alloc(&c->m, NULL, &c->sim, NULL) != RPS3_OK ||
          rps3_ctrl_alloc(RPS3_CTRL_COMPUTED_TORQUE, 400.0, 40.0, &c->m, &tr,
                          &c->ctrl, NULL) != RPS3_OK ||
          user_law_init(&c->user, &c->m, &tr, 400.0, 40.0, 1) != RPS3_OK ||
          rps3_sim_start(c->sim, 0.0, pt.pose[0], pt.dpose[0]) != RPS3_OK) {
        fprintf(stderr, "rps3-bench: %s: set-up failed\n", c->name);
        return 2;
      }
    }
    if (c->kind == K_DESIGN) {
      rps3_design_out *o = &c->dout;
      o->flags = malloc(BATCH_N * sizeof(int));
      o->l = malloc(3 * BATCH_N * sizeof(double));
      o->theta = malloc(3 * BATCH_N * sizeof(double));
      o->ball = malloc(3 * BATCH_N * sizeof(double));
      o->c = malloc(3 * BATCH_N * sizeof(double));
      o->clearance = malloc(BATCH_N * sizeof(double));
      o->lti = malloc(BATCH_N * sizeof(double));
      o->oti = malloc(BATCH_N * sizeof(double));
      o->cti = malloc(BATCH_N * sizeof(double));
      o->cond_h = malloc(BATCH_N * sizeof(double));
      o->transmission = malloc(BATCH_N * sizeof(double));
      o->spin = malloc(BATCH_N * sizeof(double));
      if (!o->flags || !o->l || !o->theta || !o->ball || !o->c ||
          !o->clearance || !o->lti || !o->oti || !o->cti || !o->cond_h ||
          !o->transmission || !o->spin ||
          rps3_design_ws_alloc(&c->dws) != RPS3_OK) {
        fprintf(stderr, "rps3-bench: out of memory\n");
        return 2;
      }
    }
    if (c->kind == K_CONSISTENT && cfit_make(c) != 0) return 2;
    /* warm-up batch: caches, branch predictors, the walk's warm start */
    run_batch(c, &pt, calls);
    c->iter = c->solves = c->failures = 0;
  }

  /* timed batches, round-robin over the cases */
  for (b = 0; b < batches; b++)
    for (i = 0; i < ncase; i++) {
      /* K_CONSISTENT: one fit a batch, timed as one call */
      double nc = cases[i].kind == K_CONSISTENT ? 1.0 : (double)calls;
      double t0 = clock_ns(CLOCK_MONOTONIC), t1, c0, c1;
      c0 = clock_ns(CLOCK_THREAD_CPUTIME_ID);
      run_batch(&cases[i], &pt, calls);
      c1 = clock_ns(CLOCK_THREAD_CPUTIME_ID);
      t1 = clock_ns(CLOCK_MONOTONIC);
      cases[i].per_call[b] = (t1 - t0) / nc;
      cases[i].cpu_call[b] = (c1 - c0) / nc;
    }
  /* ratios batch by batch (the same round of the interleaving), before
     the per-case sort */
  nratio = ratios(cases, ncase, batches, rat);
  for (i = 0; i < ncase; i++) summarize(&cases[i], calls, batches, &rows[i]);
  /* the forward dynamics' target is relative to this run's inverse */
  for (i = 0; i < ncase; i++)
    if (strcmp(rows[i].name, "fwddyn_full") == 0) {
      int j;
      for (j = 0; j < ncase; j++)
        if (strcmp(rows[j].name, "pipeline_closed_lagrange_full_nocert") == 0)
          rows[i].target_ns = FWDDYN_PER_INVERSE * rows[j].median_ns;
    }

  /* the table */
  machine_name(machine, sizeof(machine));
  printf("rps3-bench: %s; %ld batches x %ld calls per case; helix of "
         "Table II at %.0f Hz (%d points)\n",
         machine, batches, calls, RATE_HZ, pt.n);
  printf("%-34s %10s %19s %8s %6s %9s %7s\n", "case", "median ns",
         "p10 - p90 ns", "cpu ns", "iter", "target ns", "ratio");
  for (i = 0; i < ncase; i++) {
    const bench_row *r = &rows[i];
    char it[16] = "", tg[16] = "", ra[16] = "";
    if (!isnan(r->mean_iter)) snprintf(it, sizeof(it), "%.2f", r->mean_iter);
    if (!isnan(r->target_ns)) {
      snprintf(tg, sizeof(tg), "%.0f", r->target_ns);
      snprintf(ra, sizeof(ra), "%.2f", r->median_ns / r->target_ns);
    }
    printf("%-34s %10.1f %9.1f - %7.1f %8.1f %6s %9s %7s%s\n", r->name,
           r->median_ns, r->p10_ns, r->p90_ns, r->cpu_median_ns, it, tg, ra,
           r->failures ? "  FAILED CALLS" : "");
    if (r->failures) fail = 1;
  }
  printf("ratio = median / target (<= 1 meets the target); one core, "
         "single thread\n");
  print_ratios(rat, nratio, batches);
  print_ratio_goals(rat, nratio);
  /* the verdict on the user's own controller with the plant's state,
     after the ratio goals' lines: on the thread's CPU time, which a
     shared machine does not inflate by descheduling the thread (a batch
     of 2000 periods lasts milliseconds, a time slice); the wall time is
     printed beside it */
  for (i = 0; i < ncase; i++)
    if (strstr(rows[i].name, "_user_plant_") != NULL)
      printf("goal: a user's computed torque offered the plant's state, "
             "%s, >= 1000x real time (<= %.0f ns a 1 ms period): median "
             "cpu %.1f ns = %.0fx real time (wall %.1f ns = %.0fx): %s\n",
             strstr(rows[i].name, "_run_") ? "the helix as one run"
                                            : "a call every period",
             TARGET_SIM_NS, rows[i].cpu_median_ns,
             1e6 / rows[i].cpu_median_ns, rows[i].median_ns,
             1e6 / rows[i].median_ns,
             rows[i].cpu_median_ns <= TARGET_SIM_NS ? "met" : "NOT met");

  snprintf(trajdoc, sizeof(trajdoc),
           "helix of Table II sampled at %.0f Hz (%d points), walked forward "
           "and back; stage-only cases cycle over %d snapshots along it",
           RATE_HZ, pt.n, RING);
  info.machine = machine;
  info.compiler =
#ifdef __VERSION__
      __VERSION__;
#else
      "unknown";
#endif
  info.trajectory = trajdoc;
  info.scene_full = scene_full_doc;
  info.scene_gravity = scene_gravity_doc;
  info.scene_general = scene_general_doc;
  info.clock = "clock_gettime(CLOCK_MONOTONIC) (wall) and "
               "CLOCK_THREAD_CPUTIME_ID (cpu) around each batch";
  if (strcmp(out, "-") != 0) {
    if (bench_write_h5(out, &info, rows, ncase) != 0)
      fail = 1;
    else
      printf("wrote %s\n", out);
  }

  for (i = 0; i < ncase; i++) {
    rps3_data_free(cases[i].d);
    rps3_sim_free(cases[i].sim);
    rps3_ctrl_free(cases[i].ctrl);
    user_law_free(&cases[i].user);
    cfit_free(cases[i].cf);
    free(cases[i].per_call);
    free(cases[i].cpu_call);
    free(cases[i].b_status);
    free(cases[i].b_warn);
    free(cases[i].b_niter);
    free(cases[i].b_F);
    free(cases[i].b_Y);
    free(cases[i].b_Fe);
    free(cases[i].b_l);
    free(cases[i].b_theta);
    free(cases[i].b_lambda);
    free(cases[i].b_cond);
    free(cases[i].b_eres);
  }
  free(pt.pose);
  free(pt.dpose);
  free(pt.ddpose);
  free(pt.l);
  free(pt.soa_pose);
  free(pt.soa_dpose);
  free(pt.soa_ddpose);
  free(pt.dl);
  free(pt.F);
  return fail;
}
