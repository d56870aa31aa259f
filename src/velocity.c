/*
 * velocity.c - velocities and accelerations, section IV, eqs. (25)-(33),
 * by two routes: from the pose rates (alpha, beta, z_c) and from the link
 * rates through the constraint Jacobian.  Tests check one against the other
 * and both against central differences of positions.
 */
#include "internal.h"
#include "linalg.h"
#include "links.h"
#include "power.h"

/*
 * Angular velocity (or acceleration) of the platform from the motion of its
 * three ball joints relative to the centre: u_i = omega x rho_i.  For three
 * points at 120 degrees in the plane normal to a,
 *   sum rho_i x u_i = (3 r^2 / 2) (omega + (a . omega) a),
 * which inverts in closed form.  This is (26)-(28) solved for omega.
 */
void rps3_omega_from_balls(double omega[3], const double rho[3][3],
                           const double u[3][3], const double a[3], double r) {
  double w[3] = {0, 0, 0}, t[3];
  int i;
  for (i = 0; i < 3; i++) {
    v3_cross(t, rho[i], u[i]);
    v3_axpy(w, w, 1.0, t);
  }
  RPS3_OMEGA_OF_SUM(RPS3_V3C, 2.0 / (3.0 * r * r), w[0], w[1], w[2], a, omega);
}

/* factor df/dtheta for the rate stages: RPS3_ESING when singular or
   conditioned worse than opt.cond_max (the same test as the lambda system
   of rps3_invdyn) */
int rps3_jt_factor(const rps3_model *m, rps3_data *d, const double Jt[3][3],
                   double LU[9], int perm[3]) {
  double A[9], cond;
  int i, k;
  for (i = 0; i < 3; i++)
    for (k = 0; k < 3; k++) A[3 * i + k] = LU[3 * i + k] = Jt[i][k];
  cond = rps3_lu_factor(3, LU, perm) != 0 ? HUGE_VAL
                                          : rps3_lu_cond1(3, A, LU, perm);
  return rps3_sing_check(m, d, RPS3_SING_JT, cond);
}

/* solve (df/dtheta) x = rhs, after rps3_jt_factor's test */
static int solve_jt(const rps3_model *m, rps3_data *d, double Jt[3][3],
                    double x[3]) {
  double LU[9];
  int perm[3], status;
  status = rps3_jt_factor(m, d, M3C(Jt), LU, perm);
  if (status != RPS3_OK) return status;
  rps3_lu_solve(3, LU, perm, x);
  return RPS3_OK;
}

void rps3_pose_twist(const rps3_model *m, const rps3_pose_trig *t,
                     const double dpose[3], double w[3], double vc[3]) {
  const double ca = t->ca, sa = t->sa, sb = t->sb, vb = t->vb;
  const double da = dpose[0], db = dpose[1], dvb = sb * db;
  /* omega of Rz(alpha) Ry(beta) Rz(-alpha): alpha-dot (e_z - a) plus
     beta-dot about the node line e_beta = (-sin a, cos a, 0) */
  w[0] = -da * sb * ca - db * sa;
  w[1] = -da * sb * sa + db * ca;
  w[2] = da * vb;
  /* centre velocity: derivative of (3)-(4), then z_c */
  vc[0] = -0.5 * m->r * (dvb * t->C - 2.0 * vb * t->S * da);
  vc[1] = 0.5 * m->r * (dvb * t->S + 2.0 * vb * t->C * da);
  vc[2] = dpose[2];
}

