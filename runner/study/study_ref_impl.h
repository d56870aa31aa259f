/*
 * study_ref_impl.h - the body of study_ref.c, included once per precision
 * with REAL (the floating type), S(name) (a suffixed name), RF(f) (the
 * math function f of REAL) and REF_FORCES (the public name) defined.  No
 * include guard: it is meant to be included twice.
 *
 * Kane's equations in the pose coordinates q = (alpha, beta, z_c): the
 * actuators do virtual work F_i dl_i, so for every j
 *   sum_i F_i dl_i/dq_j = sum over bodies of (momentum rate + weight)
 *                          . (partial velocity of q'_j)  - pin torques,
 * a 3 x 3 system in F with no multipliers and no link coordinates.  Every
 * position is written from the pose; its time derivatives and partials in q
 * come from jets (value, first, second derivative) pushed through the same
 * code, so nothing is differentiated by hand.
 */

typedef struct {
  REAL v, d, dd; /* value, first and second derivative along the seed */
} S(jet);

static S(jet) S(jk)(REAL v) {
  S(jet) r = {v, 0, 0};
  return r;
}

static S(jet) S(jadd)(S(jet) a, S(jet) b) {
  S(jet) r = {a.v + b.v, a.d + b.d, a.dd + b.dd};
  return r;
}

static S(jet) S(jsub)(S(jet) a, S(jet) b) {
  S(jet) r = {a.v - b.v, a.d - b.d, a.dd - b.dd};
  return r;
}

static S(jet) S(jscale)(REAL s, S(jet) a) {
  S(jet) r = {s * a.v, s * a.d, s * a.dd};
  return r;
}

static S(jet) S(jmul)(S(jet) a, S(jet) b) {
  S(jet) r = {a.v * b.v, a.d * b.v + a.v * b.d,
              a.dd * b.v + 2 * a.d * b.d + a.v * b.dd};
  return r;
}

static S(jet) S(jdiv)(S(jet) a, S(jet) b) {
  S(jet) r;
  r.v = a.v / b.v;
  r.d = (a.d - r.v * b.d) / b.v;
  r.dd = (a.dd - 2 * r.d * b.d - r.v * b.dd) / b.v;
  return r;
}

static S(jet) S(jsin)(S(jet) a) {
  REAL s = RF(sin)(a.v), c = RF(cos)(a.v);
  S(jet) r = {s, c * a.d, c * a.dd - s * a.d * a.d};
  return r;
}

static S(jet) S(jcos)(S(jet) a) {
  REAL s = RF(sin)(a.v), c = RF(cos)(a.v);
  S(jet) r = {c, -s * a.d, -s * a.dd - c * a.d * a.d};
  return r;
}

static S(jet) S(jsqrt)(S(jet) a) {
  REAL s = RF(sqrt)(a.v);
  S(jet) r = {s, a.d / (2 * s), a.dd / (2 * s) - a.d * a.d / (4 * s * s * s)};
  return r;
}

/* atan2(y, x): d = (x y' - y x') / (x^2 + y^2) */
static S(jet) S(jatan2)(S(jet) y, S(jet) x) {
  REAL D = x.v * x.v + y.v * y.v, N = x.v * y.d - y.v * x.d;
  REAL Nd = x.v * y.dd - y.v * x.dd, Dd = 2 * (x.v * x.d + y.v * y.d);
  S(jet) r = {RF(atan2)(y.v, x.v), N / D, (Nd * D - N * Dd) / (D * D)};
  return r;
}

/* positions of every body from the pose */
typedef struct {
  S(jet) rot[3][3]; /* platform axes as columns */
  S(jet) c[3];      /* platform centre */
  S(jet) p[3];      /* payload centre of mass */
  S(jet) l[3];      /* link lengths */
  S(jet) th[3];     /* link angles to the base plane */
  S(jet) x[3][3];   /* link centroids */
} S(kin);

