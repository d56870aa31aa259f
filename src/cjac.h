/*
 * cjac.h - the constraints (8)-(10) and their Jacobian, written once.
 *
 * The pair k = (i, j), j = i + 1 (mod 3), of (8)-(10) is
 *   f_k = |b_i - b_j|^2 - 3 r^2,
 * with b_i the ball joint of link i.  Two forms, each the one source of
 * the stages that use it; tests/test_jacobian.c holds each to differences
 * of f and the two to each other:
 *
 *   - from the positions (RPS3_CJAC_ROW): d b_i / d l_i = phi_i and
 *     d b_i / d theta_i = l_i dphi_i (12)-(14), (29), so with D = b_i - b_j
 *       df_k/dl_i = 2 D . phi_i,          df_k/dl_j = -2 D . phi_j,
 *       df_k/dtheta_i = 2 l_i D . dphi_i,  df_k/dtheta_j = -2 l_j D . dphi_j.
 *     A macro over the 3-vector type (its dot product DOT): the scalar
 *     stages (src/ik.c, double[3]) and the vectorised batch kernel
 *     (src/batch_kmech.h, kv3 by value) compile the same text;
 *
 *   - in the links' planes (rps3_plane_pair), from l and the cosine and
 *     sine of theta alone, for the solvers that iterate on theta and form
 *     no positions (the theta solve of src/fk.c in units of R, the forward
 *     dynamics of src/fwddyn_plane.h in metres): b_i = h_i u_i + Z_i e_z
 *     with h_i = R - l_i cos theta_i, Z_i = l_i sin theta_i, u_i . u_j =
 *     -1/2, so
 *       f_k = h_i^2 + h_j^2 + h_i h_j + (Z_i - Z_j)^2 - 3 r^2,
 *     and with A = 2 h_i + h_j, B = 2 h_j + h_i, E = 2 (Z_i - Z_j)
 *       df_k/dtheta_i = l_i (A sin_i + E cos_i),
 *       df_k/dtheta_j = l_j (B sin_j - E cos_j),
 *       df_k/dl_i = E sin_i - A cos_i,  df_k/dl_j = -B cos_j - E sin_j.
 *
 * Not installed.
 */
#ifndef RPS3_CJAC_H
#define RPS3_CJAC_H

/* row k of the constraint Jacobian from D = b_i - b_j and links i, j
   (phi, dphi, l): lc = df_k/dl_i, le = df_k/dl_j, ta = df_k/dtheta_i,
   tb = df_k/dtheta_j; DOT(a, b) is the dot product of the vector type */
/* clang-format would take (l_i) * DOT(...) for a cast */
/* clang-format off */
#define RPS3_CJAC_ROW(DOT, D, phi_i, dphi_i, l_i, phi_j, dphi_j, l_j, lc,   \
                      le, ta, tb)                                           \
  do {                                                                      \
    (lc) = 2.0 * DOT(D, phi_i);                                             \
    (le) = -2.0 * DOT(D, phi_j);                                            \
    (ta) = 2.0 * (l_i) * DOT(D, dphi_i);                                    \
    (tb) = -2.0 * (l_j) * DOT(D, dphi_j);                                   \
  } while (0)
/* clang-format on */

/* pair k in the links' planes: f_k, A, B, E and the two entries of its
   row of df/dtheta (at = df_k/dtheta_i, bt = df_k/dtheta_j), from h, Z,
   l, cos and sin theta of links i and j and r3 = 3 r^2, in one unit of
   length throughout */
typedef struct {
  double f, A, B, E, at, bt;
} rps3_plane_pair;

static inline rps3_plane_pair rps3_plane_pair_eval(
    double hi, double hj, double Zi, double Zj, double li, double lj, double ci,
    double si, double cj, double sj, double r3) {
  rps3_plane_pair q;
  q.A = 2.0 * hi + hj;
  q.B = 2.0 * hj + hi;
  q.E = 2.0 * (Zi - Zj);
  q.f = hi * hi + hj * hj + hi * hj + 0.25 * q.E * q.E - r3;
  q.at = li * (q.A * si + q.E * ci);
  q.bt = lj * (q.B * sj - q.E * cj);
  return q;
}

/* the pair's row of df/dl (al = df_k/dl_i, bl = df_k/dl_j) from its A,
   B, E and cos and sin theta of links i and j */
static inline void rps3_plane_pair_dl(const rps3_plane_pair *q, double ci,
                                      double si, double cj, double sj,
                                      double *al, double *bl) {
  *al = q->E * si - q->A * ci;
  *bl = -q->B * cj - q->E * sj;
}

#endif /* RPS3_CJAC_H */