void rps3_pose_twist_rate(const rps3_model *m, const rps3_pose_trig *t,
                          const double dpose[3], const double ddpose[3],
                          const double w[3], double dw[3], double ac[3]) {
  const double ca = t->ca, sa = t->sa, sb = t->sb, cb = t->cb, vb = t->vb;
  const double C = t->C, S = t->S, da = dpose[0], db = dpose[1];
  const double dda = ddpose[0], ddb = ddpose[1];
  double a[3], ez_a[3], adot[3], dvb, ddvb, dC, dS, ddC, ddS;
  /* d/dt of omega = da (e_z - a) + db e_beta */
  a[0] = sb * ca;
  a[1] = sb * sa;
  a[2] = cb;
  ez_a[0] = -a[0];
  ez_a[1] = -a[1];
  ez_a[2] = vb;
  v3_cross(adot, w, a);
  dw[0] = dda * ez_a[0] - da * adot[0] - ddb * sa - db * da * ca;
  dw[1] = dda * ez_a[1] - da * adot[1] + ddb * ca - db * da * sa;
  dw[2] = dda * ez_a[2] - da * adot[2];
  /* centre: second derivative of (3)-(4) */
  dvb = sb * db;
  ddvb = cb * db * db + sb * ddb;
  dC = -2.0 * S * da;
  dS = 2.0 * C * da;
  ddC = -4.0 * C * da * da - 2.0 * S * dda;
  ddS = -4.0 * S * da * da + 2.0 * C * dda;
  ac[0] = -0.5 * m->r * (ddvb * C + 2.0 * dvb * dC + vb * ddC);
  ac[1] = 0.5 * m->r * (ddvb * S + 2.0 * dvb * dS + vb * ddS);
  ac[2] = ddpose[2];
}

int rps3_link_motion(const rps3_model *m, rps3_data *d, int acc) {
  rps3_pose_trig t;
  double rot[3][3], c[3], w[3], vc[3], dw[3], ac[3], chk = 0.0;
  int i;
  d->stage = 0;
  d->warn = 0;
  if (!v3_finite(d->pose) || !v3_finite(d->dpose) ||
      (acc && !v3_finite(d->ddpose)))
    RPS3_ERROR(d, RPS3_EINVAL, "pose, dpose or ddpose is not finite");
  rps3_pose_trig_eval(&t, d->pose, 1);
  rps3_pose_frame(m, &t, d->pose[2], rot, c);
  rps3_pose_twist(m, &t, d->dpose, w, vc);
  if (acc) rps3_pose_twist_rate(m, &t, d->dpose, d->ddpose, w, dw, ac);
  for (i = 0; i < 3; i++) {
    double rx[3], ry[3], b[3], rho[3], v[3], wr[3], bd[3], l2, l, il, dl;
    double radial;
    int q;
    /* the ball joint and the link vector (src/links.h; the ball joint and
       the pin lie in their frames' xy planes, the model's body[i][2] =
       pin[i][2] = 0) */
    for (q = 0; q < 3; q++) {
      rx[q] = rot[q][0];
      ry[q] = rot[q][1];
    }
    RPS3_LINK_BALL(RPS3_V3C, RPS3_MA, m->body[i][0], m->body[i][1], rx, ry, c,
                   rho, b);
    RPS3_LINK_VEC(RPS3_V3C, v3_dot, RPS3_MA, b, m->pin[i][0], m->pin[i][1],
                  m->radial[i][0], m->radial[i][1], v, l2, l, radial);
    (void)radial; /* no directions here */
    if (!RPS3_LINK_REACHABLE(l, v[2]))
      RPS3_ERROR(d, RPS3_EREACH,
                 "link %d: length %.6g m, ball joint height %.6g m (needs "
                 "length > 0 and height > 0) at pose (%.6g, %.6g, %.6g)",
                 i + 1, l, v[2], d->pose[0], d->pose[1], d->pose[2]);
    il = 1.0 / l;
    /* the ball joint's velocity (26), l' = n . b' (src/links.h at v in
       place of phi, n = v / l) */
    RPS3_BALL_VEL(RPS3_V3C, RPS3_MS, w, rho, vc, wr, bd);
    dl = v3_dot(v, bd) * il;
    d->l[i] = l;
    d->dl[i] = dl;
    chk += l + fabs(dl);
    if (acc) {
      /* l l'' = |b'|^2 - l'^2 + (b - P) . b'',  b'' = ac + dw x rho + w x
         (w x rho) */
      double bdd[3];
      RPS3_BALL_ACC(RPS3_V3C, RPS3_MS, w, dw, rho, wr, ac, bdd);
      d->ddl[i] = (v3_dot(bd, bd) - dl * dl + v3_dot(v, bdd)) * il;
      chk += fabs(d->ddl[i]);
    }
  }
  if (!(chk <= DBL_MAX)) {
    RPS3_CHECK_FINITE(d, d->l, 3, "l");
    RPS3_CHECK_FINITE(d, d->dl, 3, "dl");
    if (acc) RPS3_CHECK_FINITE(d, d->ddl, 3, "ddl");
  }
  return RPS3_OK;
}

