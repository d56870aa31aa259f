/*
 * bodies.c - the loads of the general model's legs (rps3_leg), written
 * once for every formulation that reads them: the Lagrange route and the
 * Newton-Euler one (invdyn.c, invdyn_ne.c), the regressor (ident_std.c)
 * and the forward dynamics.
 *
 * Leg i turns about its pin axis w = axis_i (30), with dphi_i = w x phi_i,
 * at the rate theta_i'; its bodies' axes are e1 = phi_i, e2 = w, e3 = e1 x
 * e2.  A body's standard parameters (rps3.h, RPS3_NSTD: m, h = m c,
 * I about the frame's origin, body axes) give, with h and I turned into
 * the base frame (h_w = E h, I_w = E I E^T), the Newton-Euler wrench
 * about its origin O that moves with the body (rps3_body_wrench, which
 * the Newton-Euler route applies to a general platform too):
 *   f = m (a_O + g e_z) + omega' x h_w + omega x (omega x h_w),
 *   n = I_w omega' + omega x I_w omega + h_w x (a_O + g e_z),
 * omega = theta' w, omega' = theta'' w (w is fixed in the base).  Virtual
 * power puts it on the leg's coordinates: O moves by dO/dl and dO/dtheta,
 * the body turns by w per unit theta, so
 *   wl = dO/dl . f,  wt = dO/dtheta . f + w . n.
 * The cylinder's origin is the pin, fixed: wt = w . n alone, which is
 * I_w,ww theta'' + g w . (h_w x e_z) (w . (omega x I_w omega) = 0 for
 * omega along w).  The piston's is the ball joint b_i = P_i + l_i phi_i:
 * dO/dl = phi_i, dO/dtheta = l_i dphi_i, a_O = b_i''.  A point mass m at
 * d on the cylinder (h = (m d, 0, 0), I_yy = m d^2 + I_c) is the paper's
 * link ((21)-(22)); a massless piston adds nothing.
 *
 * The weight (g) and the inertia (a_O, theta', theta'') are separate
 * calls, the shares of RPS3_EFF_LINK_GRAVITY and RPS3_EFF_LINK_INERTIA.
 * Each is linear in the standard parameters and written as its rows (the
 * load of each unit parameter): the forces multiply them by the
 * parameters, the regressor (ident_std.c) takes them as its columns.
 */
#include "internal.h"
#include "linalg.h"

/* the body's inertia about its origin as a 3 x 3 in body axes, from its
   standard parameters (the certificate's) */
static void inertia_of(const double p[10], double I[3][3]) {
  I[0][0] = p[4];
  I[0][1] = I[1][0] = p[5];
  I[0][2] = I[2][0] = p[6];
  I[1][1] = p[7];
  I[1][2] = I[2][1] = p[8];
  I[2][2] = p[9];
}

/* x = E v (body axes to the base frame), E's columns e[0..2] */
static void to_base(const double e[3][3], const double v[3], double x[3]) {
  int k;
  for (k = 0; k < 3; k++)
    x[k] = e[0][k] * v[0] + e[1][k] * v[1] + e[2][k] * v[2];
}

/* the pairs (j, k) of the inertia's six parameters Ixx, Ixy, Ixz, Iyy,
   Iyz, Izz */
static const int IJ[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};

void rps3_body_wrench_rows(const double e[3][3], const double om[3],
                           const double dom[3], const double a[3],
                           double Wf[3][10], double Wn[3][10]) {
  double t[3], u[3], x[3], y[3];
  int j, k, r;
  for (r = 0; r < 3; r++) {
    /* the mass: f = m a */
    Wf[r][0] = a[r];
    Wn[r][0] = 0.0;
  }
  for (j = 0; j < 3; j++) {
    /* h = E hb: f = omega' x h + omega x (omega x h), n = h x a */
    v3_cross(t, dom, e[j]);
    v3_cross(u, om, e[j]);
    v3_cross(x, om, u);
    v3_cross(y, e[j], a);
    for (r = 0; r < 3; r++) {
      Wf[r][1 + j] = t[r] + x[r];
      Wn[r][1 + j] = y[r];
    }
  }
  for (k = 0; k < 6; k++) {
    /* I_w = E I E^T: a parameter at (p, q) and (q, p) puts e_p (e_q . x)
       + e_q (e_p . x) into I_w x; n = I_w omega' + omega x I_w omega */
    const int p = IJ[k][0], q = IJ[k][1];
    double Io[3], Id[3];
    v3_scale(Io, v3_dot(e[q], om), e[p]);
    v3_scale(Id, v3_dot(e[q], dom), e[p]);
    if (p != q) {
      v3_axpy(Io, Io, v3_dot(e[p], om), e[q]);
      v3_axpy(Id, Id, v3_dot(e[p], dom), e[q]);
    }
    v3_cross(t, om, Io);
    for (r = 0; r < 3; r++) {
      Wf[r][4 + k] = 0.0;
      Wn[r][4 + k] = Id[r] + t[r];
    }
  }
}