static int S(kinematics)(const rps3_model *m, const S(jet) q[3], S(kin) *k) {
  REAL R = (REAL)m->R, r = (REAL)m->rho * R, d = (REAL)m->d;
  REAL pi = RF(atan2)(0, -1), cp[3], sp[3];
  S(jet) T[3][3], w[3][3], rhs[2];
  S(jet) ca = S(jcos)(q[0]), sa = S(jsin)(q[0]);
  S(jet) cb = S(jcos)(q[1]), sb = S(jsin)(q[1]);
  S(jet) zero = S(jk)(0), one = S(jk)(1);
  /* rot = Rz(alpha) Ry(beta) Rz(-alpha), the spin gamma = -alpha of (2) */
  S(jet) A[3][3] = {
      {ca, S(jscale)(-1, sa), zero}, {sa, ca, zero}, {zero, zero, one}};
  S(jet) B[3][3] = {
      {cb, zero, sb}, {zero, one, zero}, {S(jscale)(-1, sb), zero, cb}};
  REAL det;
  int i, j, n;
  for (i = 0; i < 3; i++) {
    cp[i] = RF(cos)(2 * pi * (REAL)i / 3);
    sp[i] = RF(sin)(2 * pi * (REAL)i / 3);
  }
  for (i = 0; i < 3; i++)
    for (j = 0; j < 3; j++) {
      T[i][j] = zero;
      for (n = 0; n < 3; n++)
        T[i][j] = S(jadd)(T[i][j], S(jmul)(A[i][n], B[n][j]));
    }
  /* Rz(-alpha) = Rz(alpha)^T */
  for (i = 0; i < 3; i++)
    for (j = 0; j < 3; j++) {
      k->rot[i][j] = zero;
      for (n = 0; n < 3; n++)
        k->rot[i][j] = S(jadd)(k->rot[i][j], S(jmul)(T[i][n], A[j][n]));
    }
  /* platform radius vectors r_i = r (cos psi_i, sin psi_i, 0), world */
  for (i = 0; i < 3; i++)
    for (j = 0; j < 3; j++)
      w[i][j] = S(jadd)(S(jscale)(r * cp[i], k->rot[j][0]),
                        S(jscale)(r * sp[i], k->rot[j][1]));
  /* the centre: ball joints 1 and 2 each in their pin's vertical plane,
     (c + w_i) . (-sin psi_i, cos psi_i, 0) = 0, linear in (x_c, y_c) */
  for (i = 0; i < 2; i++)
    rhs[i] = S(jsub)(S(jscale)(sp[i], w[i][0]), S(jscale)(cp[i], w[i][1]));
  det = -sp[0] * cp[1] + cp[0] * sp[1];
  k->c[0] = S(jscale)(
      1 / det, S(jsub)(S(jscale)(cp[1], rhs[0]), S(jscale)(cp[0], rhs[1])));
  k->c[1] = S(jscale)(
      1 / det, S(jsub)(S(jscale)(-sp[0], rhs[1]), S(jscale)(-sp[1], rhs[0])));
  k->c[2] = q[2];
  /* links: from pin P_i to ball joint b_i = c + w_i */
  for (i = 0; i < 3; i++) {
    S(jet) v[3], radial;
    REAL P[3];
    P[0] = R * cp[i];
    P[1] = R * sp[i];
    P[2] = 0;
    for (j = 0; j < 3; j++)
      v[j] = S(jsub)(S(jadd)(k->c[j], w[i][j]), S(jk)(P[j]));
    k->l[i] =
        S(jsqrt)(S(jadd)(S(jadd)(S(jmul)(v[0], v[0]), S(jmul)(v[1], v[1])),
                         S(jmul)(v[2], v[2])));
    if (!(v[2].v > 0) || !(k->l[i].v > 0)) return -1;
    radial = S(jadd)(S(jscale)(cp[i], v[0]), S(jscale)(sp[i], v[1]));
    k->th[i] = S(jatan2)(v[2], S(jscale)(-1, radial));
    for (j = 0; j < 3; j++)
      k->x[i][j] = S(jadd)(S(jk)(P[j]),
                           S(jmul)(S(jscale)(d, v[j]), S(jdiv)(one, k->l[i])));
  }
  for (j = 0; j < 3; j++) {
    k->p[j] = k->c[j];
    for (n = 0; n < 3; n++)
      k->p[j] =
          S(jadd)(k->p[j], S(jscale)((REAL)m->payload.com[n], k->rot[j][n]));
  }
  return 0;
}