int rps3_velocity(const rps3_model *m, rps3_data *d) {
  return rps3_velocity_with(m, d, NULL);
}

int rps3_velocity_with(const rps3_model *m, rps3_data *d,
                       const rps3_pose_trig *pt) {
  rps3_pose_trig own;
  double rho[3], wr[3], bd[3];
  int i;
  if (m == NULL || d == NULL || !m->valid) return RPS3_EINVAL;
  if (!(d->stage & RPS3_STAGE_POS))
    RPS3_ERROR(d, RPS3_ESTATE, "velocity needs positions (rps3_ik or rps3_fk)");
  if (!v3_finite(d->dpose))
    RPS3_ERROR(d, RPS3_EINVAL, "dpose (%g, %g, %g) is not finite", d->dpose[0],
               d->dpose[1], d->dpose[2]);
  d->stage &= RPS3_STAGE_POS;
  if (pt == NULL) {
    rps3_pose_trig_eval(&own, d->pose, 0);
    pt = &own;
  }
  rps3_pose_twist(m, pt, d->dpose, d->omega, d->vc);

  /* ball joints (26), then the joint rates from (28) (src/links.h) */
  for (i = 0; i < 3; i++) {
    v3_sub(rho, d->b[i], d->c);
    RPS3_BALL_VEL(RPS3_V3C, RPS3_MS, d->omega, rho, d->vc, wr, bd);
    RPS3_LINK_VEL(v3_dot, d->phi[i], d->dphi[i], 1.0 / d->l[i], bd, d->dl[i],
                  d->dtheta[i]);
  }
  RPS3_CHECK_FINITE(d, d->omega, 3, "omega");
  RPS3_CHECK_FINITE(d, d->vc, 3, "vc");
  RPS3_CHECK_FINITE(d, d->dl, 3, "dl");
  RPS3_CHECK_FINITE(d, d->dtheta, 3, "dtheta");
  d->stage |= RPS3_STAGE_VEL;
  return RPS3_OK;
}

int rps3_acceleration(const rps3_model *m, rps3_data *d) {
  return rps3_acceleration_with(m, d, NULL);
}