void rps3_body_wrench(const double p[10], const double e[3][3],
                      const double om[3], const double dom[3],
                      const double a[3], double f[3], double n[3]) {
  double Wf[3][10], Wn[3][10];
  int r, k;
  rps3_body_wrench_rows(e, om, dom, a, Wf, Wn);
  for (r = 0; r < 3; r++) {
    f[r] = n[r] = 0.0;
    for (k = 0; k < 10; k++) {
      f[r] += Wf[r][k] * p[k];
      n[r] += Wn[r][k] * p[k];
    }
  }
}

void rps3_leg_rows(const rps3_model *m, int i, const double phi[3],
                   const double dphi[3], double l, double dth, double ddth,
                   const double bdd[3], double g, double WL[20],
                   double WT[20]) {
  const double *w = m->axis[i];
  double e[3][3], a[3], om[3], dom[3], Wf[3][10], Wn[3][10];
  int k;
  v3_copy(e[0], phi);
  v3_copy(e[1], w);
  v3_cross(e[2], phi, w);
  v3_scale(om, dth, w);
  v3_scale(dom, ddth, w);
  /* the cylinder: origin the pin, at rest; wt = w . n alone */
  a[0] = a[1] = 0.0;
  a[2] = g;
  rps3_body_wrench_rows(M3C(e), om, dom, a, Wf, Wn);
  for (k = 0; k < 10; k++) {
    WL[k] = 0.0;
    WT[k] = w[0] * Wn[0][k] + w[1] * Wn[1][k] + w[2] * Wn[2][k];
  }
  /* the piston: origin the ball joint, moved by phi and l dphi */
  if (bdd != NULL) v3_copy(a, bdd);
  else
    a[0] = a[1] = a[2] = 0.0;
  a[2] += g;
  rps3_body_wrench_rows(M3C(e), om, dom, a, Wf, Wn);
  for (k = 0; k < 10; k++) {
    const double fk[3] = {Wf[0][k], Wf[1][k], Wf[2][k]};
    WL[10 + k] = v3_dot(phi, fk);
    WT[10 + k] = l * v3_dot(dphi, fk) + w[0] * Wn[0][k] + w[1] * Wn[1][k] +
                 w[2] * Wn[2][k];
  }
}

void rps3_leg_loads(const rps3_model *m, int i, const double phi[3],
                    const double dphi[3], double l, double dth, double ddth,
                    const double bdd[3], double g, double *wl, double *wt) {
  const double *pc = m->std[1 + 2 * i], *pp = m->std[2 + 2 * i];
  double WL[20], WT[20];
  int k;
  rps3_leg_rows(m, i, phi, dphi, l, dth, ddth, bdd, g, WL, WT);
  *wl = *wt = 0.0;
  for (k = 0; k < 10; k++) {
    *wl += WL[10 + k] * pp[k];
    *wt += WT[k] * pc[k] + WT[10 + k] * pp[k];
  }
}

/*
 * The energy-rate certificate's terms of a general body (invdyn.c,
 * certify), from its motion alone, not from its wrench: with its centre of
 * mass G = O + E c (c = h / m) and its inertia about G by parallel axes,
 * I_G = I - m (|c|^2 1 - c c^T),
 *   dT/dt = m v_G . a_G + omega . I_G,w omega',  dP/dt = m g v_G,z,
 * v_G = v_O + omega x E c, a_G = a_O + omega' x E c + omega x (omega x E
 * c).  *pT, *pP the two rates, *s the magnitudes of their terms.
 */
void rps3_body_power(const double p[10], const double e[3][3],
                     const double vO[3], const double aO[3],
                     const double om[3], const double dom[3], double g,
                     double *pT, double *pP, double *s) {
  double I[3][3], c[3], cw[3], vG[3], aG[3], t[3], ob[3], db[3], tt, tr;
  int j, k;
  const double m = p[0];
  inertia_of(p, I);
  for (k = 0; k < 3; k++) c[k] = m > 0.0 ? p[1 + k] / m : 0.0;
  /* about the centre of mass */
  for (j = 0; j < 3; j++)
    for (k = 0; k < 3; k++)
      I[j][k] -= m * ((j == k ? v3_dot(c, c) : 0.0) - c[j] * c[k]);
  to_base(e, c, cw);
  v3_cross(t, om, cw);
  v3_axpy(vG, vO, 1.0, t);
  v3_cross(aG, dom, cw);
  v3_axpy(aG, aG, 1.0, aO);
  v3_cross(t, om, t);
  v3_axpy(aG, aG, 1.0, t);
  for (k = 0; k < 3; k++) {
    ob[k] = v3_dot(e[k], om);
    db[k] = v3_dot(e[k], dom);
  }
  tr = 0.0;
  for (j = 0; j < 3; j++)
    for (k = 0; k < 3; k++) tr += ob[j] * I[j][k] * db[k];
  tt = m * v3_dot(vG, aG);
  *pT = tt + tr;
  *pP = m * g * vG[2];
  *s = fabs(tt) + fabs(tr) + fabs(*pP);
}