/* axial vector of the skew part of S */
static void S(vee)(REAL out[3], REAL Sm[3][3]) {
  out[0] = (Sm[2][1] - Sm[1][2]) / 2;
  out[1] = (Sm[0][2] - Sm[2][0]) / 2;
  out[2] = (Sm[1][0] - Sm[0][1]) / 2;
}

/* X Y^T with X, Y read from field f of the rot jets (0 v, 1 d, 2 dd) */
static REAL S(field)(S(jet) a, int f) {
  return f == 0 ? a.v : f == 1 ? a.d : a.dd;
}

static void S(rot_vee)(REAL out[3], S(jet) X[3][3], int fx, S(jet) Y[3][3]) {
  REAL M3[3][3];
  int a, b, c;
  for (a = 0; a < 3; a++)
    for (b = 0; b < 3; b++) {
      M3[a][b] = 0;
      for (c = 0; c < 3; c++) M3[a][b] += S(field)(X[a][c], fx) * Y[b][c].v;
    }
  S(vee)(out, M3);
}

/* I w' + w x I w with I = rot diag(I) rot^T, world axes */
static void S(euler)(REAL out[3], S(jet) rot[3][3], const REAL I[3],
                     const REAL w[3], const REAL dw[3]) {
  REAL Iw[3], Idw[3], t[3], s[3];
  int a, b;
  for (b = 0; b < 3; b++) {
    t[b] = s[b] = 0;
    for (a = 0; a < 3; a++) {
      t[b] += rot[a][b].v * w[a];
      s[b] += rot[a][b].v * dw[a];
    }
    t[b] *= I[b];
    s[b] *= I[b];
  }
  for (a = 0; a < 3; a++) {
    Iw[a] = Idw[a] = 0;
    for (b = 0; b < 3; b++) {
      Iw[a] += rot[a][b].v * t[b];
      Idw[a] += rot[a][b].v * s[b];
    }
  }
  out[0] = Idw[0] + w[1] * Iw[2] - w[2] * Iw[1];
  out[1] = Idw[1] + w[2] * Iw[0] - w[0] * Iw[2];
  out[2] = Idw[2] + w[0] * Iw[1] - w[1] * Iw[0];
}