int rps3_acceleration_with(const rps3_model *m, rps3_data *d,
                           const rps3_pose_trig *pt) {
  rps3_pose_trig own;
  double wr[3], rho[3], bdd[3];
  int i;
  if (m == NULL || d == NULL || !m->valid) return RPS3_EINVAL;
  if (!(d->stage & RPS3_STAGE_VEL))
    RPS3_ERROR(d, RPS3_ESTATE, "acceleration needs rps3_velocity first");
  if (!v3_finite(d->ddpose))
    RPS3_ERROR(d, RPS3_EINVAL, "ddpose (%g, %g, %g) is not finite",
               d->ddpose[0], d->ddpose[1], d->ddpose[2]);
  d->stage &= RPS3_STAGE_POS | RPS3_STAGE_VEL;
  if (pt == NULL) {
    rps3_pose_trig_eval(&own, d->pose, 1);
    pt = &own;
  }
  rps3_pose_twist_rate(m, pt, d->dpose, d->ddpose, d->omega, d->domega, d->ac);

  /* ball joints, then joint accelerations (src/links.h) */
  for (i = 0; i < 3; i++) {
    const double il = 1.0 / d->l[i];
    v3_sub(rho, d->b[i], d->c);
    RPS3_BALL_VEL(RPS3_V3C, RPS3_MS, d->omega, rho, d->vc, wr, bdd);
    RPS3_BALL_ACC(RPS3_V3C, RPS3_MS, d->omega, d->domega, rho, wr, d->ac, bdd);
    RPS3_LINK_ACC_L(v3_dot, d->phi[i], d->l[i], bdd, d->dtheta[i], d->ddl[i]);
    RPS3_LINK_ACC_THETA(v3_dot, d->dphi[i], il, bdd, d->dl[i], d->dtheta[i],
                        d->ddtheta[i]);
  }
  RPS3_CHECK_FINITE(d, d->domega, 3, "domega");
  RPS3_CHECK_FINITE(d, d->ac, 3, "ac");
  RPS3_CHECK_FINITE(d, d->ddl, 3, "ddl");
  RPS3_CHECK_FINITE(d, d->ddtheta, 3, "ddtheta");
  d->stage |= RPS3_STAGE_ACC;
  return RPS3_OK;
}

/* pose rates from omega and vc; alpha-dot is not defined at beta = 0 */
void rps3_pose_rates(rps3_data *d) {
  double ca = cos(d->pose[0]), sa = sin(d->pose[0]), sb = sin(d->pose[1]);
  double vb = 2.0 * sin(0.5 * d->pose[1]) * sin(0.5 * d->pose[1]);
  double ez_a[3] = {-sb * ca, -sb * sa, vb};
  d->dpose[1] = -d->omega[0] * sa + d->omega[1] * ca;
  if (vb > 1e-18) {
    d->dpose[0] = v3_dot(d->omega, ez_a) / (2.0 * vb);
  } else {
    d->dpose[0] = 0.0;
    d->warn |= RPS3_WARN_ALPHA;
  }
  d->dpose[2] = d->vc[2];
}

/* from dtheta (and l, dl, the positions): the ball joint velocities (28),
   the centre's (25), omega (26)-(28) and, when dpose, the pose rates (NaN
   otherwise); the stage */
int rps3_joint_velocity_from(const rps3_model *m, rps3_data *d, int dpose) {
  double bd[3][3], rho[3][3], u[3][3], a[3];
  int i;
  d->vc[0] = d->vc[1] = d->vc[2] = 0.0;
  for (i = 0; i < 3; i++) {
    RPS3_BALL_VEL_JOINTS(RPS3_V3C, d->phi[i], d->dphi[i], d->l[i], d->dl[i],
                         d->dtheta[i], bd[i]);
    v3_axpy(d->vc, d->vc, 1.0 / 3.0, bd[i]);
  }
  for (i = 0; i < 3; i++) {
    v3_sub(rho[i], d->b[i], d->c);
    v3_sub(u[i], bd[i], d->vc);
  }
  for (i = 0; i < 3; i++) a[i] = d->rot[i][2];
  rps3_omega_from_balls(d->omega, M3C(rho), M3C(u), a, m->r);
  RPS3_CHECK_FINITE(d, d->dtheta, 3, "dtheta");
  RPS3_CHECK_FINITE(d, d->vc, 3, "vc");
  RPS3_CHECK_FINITE(d, d->omega, 3, "omega");
  if (dpose) {
    rps3_pose_rates(d);
    RPS3_CHECK_FINITE(d, d->dpose, 3, "dpose");
  } else {
    d->dpose[0] = d->dpose[1] = d->dpose[2] = (double)NAN;
  }
  d->stage |= RPS3_STAGE_VEL;
  return RPS3_OK;
}

