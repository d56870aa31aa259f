/*
 * mujoco_bench.c - MuJoCo's mj_inverse on the same states as rps3_inverse
 * and the generated anchor, timed in one process, interleaved.
 *
 *   rps3-mujoco-bench [-n ROUNDS] [-x MODEL.xml]
 *
 * MuJoCo is called as a C library (libmujoco from the `mujoco` wheel that
 * `make venv` installs, linked directly), not through Python, so no
 * interpreter overhead enters its time.  The mechanism in MJCF: the
 * platform a free body (the disc of (21): M, I = M r^2 (1/4, 1/4, 1/2));
 * each link a hinge at its pin about the pin axis (30), angle theta_i, a
 * point mass m at d from the pin, and a piston on a slide joint along the
 * link, length l_i (1e-6 kg, nearly massless); the three ball joints are
 * `connect` equality constraints between platform and pistons.  12 dofs,
 * 9 constraint rows, 3 degrees of freedom, as the mechanism.
 *
 * The states come from rps3_inverse along the paper's helix at 1 kHz:
 * qpos = (c, quat(rot), theta_1, l_1, ...), qvel = (vc, rot^T omega,
 * theta_1', l_1', ...), qacc likewise; the program first checks that they
 * close the chains (ball joint sites within 1e-12 m).  mj_inverse then
 * gives qfrc_inverse (not yet the actuator forces: a MuJoCo user still has
 * to resolve the constraint forces).  rps3 computes the paper's four
 * effects, certify off (F only).  Ratios are taken round by round.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <gsl/gsl_errno.h>
#include <mujoco/mujoco.h>

#include "anchor_gen.h"
#include "rps3.h"

#define RATE_HZ 1000.0
#define CALLS 2000

static double clock_ns(clockid_t id) {
  struct timespec ts;
  clock_gettime(id, &ts);
  return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* median, min, max of x[0..n) (sorts x) */
static void stats(double *x, int n, double out[3]) {
  qsort(x, (size_t)n, sizeof(double), cmp_double);
  out[0] = (n % 2) ? x[n / 2] : 0.5 * (x[n / 2 - 1] + x[n / 2]);
  out[1] = x[0];
  out[2] = x[n - 1];
}

/* the MJCF of model m (positions and inertias from the rps3 model) */
static int write_mjcf(const rps3_model *m, const char *path) {
  FILE *f = fopen(path, "w");
  double r = m->r;
  int i;
  if (f == NULL) return -1;
  fprintf(f, "<mujoco model=\"rps3\">\n"
             "  <compiler angle=\"radian\"/>\n"
             "  <option gravity=\"0 0 %.17g\"/>\n  <worldbody>\n"
             "    <body name=\"platform\" pos=\"0 0 0.3\">\n"
             "      <freejoint/>\n"
             "      <inertial pos=\"0 0 0\" mass=\"%.17g\" "
             "diaginertia=\"%.17g %.17g %.17g\"/>\n",
          -m->g, m->M, m->Ip[0], m->Ip[1], m->Ip[2]);
  for (i = 0; i < 3; i++)
    fprintf(f, "      <site name=\"ball%d\" pos=\"%.17g %.17g 0\"/>\n", i,
            m->body[i][0], m->body[i][1]);
  fprintf(f, "    </body>\n");
  for (i = 0; i < 3; i++) {
    const double *u = m->radial[i], *a = m->axis[i];
    /* at hinge angle 0 the link points inwards, -u: rotating about the
       pin axis by theta gives phi_l = -cos(theta) u + sin(theta) K (29) */
    fprintf(f,
            "    <body name=\"link%d\" pos=\"%.17g %.17g 0\">\n"
            "      <joint name=\"pin%d\" type=\"hinge\" axis=\"%.17g %.17g "
            "%.17g\"/>\n"
            "      <inertial pos=\"%.17g %.17g 0\" mass=\"%.17g\" "
            "diaginertia=\"1e-12 1e-12 1e-12\"/>\n"
            "      <body name=\"piston%d\">\n"
            "        <joint name=\"slide%d\" type=\"slide\" axis=\"%.17g "
            "%.17g 0\"/>\n"
            "        <inertial pos=\"0 0 0\" mass=\"1e-6\" "
            "diaginertia=\"1e-12 1e-12 1e-12\"/>\n"
            "        <site name=\"tip%d\"/>\n"
            "      </body>\n    </body>\n",
            i, m->pin[i][0], m->pin[i][1], i, a[0], a[1], a[2],
            -m->d * u[0], -m->d * u[1], m->m > 0 ? m->m : 1e-6, i, i, -u[0],
            -u[1], i);
  }
  fprintf(f, "  </worldbody>\n  <equality>\n");
  for (i = 0; i < 3; i++)
    fprintf(f, "    <connect body1=\"platform\" body2=\"piston%d\" "
               "anchor=\"%.17g %.17g 0\"/>\n",
            i, r * cos(2.0 * i * 3.14159265358979323846 / 3.0),
            r * sin(2.0 * i * 3.14159265358979323846 / 3.0));
  fprintf(f, "  </equality>\n  <actuator>\n");
  for (i = 0; i < 3; i++)
    fprintf(f, "    <motor joint=\"slide%d\"/>\n", i);
  fprintf(f, "  </actuator>\n</mujoco>\n");
  return fclose(f) == 0 ? 0 : -1;
}