static REAL S(dot)(const REAL a[3], const REAL b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* A x = b for the augmented [A | b] by Gaussian elimination with partial
   pivoting, x into column 3; 0, or -1 when A is singular */
static int S(solve3)(REAL A[3][4]) {
  int i, j, n;
  for (n = 0; n < 3; n++) {
    int piv = n;
    for (i = n + 1; i < 3; i++)
      if (RF(fabs)(A[i][n]) > RF(fabs)(A[piv][n])) piv = i;
    if (A[piv][n] == 0) return -1;
    for (j = 0; piv != n && j < 4; j++) {
      REAL t = A[n][j];
      A[n][j] = A[piv][j];
      A[piv][j] = t;
    }
    for (i = n + 1; i < 3; i++) {
      REAL f = A[i][n] / A[n][n];
      for (j = n; j < 4; j++) A[i][j] -= f * A[n][j];
    }
  }
  for (n = 2; n >= 0; n--) {
    REAL s = A[n][3];
    for (j = n + 1; j < 3; j++) s -= A[n][j] * A[j][3];
    A[n][3] = s / A[n][n];
  }
  return 0;
}

int REF_FORCES(const rps3_model *m, int eff, const double pose[3],
               const double dpose[3], const double ddpose[3], double F[3]) {
  S(kin) kt, kp[3];
  S(jet) q[3];
  REAL w[3], dw[3], pw[3][3], A[3][4], g = (REAL)m->g;
  REAL M = (REAL)m->M, ml = (REAL)m->m, r = (REAL)m->rho * (REAL)m->R;
  REAL Ip[3], Ipl[3], ep[3], epl[3];
  int i, j, n;
  /* the motion (seed: the rates) and the partials (seed: e_j) */
  for (i = 0; i < 3; i++) {
    q[i].v = (REAL)pose[i];
    q[i].d = (REAL)dpose[i];
    q[i].dd = (REAL)ddpose[i];
  }
  if (S(kinematics)(m, q, &kt) != 0) return -1;
  for (j = 0; j < 3; j++) {
    for (i = 0; i < 3; i++) {
      q[i].d = (i == j);
      q[i].dd = 0;
    }
    if (S(kinematics)(m, q, &kp[j]) != 0) return -1;
  }
  /* omega = vee(rot' rot^T), omega' = vee(rot'' rot^T) (rot' rot'^T is
     symmetric), partial angular velocities vee(d rot / dq_j rot^T) */
  S(rot_vee)(w, kt.rot, 1, kt.rot);
  S(rot_vee)(dw, kt.rot, 2, kt.rot);
  for (j = 0; j < 3; j++) S(rot_vee)(pw[j], kp[j].rot, 1, kp[j].rot);
  /* the uniform disc of (21) and the payload's principal moments */
  Ip[0] = Ip[1] = M * r * r / 4;
  Ip[2] = M * r * r / 2;
  for (i = 0; i < 3; i++) Ipl[i] = (REAL)m->payload.inertia[i];
  S(euler)(ep, kt.rot, Ip, w, dw);
  S(euler)(epl, kt.rot, Ipl, w, dw);
  for (j = 0; j < 3; j++) {
    REAL s = 0, dc[3], dp[3], cdd[3], pdd[3];
    for (n = 0; n < 3; n++) {
      dc[n] = kp[j].c[n].d;
      dp[n] = kp[j].p[n].d;
      cdd[n] = kt.c[n].dd;
      pdd[n] = kt.p[n].dd;
    }
    if (eff & RPS3_EFF_PLATFORM_GRAVITY) s += M * g * dc[2];
    if (eff & RPS3_EFF_PLATFORM_INERTIA)
      s += M * S(dot)(cdd, dc) + S(dot)(ep, pw[j]);
    if (eff & RPS3_EFF_PAYLOAD) {
      REAL mp = (REAL)m->payload.mass;
      s += mp * (S(dot)(pdd, dp) + g * dp[2]) + S(dot)(epl, pw[j]);
    }
    for (i = 0; i < 3; i++) {
      REAL dth = kp[j].th[i].d, rate = kt.th[i].d;
      if (eff & RPS3_EFF_LINK_GRAVITY) s += ml * g * kp[j].x[i][2].d;
      if (eff & RPS3_EFF_LINK_INERTIA) {
        for (n = 0; n < 3; n++) s += ml * kt.x[i][n].dd * kp[j].x[i][n].d;
        s += (REAL)m->link_Ic * kt.th[i].dd * dth;
      }
      if (eff & RPS3_EFF_PIN_FRICTION) {
        /* the pin friction law of rps3.h: sign, or tanh(rate / vreg) */
        REAL vreg = (REAL)m->friction.vreg;
        REAL sg =
            vreg > 0 ? RF(tanh)(rate / vreg) : (REAL)((rate > 0) - (rate < 0));
        REAL tau = -((REAL)m->friction.viscous * rate +
                     (REAL)m->friction.coulomb * sg);
        s -= tau * dth;
      }
      A[j][i] = kp[j].l[i].d; /* virtual work of F_i: dl_i / dq_j */
    }
    A[j][3] = s;
  }
  if (S(solve3)(A) != 0) return -1;
  for (i = 0; i < 3; i++) F[i] = (double)A[i][3];
  return 0;
}