int rps3_joint_velocity(const rps3_model *m, rps3_data *d) {
  double Jl[3][3], Jt[3][3], x[3];
  int status;
  if (m == NULL || d == NULL || !m->valid) return RPS3_EINVAL;
  if (!(d->stage & RPS3_STAGE_POS))
    RPS3_ERROR(d, RPS3_ESTATE, "joint velocity needs positions");
  if (!v3_finite(d->dl))
    RPS3_ERROR(d, RPS3_EINVAL, "dl (%g, %g, %g) is not finite", d->dl[0],
               d->dl[1], d->dl[2]);
  d->stage &= RPS3_STAGE_POS;
  /* theta-dot from the constraint rates: Jt theta' = -Jl l' */
  rps3_constraint_jacobian(d, Jl, Jt);
  m3_mulv(x, M3C(Jl), d->dl);
  v3_scale(x, -1.0, x);
  status = solve_jt(m, d, Jt, x);
  if (status != RPS3_OK) return status;
  v3_copy(d->dtheta, x);
  return rps3_joint_velocity_from(m, d, 1);
}

/* the second derivative of (8)-(10), D.D'' + |D'|^2 = 0 for D = b_i - b_j,
   as Jt theta'' = x: x, and b_i'' without its theta'' part (known), from
   the pairs' D_k = b_k - b_(k+1), the links' directions, lengths and
   rates (ddl NULL: l'' = 0) */
void rps3_constraint_acc_rhs(const double D[3][3], const double phi[3][3],
                             const double dphi[3][3], const double l[3],
                             const double dl[3], const double dth[3],
                             const double ddl[3], double known[3][3],
                             double x[3]) {
  double bd[3][3];
  int i, k;
  for (i = 0; i < 3; i++) {
    /* b_i' and b_i'' at theta_i'' = 0 (src/links.h) */
    RPS3_BALL_VEL_JOINTS(RPS3_V3C, phi[i], dphi[i], l[i], dl[i], dth[i], bd[i]);
    RPS3_BALL_ACC_JOINTS(RPS3_V3C, phi[i], dphi[i], l[i], dl[i], dth[i],
                         ddl != NULL ? ddl[i] : 0.0, 0.0, known[i]);
  }
  for (k = 0; k < 3; k++) {
    int q = (k + 1) % 3;
    double Dd[3], Kd[3];
    v3_sub(Dd, bd[k], bd[q]);
    v3_sub(Kd, known[k], known[q]);
    x[k] = -2.0 * (v3_dot(Dd, Dd) + v3_dot(D[k], Kd));
  }
}

void rps3_joint_acc_rhs(const rps3_data *d, double known[3][3], double x[3]) {
  double D[3][3];
  int k;
  for (k = 0; k < 3; k++) v3_sub(D[k], d->b[k], d->b[(k + 1) % 3]);
  rps3_constraint_acc_rhs(M3C(D), M3C(d->phi), M3C(d->dphi), d->l, d->dl,
                          d->dtheta, d->ddl, known, x);
}

/* from ddtheta and known (rps3_joint_acc_rhs): the centre's acceleration
   and the platform's angular acceleration; the stage */
int rps3_joint_acc_from(const rps3_model *m, rps3_data *d,
                        const double known[3][3]) {
  double bdd[3][3], rho[3][3], u[3][3], a[3], t[3];
  int i;
  d->ac[0] = d->ac[1] = d->ac[2] = 0.0;
  for (i = 0; i < 3; i++) {
    v3_axpy(bdd[i], known[i], d->l[i] * d->ddtheta[i], d->dphi[i]);
    v3_axpy(d->ac, d->ac, 1.0 / 3.0, bdd[i]);
  }
  /* omega-dot x rho_i = b_i'' - ac - omega x (omega x rho_i) */
  for (i = 0; i < 3; i++) {
    v3_sub(rho[i], d->b[i], d->c);
    v3_cross(t, d->omega, rho[i]);
    v3_cross(t, d->omega, t);
    v3_sub(u[i], bdd[i], d->ac);
    v3_sub(u[i], u[i], t);
  }
  for (i = 0; i < 3; i++) a[i] = d->rot[i][2];
  rps3_omega_from_balls(d->domega, M3C(rho), M3C(u), a, m->r);
  RPS3_CHECK_FINITE(d, d->ddtheta, 3, "ddtheta");
  RPS3_CHECK_FINITE(d, d->ac, 3, "ac");
  RPS3_CHECK_FINITE(d, d->domega, 3, "domega");
  d->stage |= RPS3_STAGE_ACC;
  return RPS3_OK;
}

