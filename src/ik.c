/*
 * ik.c - inverse kinematics, eqs. (2)-(7) and (39), and the geometry shared
 * with forward kinematics: ball joints from (l, theta) (12)-(14), the
 * platform frame from the ball joints (11), (18)-(20), and the constraint
 * Jacobian of (8)-(10).
 */
#include "internal.h"
#include "linalg.h"
#include "links.h"

/* (29): the directions of link i from cos and sin of theta_i and the
   radial unit vector u of pin i (src/links.h) */
static void set_link_dir(rps3_data *d, int i, const double u[3], double ct,
                         double st) {
  RPS3_LINK_PHI(RPS3_V3C, u[0], u[1], ct, st, d->phi[i]);
  RPS3_LINK_DPHI(RPS3_V3C, u[0], u[1], ct, st, d->dphi[i]);
}

void rps3_pose_frame(const rps3_model *m, const rps3_pose_trig *t, double z,
                     double rot[3][3], double c[3]) {
  const double ca = t->ca, sa = t->sa, sb = t->sb, vb = t->vb;
  /* orientation Rz(alpha) Ry(beta) Rz(-alpha), spin gamma = -alpha (2) */
  rot[0][0] = 1.0 - vb * ca * ca;
  rot[0][1] = -vb * ca * sa;
  rot[0][2] = sb * ca;
  rot[1][0] = -vb * ca * sa;
  rot[1][1] = 1.0 - vb * sa * sa;
  rot[1][2] = sb * sa;
  rot[2][0] = -sb * ca;
  rot[2][1] = -sb * sa;
  rot[2][2] = t->cb;
  /* centre (3)-(4): the only x, y the three pin planes allow */
  c[0] = -0.5 * m->r * vb * t->C;
  c[1] = 0.5 * m->r * vb * t->S;
  c[2] = z;
}

int rps3_ik(const rps3_model *m, rps3_data *d) {
  rps3_pose_trig t;
  return rps3_ik_with(m, d, &t, RPS3_IK_THETA, NULL);
}

int rps3_ik_with(const rps3_model *m, rps3_data *d, rps3_pose_trig *t,
                 int theta, rps3_cjac *J) {
  rps3_cjac own;
  int i;
  if (m == NULL || d == NULL || !m->valid) return RPS3_EINVAL;
  d->stage = 0;
  d->warn = 0;
  if (!v3_finite(d->pose))
    RPS3_ERROR(d, RPS3_EINVAL, "pose (%g, %g, %g) is not finite", d->pose[0],
               d->pose[1], d->pose[2]);
  rps3_pose_trig_eval(t, d->pose, 1);
  rps3_pose_frame(m, t, d->pose[2], d->rot, d->c);

  /* ball joints (15)-(17), link lengths (5)-(7) and angles (39), the
     formulas of src/links.h; the model's body[i][2] = pin[i][2] = 0 */
  for (i = 0; i < 3; i++) {
    double rx[3], ry[3], rho[3], v[3], l2, radial, vz, ct, st;
    int q;
    for (q = 0; q < 3; q++) {
      rx[q] = d->rot[q][0];
      ry[q] = d->rot[q][1];
    }
    RPS3_LINK_BALL(RPS3_V3C, RPS3_MA, m->body[i][0], m->body[i][1], rx, ry,
                   d->c, rho, d->b[i]);
    RPS3_LINK_VEC(RPS3_V3C, v3_dot, RPS3_MA, d->b[i], m->pin[i][0],
                  m->pin[i][1], m->radial[i][0], m->radial[i][1], v, l2,
                  d->l[i], radial);
    vz = v[2];
    if (!RPS3_LINK_REACHABLE(d->l[i], vz))
      RPS3_ERROR(d, RPS3_EREACH,
                 "link %d: length %.6g m, ball joint height %.6g m (needs "
                 "length > 0 and height > 0) at pose (%.6g, %.6g, %.6g)",
                 i + 1, d->l[i], vz, d->pose[0], d->pose[1], d->pose[2]);
    if (theta == RPS3_IK_NO_THETA) continue; /* the solve takes over */
    /* (39) with atan2, so that theta > pi/2 is found too; the link
       directions (29) from the same two components, without more trig.
       The forces need only the directions: without RPS3_OUT_THETA, no atan2 */
    d->theta[i] = (theta == RPS3_IK_THETA) ? RPS3_LINK_THETA(atan2, radial, vz)
                                           : (double)NAN;
    RPS3_LINK_COS_SIN(radial, vz, 1.0 / d->l[i], ct, st);
    set_link_dir(d, i, m->radial[i], ct, st);
  }
  /* finite pose, yet a height of 1e200 m overflows |b_i - P_i| */
  RPS3_CHECK_FINITE(d, d->c, 3, "c");
  RPS3_CHECK_FINITE(d, d->rot, 9, "rot");
  RPS3_CHECK_FINITE(d, d->b, 9, "b");
  RPS3_CHECK_FINITE(d, d->l, 3, "l");
  if (theta == RPS3_IK_NO_THETA) return RPS3_OK;
  /* the mode needs only the link directions, which RPS3_IK_DIRS also has;
     the positions are final: the Jacobian for the later stages */
  if (J == NULL) J = &own;
  rps3_cjac_eval(d, J);
  d->mode = rps3_mode_of_jac(M3C(J->Jt));
  d->have_theta = (theta == RPS3_IK_THETA);
  d->stage = RPS3_STAGE_POS;
  return RPS3_OK;
}