int main(int argc, char **argv) {
  const char *xml = "build/rps3_mujoco.xml";
  int rounds = 51, i, k, r, n;
  char err[1024];
  rps3_check chk;
  rps3_model rm;
  rps3_traj tr;
  rps3_data *rd = NULL;
  mjModel *mm;
  mjData *md;
  double *qpos, *qvel, *qacc, (*pose)[3], (*dpose)[3], (*ddpose)[3];
  double gap = 0.0, T, par[6], sink = 0.0;
  double *t_mj, *t_rps3, *t_anc, *c_mj, *c_rps3, *c_anc, *ratio;
  double s[3];

  for (i = 1; i < argc; i++) {
    if (strcmp(argv[i], "-n") == 0 && i + 1 < argc)
      rounds = atoi(argv[++i]);
    else if (strcmp(argv[i], "-x") == 0 && i + 1 < argc)
      xml = argv[++i];
    else {
      fprintf(stderr, "usage: rps3-mujoco-bench [-n ROUNDS] [-x MODEL.xml]\n");
      return 2;
    }
  }
  if (rounds < 1) rounds = 1;
  gsl_set_error_handler_off();
  rps3_model_default(&rm);
  rm.opt.effects = RPS3_EFF_DEFAULT; /* the paper's four effects */
  rm.opt.outputs &= ~RPS3_OUT_CERTIFY;
  if (rps3_model_init(&rm, &chk) != RPS3_OK ||
      rps3_data_alloc(&rm, &rd) != RPS3_OK) {
    fprintf(stderr, "rps3-mujoco-bench: %s\n", chk.msg);
    return 2;
  }
  if (write_mjcf(&rm, xml) != 0) {
    fprintf(stderr, "rps3-mujoco-bench: cannot write %s\n", xml);
    return 2;
  }
  mm = mj_loadXML(xml, NULL, err, sizeof(err));
  if (mm == NULL) {
    fprintf(stderr, "rps3-mujoco-bench: %s: %s\n", xml, err);
    return 2;
  }
  md = mj_makeData(mm);
  if (mm->nq != 13 || mm->nv != 12) {
    fprintf(stderr, "rps3-mujoco-bench: unexpected nq %d nv %d\n",
            (int)mm->nq, (int)mm->nv);
    return 2;
  }

  /* the states: the helix at 1 kHz through rps3_inverse */
  rps3_traj_default(&tr);
  T = rps3_traj_duration(&tr);
  n = (int)floor(T * RATE_HZ + 0.5) + 1;
  qpos = malloc((size_t)n * 13 * sizeof(double));
  qvel = malloc((size_t)n * 12 * sizeof(double));
  qacc = malloc((size_t)n * 12 * sizeof(double));
  pose = malloc((size_t)n * sizeof(*pose));
  dpose = malloc((size_t)n * sizeof(*dpose));
  ddpose = malloc((size_t)n * sizeof(*ddpose));
  t_mj = malloc((size_t)rounds * 7 * sizeof(double));
  if (!qpos || !qvel || !qacc || !pose || !dpose || !ddpose || !t_mj) {
    fprintf(stderr, "rps3-mujoco-bench: out of memory\n");
    return 2;
  }
  t_rps3 = t_mj + rounds;
  t_anc = t_rps3 + rounds;
  c_mj = t_anc + rounds;
  c_rps3 = c_mj + rounds;
  c_anc = c_rps3 + rounds;
  ratio = c_anc + rounds;
  for (k = 0; k < n; k++) {
    double *qp = qpos + 13 * k, *qv = qvel + 12 * k, *qa = qacc + 12 * k;
    double rot9[9], w[3];
    rps3_traj_eval(&rm, &tr, T * (double)k / (double)(n - 1), pose[k],
                   dpose[k], ddpose[k]);
    memcpy(rd->pose, pose[k], sizeof(rd->pose));
    memcpy(rd->dpose, dpose[k], sizeof(rd->dpose));
    memcpy(rd->ddpose, ddpose[k], sizeof(rd->ddpose));
    if (rps3_inverse(&rm, rd) != RPS3_OK) {
      fprintf(stderr, "rps3-mujoco-bench: point %d: %s\n", k, rd->err.msg);
      return 2;
    }
    for (i = 0; i < 3; i++) {
      int j;
      qp[i] = rd->c[i];
      qv[i] = rd->vc[i];
      qa[i] = rd->ac[i];
      for (j = 0; j < 3; j++) rot9[3 * i + j] = rd->rot[i][j];
    }
    mju_mat2Quat(qp + 3, rot9);
    /* free joint: angular velocity and its rate in the body frame */
    for (i = 0; i < 3; i++) {
      qv[3 + i] = rd->rot[0][i] * rd->omega[0] + rd->rot[1][i] * rd->omega[1] +
                  rd->rot[2][i] * rd->omega[2];
      w[i] = rd->rot[0][i] * rd->domega[0] + rd->rot[1][i] * rd->domega[1] +
             rd->rot[2][i] * rd->domega[2];
    }
    for (i = 0; i < 3; i++) {
      qa[3 + i] = w[i];
      qp[7 + 2 * i] = rd->theta[i];
      qp[8 + 2 * i] = rd->l[i];
      qv[6 + 2 * i] = rd->dtheta[i];
      qv[7 + 2 * i] = rd->dl[i];
      qa[6 + 2 * i] = rd->ddtheta[i];
      qa[7 + 2 * i] = rd->ddl[i];
    }
    /* the state closes the three chains */
    memcpy(md->qpos, qp, 13 * sizeof(double));
    mj_kinematics(mm, md);
    for (i = 0; i < 3; i++) {
      int j;
      for (j = 0; j < 3; j++) {
        double e = fabs(md->site_xpos[3 * i + j] - md->site_xpos[9 + 3 * i + j]);
        if (!(e <= gap)) gap = e;
      }
    }
  }
  if (!(gap <= 1e-12)) {
    fprintf(stderr, "rps3-mujoco-bench: the states do not close the chains "
                    "(gap %.3g m)\n", gap);
    return 1;
  }
  par[0] = rm.R;
  par[1] = rm.rho;
  par[2] = rm.M;
  par[3] = rm.m;
  par[4] = rm.d;
  par[5] = rm.g;

  /* rounds: CALLS points of each, back to back, from the same offset */
  for (r = 0; r < rounds + 1; r++) {
    int p0 = (r * CALLS) % (n - CALLS);
    double w0, w1, c0, c1;
    /* mj_inverse */
    w0 = clock_ns(CLOCK_MONOTONIC);
    c0 = clock_ns(CLOCK_THREAD_CPUTIME_ID);
    for (k = p0; k < p0 + CALLS; k++) {
      memcpy(md->qpos, qpos + 13 * k, 13 * sizeof(double));
      memcpy(md->qvel, qvel + 12 * k, 12 * sizeof(double));
      memcpy(md->qacc, qacc + 12 * k, 12 * sizeof(double));
      mj_inverse(mm, md);
      sink += md->qfrc_inverse[7];
    }
    c1 = clock_ns(CLOCK_THREAD_CPUTIME_ID);
    w1 = clock_ns(CLOCK_MONOTONIC);
    if (r > 0) {
      t_mj[r - 1] = (w1 - w0) / CALLS;
      c_mj[r - 1] = (c1 - c0) / CALLS;
    }
    /* rps3_inverse */
    w0 = clock_ns(CLOCK_MONOTONIC);
    c0 = clock_ns(CLOCK_THREAD_CPUTIME_ID);
    for (k = p0; k < p0 + CALLS; k++) {
      memcpy(rd->pose, pose[k], sizeof(rd->pose));
      memcpy(rd->dpose, dpose[k], sizeof(rd->dpose));
      memcpy(rd->ddpose, ddpose[k], sizeof(rd->ddpose));
      if (rps3_inverse(&rm, rd) != RPS3_OK) return 1;
      sink += rd->F[0];
    }
    c1 = clock_ns(CLOCK_THREAD_CPUTIME_ID);
    w1 = clock_ns(CLOCK_MONOTONIC);
    if (r > 0) {
      t_rps3[r - 1] = (w1 - w0) / CALLS;
      c_rps3[r - 1] = (c1 - c0) / CALLS;
    }
    /* the generated anchor */
    w0 = clock_ns(CLOCK_MONOTONIC);
    c0 = clock_ns(CLOCK_THREAD_CPUTIME_ID);
    for (k = p0; k < p0 + CALLS; k++) {
      double F[3];
      if (rps3_anchor_forces(par, pose[k], dpose[k], ddpose[k], F) != 0)
        return 1;
      sink += F[0];
    }
    c1 = clock_ns(CLOCK_THREAD_CPUTIME_ID);
    w1 = clock_ns(CLOCK_MONOTONIC);
    if (r > 0) {
      t_anc[r - 1] = (w1 - w0) / CALLS;
      c_anc[r - 1] = (c1 - c0) / CALLS;
    }
  }

  printf("rps3-mujoco-bench: MuJoCo %s (C library of the mujoco wheel); "
         "%d rounds x %d points of the helix at 1 kHz; chains closed to "
         "%.2g m\n", mj_versionString(), rounds, CALLS, gap);
  printf("%-44s %22s %22s\n", "per point, median [min - max]", "wall ns",
         "cpu ns");
  {
    const char *names[3] = {"mj_inverse (qfrc_inverse, 12 dofs)",
                            "rps3_inverse (paper's effects, F only)",
                            "generated anchor (F)"};
    double *tw[3] = {t_mj, t_rps3, t_anc}, *tc[3] = {c_mj, c_rps3, c_anc};
    double ws[3], cs[3];
    double *copy = malloc((size_t)rounds * sizeof(double));
    int j;
    if (copy == NULL) return 2;
    /* ratios first, from the unsorted rounds */
    for (j = 0; j < 2; j++) {
      double *den = (j == 0) ? c_rps3 : c_anc;
      for (r = 0; r < rounds; r++) ratio[r] = c_mj[r] / den[r];
      stats(ratio, rounds, s);
      if (j == 0)
        printf("ratio mj_inverse / rps3_inverse (cpu, round by round): "
               "%.2f [%.2f - %.2f]\n", s[0], s[1], s[2]);
      else
        printf("ratio mj_inverse / generated anchor (cpu, round by round): "
               "%.2f [%.2f - %.2f]\n", s[0], s[1], s[2]);
    }
    for (j = 0; j < 3; j++) {
      memcpy(copy, tw[j], (size_t)rounds * sizeof(double));
      stats(copy, rounds, ws);
      memcpy(copy, tc[j], (size_t)rounds * sizeof(double));
      stats(copy, rounds, cs);
      printf("%-44s %7.1f [%5.0f - %5.0f] %7.1f [%5.0f - %5.0f]\n", names[j],
             ws[0], ws[1], ws[2], cs[0], cs[1], cs[2]);
    }
    free(copy);
  }
  if (sink == 12345.678) printf("\n"); /* keep the results live */
  mj_deleteData(md);
  mj_deleteModel(mm);
  rps3_data_free(rd);
  free(qpos);
  free(qvel);
  free(qacc);
  free(pose);
  free(dpose);
  free(ddpose);
  free(t_mj);
  return 0;
}