int rps3_joint_acceleration(const rps3_model *m, rps3_data *d) {
  double Jl[3][3], Jt[3][3], x[3], known[3][3];
  int status;
  if (m == NULL || d == NULL || !m->valid) return RPS3_EINVAL;
  if (!(d->stage & RPS3_STAGE_VEL))
    RPS3_ERROR(d, RPS3_ESTATE, "joint acceleration needs the velocities");
  if (!v3_finite(d->ddl))
    RPS3_ERROR(d, RPS3_EINVAL, "ddl (%g, %g, %g) is not finite", d->ddl[0],
               d->ddl[1], d->ddl[2]);
  d->stage &= RPS3_STAGE_POS | RPS3_STAGE_VEL;
  rps3_joint_acc_rhs(d, known, x);
  rps3_constraint_jacobian(d, Jl, Jt);
  status = solve_jt(m, d, Jt, x);
  if (status != RPS3_OK) return status;
  v3_copy(d->ddtheta, x);
  return rps3_joint_acc_from(m, d, M3C(known));
}

static void omega_paper(const rps3_model *m, const rps3_data *d,
                        double omega_body[3]) {
  /* literally (31)-(33) in the paper's normalized variables (lengths in
     units of R), with the errata's two corrections */
  const double rho = m->rho, h = 0.5 * RPS3_SQRT3;
  double L1 = d->l[0] / m->R, L2 = d->l[1] / m->R;
  double dL1 = d->dl[0] / m->R, dL2 = d->dl[1] / m->R;
  double c1 = cos(d->theta[0]), s1 = sin(d->theta[0]);
  double c2 = cos(d->theta[1]), s2 = sin(d->theta[1]);
  double t1 = d->dtheta[0], t2 = d->dtheta[1];
  double Xd = d->vc[0] / m->R, Yd = d->vc[1] / m->R, Zd = d->vc[2] / m->R;
  double o1 = d->rot[0][1], o2 = d->rot[1][1], o3 = d->rot[2][1];
  double a1 = d->rot[0][2], a2 = d->rot[1][2], a3 = d->rot[2][2];
  /* velocity of ball joint 2 relative to the centre, components (13) */
  double e1 = 0.5 * dL2 * c2 - 0.5 * L2 * s2 * t2 - Xd;
  double e2 = -h * dL2 * c2 + h * L2 * s2 * t2 - Yd;
  double e3 = dL2 * s2 + L2 * c2 * t2 - Zd;
  double wy, wx, wz;
  /* (32) */
  wy = -(1.0 / rho) * (a1 * (-dL1 * c1 + L1 * s1 * t1 - Xd) - a2 * Yd +
                       a3 * (dL1 * s1 + L1 * c1 * t1 - Zd));
  /* (31) */
  wx = (2.0 / RPS3_SQRT3) * (1.0 / rho) *
       (a1 * e1 + a2 * e2 + a3 * e3 - 0.5 * rho * wy);
  /* (33) */
  wz = -(2.0 / rho) * (o1 * e1 + o2 * e2 + o3 * e3);
  omega_body[0] = wx;
  omega_body[1] = wy;
  omega_body[2] = wz;
}

void rps3_omega_paper(const rps3_model *m, const rps3_data *d,
                      double omega_body[3]) {
  if (omega_body == NULL) return;
  if (m == NULL || d == NULL || !m->valid) {
    omega_body[0] = omega_body[1] = omega_body[2] = (double)NAN;
    return;
  }
  omega_paper(m, d, omega_body);
}