void rps3_link_dirs(const rps3_model *m, rps3_data *d) {
  int i;
  for (i = 0; i < 3; i++)
    set_link_dir(d, i, m->radial[i], cos(d->theta[i]), sin(d->theta[i]));
}

void rps3_links_from_joints(const rps3_model *m, rps3_data *d) {
  int i;
  rps3_link_dirs(m, d);
  for (i = 0; i < 3; i++) /* (12)-(14) */
    RPS3_BALL_AT(RPS3_V3C, m->pin[i], d->l[i], d->phi[i], d->b[i]);
}

void rps3_links_from_trig(const rps3_model *m, rps3_data *d, const double c[3],
                          const double s[3]) {
  int i;
  for (i = 0; i < 3; i++) {
    set_link_dir(d, i, m->radial[i], c[i], s[i]);
    RPS3_BALL_AT(RPS3_V3C, m->pin[i], d->l[i], d->phi[i], d->b[i]);
  }
}

void rps3_frame_from_balls(const rps3_model *m, rps3_data *d) {
  double n[3], o[3], a[3];
  int k;
  for (k = 0; k < 3; k++) {
    /* centre (11) */
    d->c[k] = (d->b[0][k] + d->b[1][k] + d->b[2][k]) / 3.0;
    /* n from ball 1 (18), o from balls 2 and 3 (19) */
    n[k] = (d->b[0][k] - d->c[k]) / m->r;
    o[k] = (d->b[1][k] - d->b[2][k]) / (RPS3_SQRT3 * m->r);
  }
  v3_cross(a, n, o); /* (20) */
  for (k = 0; k < 3; k++) {
    d->rot[k][0] = n[k];
    d->rot[k][1] = o[k];
    d->rot[k][2] = a[k];
  }
}

void rps3_constraint_jacobian(const rps3_data *d, double Jl[3][3],
                              double Jt[3][3]) {
  int k;
  for (k = 0; k < 3; k++) {
    /* the pairs (1,2), (2,3), (3,1) of (8)-(10), src/cjac.h */
    int i = k, j = (k + 1) % 3, q;
    double D[3];
    v3_sub(D, d->b[i], d->b[j]);
    for (q = 0; q < 3; q++) Jl[k][q] = Jt[k][q] = 0.0;
    RPS3_CJAC_ROW(v3_dot, D, d->phi[i], d->dphi[i], d->l[i], d->phi[j],
                  d->dphi[j], d->l[j], Jl[k][i], Jl[k][j], Jt[k][i], Jt[k][j]);
  }
}

void rps3_cjac_eval(const rps3_data *d, rps3_cjac *J) {
  rps3_constraint_jacobian(d, J->Jl, J->Jt);
  J->factored = 0;
}

void rps3_cjac_factor(rps3_cjac *J) {
  int i, k;
  if (J->factored) return;
  for (i = 0; i < 3; i++)
    for (k = 0; k < 3; k++) J->A[3 * i + k] = J->LU[3 * i + k] = J->Jt[k][i];
  J->sing = (rps3_lu_factor(3, J->LU, J->perm) != 0);
  J->cond = J->sing ? HUGE_VAL
                    : rps3_lu3_inverse_cond1(J->A, J->LU, J->perm, J->Ainv);
  J->factored = 1;
}

int rps3_mode_of_jac(const double J[3][3]) {
  double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
               J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
               J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
  return (det > 0.0) - (det < 0.0);
}

int rps3_mode_of(const rps3_data *d) {
  double Jl[3][3], J[3][3];
  rps3_constraint_jacobian(d, Jl, J);
  return rps3_mode_of_jac(M3C(J));
}

void rps3_transform(const rps3_data *d, double T[4][4]) {
  int i, j;
  if (T == NULL) return;
  for (i = 0; i < 3; i++) {
    for (j = 0; j < 3; j++) T[i][j] = d != NULL ? d->rot[i][j] : (double)NAN;
    T[i][3] = d != NULL ? d->c[i] : (double)NAN;
    T[3][i] = 0.0;
  }
  T[3][3] = 1.0;
}
