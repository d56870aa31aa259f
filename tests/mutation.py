"""Which tests kill which mutation of the library: proof that the oracles
can fail.

    .venv/bin/python tests/mutation.py [-o docs/mutations.md] [--all] [NAME ...]
    make mutation          # the same, writes docs/mutations.md

Each mutation below is a one-line change to src/ that a wrong model, a
wrong derivation or a typo could make.  Every entry's original text must
occur exactly once in its file (checked for all of them before anything is
built).  The tracked tree is copied into a temporary directory (never this
one: the worktree's files are only read), built once, and the whole suite
is checked to pass there, timing each test; then each mutation in turn is
written into the copy and its tests run until the first one fails (or does
not finish): that test kills the mutation, and the copy's file is restored
before the next one.  Only what a test needs is rebuilt before it runs
(make's dependencies: the library objects the change reaches, then that
test program, or the library, runner and anchor before pytest).  Every
mutation must be killed: the script exits 1 when one survives.  A survivor
has run the whole suite, so stopping at the first kill weakens nothing.

The order of the tests: the ones that killed the mutation in the last
run (read from the page this run writes, -o, when it exists) first, C
test programs before pytest, then every other C test program, then the
pytest files; within each group the fastest of the unmutated run first.
--all runs every test on every mutation (the full matrix of which tests
kill what; several times slower).

The suite: every C test program (tests/test_*.c), and the pytest files that
compare the library with truths it did not compute: the SymPy and MuJoCo
oracles (test_oracles.py, test_sim_mujoco.py), the generated anchor
(test_anchor.py), the paper's tables (test_paper.py), the golden file
(test_golden.py) and the accuracy study against its long-double reference
(test_study.py).  Pytest files that go through the Python package are left
out: the package links the library statically into .venv, which the copy
shares, so they would test the unmutated library.

Not part of `make check`.
"""

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
VPY = os.path.join(ROOT, ".venv", "bin", "python")
PYTESTS = ["tests/test_oracles.py", "tests/test_sim_mujoco.py",
           "tests/test_anchor.py", "tests/test_paper.py",
           "tests/test_golden.py", "tests/test_study.py"]
# figures are drawn, not checked against a truth: not worth their time here
PYTEST_DESELECT = "not figure"
C_TIMEOUT = 300       # s per C test program; a hang counts as a kill
PY_TIMEOUT = 1200     # s for the pytest run

# (name, file, original text (once in the file), mutated text, what it is)
MUTATIONS = [
    ("link-inertia", "src/model.c",
     "m->Jlink = m->m * m->d * m->d + m->link_Ic;",
     "m->Jlink = 1.05 * (m->m * m->d * m->d + m->link_Ic);",
     "link inertia m d^2 + I_c scaled by 1.05"),
    ("disc-inertia", "src/model.c",
     "m->Ip[2] = 0.5 * m->M * m->r * m->r;",
     "m->Ip[2] = 0.505 * m->M * m->r * m->r;",
     "the disc's polar moment M r^2 / 2, 1 % off"),
    ("jacobian-0.1%", "src/cjac.h",
     "(ta) = 2.0 * (l_i) * DOT(D, dphi_i);",
     "(ta) = 2.002 * (l_i) * DOT(D, dphi_i);",
     "d f_k / d theta_i of (8)-(10) from the positions off by 0.1 %"
     " (scalar stages and batch kernel)"),
    ("jacobian-term", "src/cjac.h",
     "q.bt = lj * (q.B * sj - q.E * cj);",
     "q.bt = lj * (q.B * sj - 1.001 * q.E * cj);",
     "one term of d f_k / d theta_j of (8)-(10) in the links' planes off"
     " by 0.1 %"),
    ("constraint-constant", "src/fk.c",
     "s->p.q.r3 = 3.0 * m->rho * m->rho;",
     "s->p.q.r3 = 3.003 * m->rho * m->rho;",
     "the constant 3 rho^2 of (8)-(10) in the theta solve (its warm Newton"
     " path and the multiroot route), 0.1 % off"),
    ("theta-newton-step", "src/fk.c",
     "x[1] = (b[1] * b[2] * f[0] + a[0] * a[2] * f[1] - a[0] * b[1] * f[2]) * id;",
     "x[1] = (b[1] * b[2] * f[0] + a[0] * a[2] * f[1] + a[0] * b[1] * f[2]) * id;",
     "the theta solve's warm Newton path (multiroot route and forward"
     " dynamics): one term of its adjugate step with the wrong sign"),
    ("theta-newton-mode", "src/fk.c",
     "if (!(mode > 0 ? det > 0.0 : det < 0.0)) return -1;",
     "if (!(mode > 0 ? det > 0.0 : det < 0.0)) (void)0;",
     "the theta solve's warm Newton path takes a root of the other"
     " assembly mode"),
    ("theta-refold-retry", "src/inverse.c",
     "if (predicted && (status != RPS3_OK || (d->warn & RPS3_WARN_MODE))) {",
     "if (predicted && status != RPS3_OK) {",
     "the multiroot route keeps a root of another assembly mode found from"
     " a predicted start"),
    ("jacobian-dl-row", "src/cjac.h",
     "(le) = -2.0 * DOT(D, phi_j);",
     "(le) = -2.002 * DOT(D, phi_j);",
     "d f_k / d l_j of (8)-(10) from the positions off by 0.1 %"
     " (the lambda system's forces, scalar and batch)"),
    ("fd-jacobian-dl", "src/cjac.h",
     "*bl = -q->B * cj - q->E * sj;",
     "*bl = -q->B * cj - 1.001 * q->E * sj;",
     "forward dynamics: d f_k / d l_j in the links' planes off by 0.1 %"),
    ("alpha-gauge", "src/fk.c",
     "if (d->pose[1] < 1e-9) {", "if (d->pose[1] < 1e-6) {",
     "beta below which forward kinematics sets alpha = 0"),
    ("centre-x", "src/ik.c",
     "c[0] = -0.5 * m->r * vb * t->C;",
     "c[0] = -0.505 * m->r * vb * t->C;",
     "x of the platform centre (39), 1 % off"),
    ("omega-balls", "src/power.h",
     "const double h_ = 0.5 * (C(a, 0) * w0_ + C(a, 1) * w1_ + C(a, 2) * w2_);",
     "const double h_ = 0.505 * (C(a, 0) * w0_ + C(a, 1) * w1_"
     " + C(a, 2) * w2_);",
     "normal component removed from omega (26)-(28) (the one copy: rate"
     " stages, transmission, forward dynamics)"),
    ("omega-scale", "src/power.h",
     "const double w0_ = (wk) * (S0), w1_ = (wk) * (S1), w2_ = (wk) * (S2);",
     "const double w0_ = 1.001 * (wk) * (S0), w1_ = 1.001 * (wk) * (S1),"
     " w2_ = 1.001 * (wk) * (S2);",
     "scale of omega from the ball joints (26)-(28), 0.1 % off (the one"
     " copy: rate stages, transmission, forward dynamics)"),
    ("alpha-rate", "src/velocity.c",
     "d->dpose[0] = v3_dot(d->omega, ez_a) / (2.0 * vb);",
     "d->dpose[0] = v3_dot(d->omega, ez_a) / (2.002 * vb);",
     "alpha' from omega (joint-rate route), 0.1 % off"),
    ("centre-acc", "src/velocity.c",
     "ddC = -4.0 * C * da * da - 2.0 * S * dda;",
     "ddC = -4.004 * C * da * da - 2.0 * S * dda;",
     "a constant of the centre's acceleration, 0.1 % off"),
    ("paper-omega", "src/velocity.c",
     "const double rho = m->rho, h = 0.5 * RPS3_SQRT3;",
     "const double rho = m->rho, h = 0.5005 * RPS3_SQRT3;",
     "sqrt(3)/2 in the paper's (31)-(33), 0.1 % off"),
    ("fd-jacobian", "src/cjac.h",
     "q.at = li * (q.A * si + q.E * ci);",
     "q.at = 1.001 * li * (q.A * si + q.E * ci);",
     "theta solve and forward dynamics: d f_k / d theta_i in the links'"
     " planes, 0.1 % off"),
    ("fd-centre-mass", "src/fwddyn_plane.h",
     "const double mc = 3.0 * K->m6; /* M / 2 at the centre */",
     "const double mc = 3.003 * K->m6;",
     "forward dynamics: the disc's M/2 at its centre in Mq's Gram form,"
     " 0.1 % off"),
    ("fd-general-bias", "src/fwddyn_general.c",
     "t.ddtheta[i] = p->ddb[i];",
     "t.ddtheta[i] = 0.0;",
     "forward dynamics of the general bodies: hq's loads without the bias"
     " theta''"),
    ("fd-general-column", "src/fwddyn_general.c",
     "t.ddtheta[i] = p->G[i][j];",
     "t.ddtheta[i] = 1.001 * p->G[i][j];",
     "forward dynamics of the general bodies: Mq's columns at theta'' ="
     " G e_j, 0.1 % off"),
    ("fd-general-no-mass", "src/fwddyn.c",
     "return p[0] > 0.0 || p[4] + p[7] + p[9] > 0.0;",
     "return p[0] >= 0.0;",
     "forward dynamics of the general bodies: a massless body taken for"
     " inertia (Mq singular, not refused)"),
    ("energy-general-kinetic", "src/fwddyn_body.c",
     "*T = 0.5 * p[0] * v3_dot(vO, vO) + v3_dot(vO, t) +",
     "*T = 0.5 * p[0] * v3_dot(vO, vO) + 1.001 * v3_dot(vO, t) +",
     "rps3_energy of the general bodies: the kinetic energy's cross term"
     " v_O . (omega x m c), 0.1 % off"),
    ("energy-general-potential", "src/fwddyn_body.c",
     "*P = g * (p[0] * zO + hw[2]);",
     "*P = g * (p[0] * zO + 1.001 * hw[2]);",
     "rps3_energy of the general bodies: a body's centre of mass height in"
     " its weight's energy, 0.1 % off"),
    ("fd-centripetal", "src/theta.h",
     "Zdd[i] = q->c[i] * v - q->s[i] * lth * dth[i];",
     "Zdd[i] = q->c[i] * v - 1.001 * q->s[i] * lth * dth[i];",
     "forward dynamics and the root predictor: a ball joint's centripetal"
     " acceleration in the links' planes, 0.1 % off"),
    ("theta-predict-second-order", "src/theta.h",
     "h = 0.5 * tau * tau;",
     "h = 0.6 * tau * tau;",
     "the root predictor (multiroot route, forward dynamics, controllers): the"
     " predicted start's second-order term, 20 % off"),
    ("fd-share-geometry", "src/fwddyn_shared.c",
     "m->R != src_model->R || m->r != src_model->r ||",
     "m->r != src_model->r ||",
     "controllers: the plant's kinematics lent to a model of another R"),
    ("fd-share-dynamics", "src/fwddyn_shared.c",
     "return a->opt.effects == b->opt.effects && a->M == b->M && a->m == b->m &&",
     "return a->opt.effects == b->opt.effects && a->m == b->m &&",
     "controllers: the plant's Mq, hq lent to a model of another M"),
    ("fd-fold-step", "src/fwddyn_singular.c",
     "const double tau = 2.0 * (double)j / SING_SAMPLES;",
     "const double tau = 1.0 * (double)j / SING_SAMPLES;",
     "singular surface: the fold test on one Newton step, not two"),
    ("fd-fold-local", "src/fwddyn_singular.c",
     "#define SING_STEP_MAX 0.05",
     "#define SING_STEP_MAX HUGE_VAL",
     "singular surface: the fold test on any step, however far"),
    ("fd-mass-adjugate", "src/fwddyn.c",
     "det > MASS_ADJ_DET * (A[0][0] * A[1][1] * A[2][2]) &&",
     "det > 0.0 &&",
     "singular surface: Mq's adjugate trusted down to rounding"),
    ("fd-mass-pivot", "src/fwddyn.c",
     "if (!(D[2] > MASS_PIVOT_TOL * A[2][2])) return 3;",
     "if (!(D[2] > 1e-9 * A[2][2])) return 3;",
     "singular surface: Mq refused by a pivot far above its rounding"),
    ("sim-stopped-short", "src/sim.c",
     "return st == RPS3_ESING ? st : RPS3_OK;",
     "return st == RPS3_ESING ? RPS3_OK : RPS3_OK;",
     "singular surface: an integrator that gives up short of it"),
    ("link-motion-acc", "src/velocity.c",
     "d->ddl[i] = (v3_dot(bd, bd) - dl * dl + v3_dot(v, bdd)) * il;",
     "d->ddl[i] = (v3_dot(bd, bd) - 1.001 * dl * dl + v3_dot(v, bdd)) * il;",
     "controllers: the desired link accelerations' l'^2 term, 0.1 % off"),
    ("sim-report", "src/sim.c",
     "st = evaluate(s, s->now.t, s->now.y, !report, keeps_plant(s));",
     "st = evaluate(s, s->now.t, s->now.y, 1, keeps_plant(s));",
     "simulation: a call's end not reported (a lean state's NaN pose)"),
    ("sim-offer-hq", "src/sim.c",
     "v3_copy(v->hq, k->hq);", "v3_scale(v->hq, 1.001, k->hq);",
     "controllers: the plant's hq offered at a tick, 0.1 % off"),
    ("sim-offer-noise", "src/sim.c",
     "return !(s->opt.noise_l > 0.0 || s->opt.noise_dl > 0.0 ||",
     "return !(s->opt.noise_dl > 0.0 ||",
     "controllers: the plant's state offered under noisy lengths"),
    ("ctrl-bias", "src/control.c",
     "v3_axpy(x, x, 1.0, d->hq);", "v3_axpy(x, x, 1.001, d->hq);",
     "controllers: their model's bias forces hq, 0.1 % off"),
    ("platform-sixth", "src/loads.h",
     "#define RPS3_DISC_BALL_MASS(M) ((M) / 6.0)",
     "#define RPS3_DISC_BALL_MASS(M) ((M) / 6.006)",
     "the disc as point masses, M/6 at each ball joint (the loads' one"
     " copy: Lagrange route, batch kernel, lean pass, forward dynamics),"
     " 0.1 % off"),
    ("link-gravity-sign", "src/loads.h",
     "((wt) = (mgd) * (cos_theta))", "((wt) = -(mgd) * (cos_theta))",
     "sign of the links' weight (22) (the loads' one copy: Lagrange route,"
     " batch kernel, forward dynamics)"),
    ("loads-ball-weight-theta", "src/loads.h",
     "(wt) = (W) * (l) * (dphi_z);", "(wt) = 1.001 * (W) * (l) * (dphi_z);",
     "the platform's weight M g / 3 on a ball joint, its load on theta_i"
     " 0.1 % off (the loads' one copy: Lagrange route, batch kernel,"
     " forward dynamics' hq)"),
    ("loads-centre-acc", "src/loads.h",
     "const double f2_ = (m6) * (C(cdd, 2) + C(bdd, 2));",
     "const double f2_ = (m6) * (C(bdd, 2));",
     "the platform's inertia on a ball joint without the centre's vertical"
     " acceleration c''_z (the loads' one copy: Lagrange route, batch"
     " kernel, forward dynamics' hq)"),
    ("platform-gravity-ne", "src/invdyn_ne.c",
     "wf[2] = m->M * m->g;", "wf[2] = -m->M * m->g;",
     "sign of the platform's weight (Newton-Euler route)"),
    ("payload-second-moment", "src/invdyn.c",
     "double tr = 0.5 * (p->inertia[0] + p->inertia[1] + p->inertia[2]);",
     "double tr = 0.505 * (p->inertia[0] + p->inertia[1] + p->inertia[2]);",
     "the payload's second moments (Lagrange route), 1 % off"),
    ("payload-weight-ne", "src/invdyn_ne.c",
     "wf[2] += m->payload.mass * m->g;", "wf[2] += m->payload.mass * 9.81;",
     "the payload's weight with g = 9.81, not the model's (Newton-Euler)"),
    ("coulomb-sign", "src/internal.h",
     "return f->viscous * v + f->coulomb * s;",
     "return f->viscous * v - f->coulomb * s;",
     "sign of Coulomb friction (pins and prismatic joints)"),
    ("viscous-friction", "src/internal.h",
     "return f->viscous * v + f->coulomb * s;",
     "return 1.01 * f->viscous * v + f->coulomb * s;",
     "viscous friction 1 % too strong (pins and prismatic joints)"),
    ("transmission-moment", "src/power.h",
     "(R) * (fabs(C(om, 0)) + fabs(C(om, 1)) + fabs(C(om, 2))))",
     "1.01 * (R) * (fabs(C(om, 0)) + fabs(C(om, 1)) + fabs(C(om, 2))))",
     "moment scale R of the force transmission, 1 % off (the measure's one"
     " copy: stages, batch kernel, forward dynamics)"),
    ("transmission-rows", "src/power.h",
     "((s0) * C(X0, k) + (s1) * C(X1, k) + (s2) * C(X2, k) + C(Y, k))",
     "((s0) * C(X0, k) + (s1) * C(X1, k) + (s2) * C(X2, k)"
     " + 1.01 * C(Y, k))",
     "the link's own rate in the transmission's twist, 1 % off (the"
     " twist's one copy: stages, batch kernel)"),
    ("transmission-centre", "src/power.h",
     "(1.0 / 3.0) * RPS3_TRANS_SUM_(C, 0, s0, s1, s2, d0, d1, d2, phi);",
     "(1.01 / 3.0) * RPS3_TRANS_SUM_(C, 0, s0, s1, s2, d0, d1, d2, phi);",
     "x of the centre's velocity in the transmission's twist, 1 % off (the"
     " twist's one copy: stages, batch kernel)"),
    ("power-link-inertia", "src/power.h",
     "RPS3_POWER_LINKS_(C, Jlink, dtheta, ddtheta, p, s)",
     "RPS3_POWER_LINKS_(C, 1.001 * (Jlink), dtheta, ddtheta, p, s)",
     "the certificate's link inertia power Jlink theta' theta'', 0.1 % off"
     " (the one copy: stages, batch kernel)"),
    ("power-body-rotation", "src/power.h",
     "((Ik) * (C(rk, 0) * C(dw, 0) + C(rk, 1) * C(dw, 1)",
     "(1.001 * (Ik) * (C(rk, 0) * C(dw, 0) + C(rk, 1) * C(dw, 1)",
     "the certificate's rotational power omega . I_world omega', 0.1 % off"
     " (the one copy: platform and payload, stages and batch kernel)"),
    ("power-body-gravity", "src/power.h",
     "(p) = (mg) * (vz);", "(p) = 1.001 * (mg) * (vz);",
     "the certificate's weight power m g v_z, 0.1 % off (the one copy:"
     " platform and payload, stages and batch kernel)"),
    ("ctrl-time-finite", "src/control.c",
     "  if (!isfinite(t)) {\n    c->meas->err.code = RPS3_EINVAL;",
     "  if (isnan(t)) {\n    c->meas->err.code = RPS3_EINVAL;",
     "controllers: an infinite time t taken as a time (only NaN refused)"),
    ("ctrl-measured-rates", "src/control.c",
     "for (i = 0; i < 6; i++) {\n    double x = i < 3 ? l[i] : dl[i - 3];",
     "for (i = 0; i < 3; i++) {\n    double x = i < 3 ? l[i] : dl[i - 3];",
     "controllers: the measured rates dl not checked to be finite"),
    ("ctrl-force-finite", "src/control.c",
     "if (v3_finite(F)) return RPS3_OK;",
     "if (!isnan(F[0] + F[1] + F[2])) return RPS3_OK;",
     "controllers: an infinite force passed (only NaN refused)"),
    ("sim-rate-h", "src/sim_setup.c",
     "if (!(period >= step / (double)RPS3_SIM_RATE_H_MAX)) {",
     "if (!(period >= step / (10.0 * RPS3_SIM_RATE_H_MAX))) {",
     "rate check: 10 times more control periods a step than allowed"),
    ("sim-rate-t-max", "src/sim_setup.c",
     "if (!(period >= t_max / (double)RPS3_SIM_MAX_PERIODS)) {",
     "if (!(period >= t_max / (100.0 * RPS3_SIM_MAX_PERIODS))) {",
     "rate check: periods a run limit 100 times too large"),
    ("sim-rate-max-steps", "src/sim_setup.c",
     "if (steps > (double)o->max_steps) {",
     "if (steps > 10.0 * (double)o->max_steps) {",
     "rate check: steps of h a period against 10 max_steps"),
    ("sim-advance-back", "src/sim.c",
     "if (t_end < s->now.t) {",
     "if (t_end < s->t0) {",
     "rps3_sim_advance: t_end checked against the start, not the time"),
    ("sim-epsabs-zero", "src/sim_setup.c",
     "REQUIRE(o->epsabs > 0 || o->integrator == RPS3_INT_RK4 ||",
     "REQUIRE(o->epsabs >= 0 || o->integrator == RPS3_INT_RK4 ||",
     "epsabs = 0 accepted for an adaptive integrator"),
    ("traj-span-max", "src/traj.c",
     "if (!(T > 0.0 && T <= (double)RPS3_TRAJ_SPAN_MAX)) {",
     "if (!(T > 0.0 && T <= 1e3 * (double)RPS3_TRAJ_SPAN_MAX)) {",
     "trajectory check: span limit 1000 times too large"),
    ("wp-span-sum", "src/timelaw.c",
     "if (!(isfinite(T) && total <= (double)RPS3_TRAJ_SPAN_MAX)) {",
     "if (!(isfinite(T) && T <= (double)RPS3_TRAJ_SPAN_MAX)) {",
     "waypoints: each segment against the span limit, not their sum"),
    ("sine-acc-overflow", "src/traj.c",
     "if (!isfinite((a * w) * w) || !isfinite((a * w) * (a * w)) ||",
     "if (!isfinite(a * w) || !isfinite((a * w) * (a * w)) ||",
     "sine check: the peak acceleration amp w^2 not checked in closed form"),
    ("traj-eval-law", "src/traj.c",
     "return law == RPS3_LAW_MINJERK || law == RPS3_LAW_QUINTIC;",
     "return (int)law >= 0;",
     "rps3_traj_eval: an unknown time law evaluated, not RPS3_EINVAL"),
    ("table-interp-finite", "src/table.c",
     "if (!v3_finite(q) || !v3_finite(dq) || !v3_finite(ddq)) {",
     "if (!v3_finite(q) || !v3_finite(dq)) {",
     "table check: an interpolant's acceleration not checked to be finite"),
    ("fd-chol-inverse", "src/fwddyn.c",
     "Li[2][0] = L10 * L21 - L20;",
     "Li[2][0] = -L20;",
     "singular surface: Mq's inverse from its Cholesky factor, L^-1 wrong"),
    # the design section (src/design.c): its indices, flags, mass model and
    # task statistics (tests/test_design.c)
    ("design-ball-velocity", "src/design_eval.c",
     "v3_axpy(vb, vb, 1.0, v);", "v3_axpy(vb, vb, 1.001, v);",
     "design: a ball's velocity under an output twist, v_c part 0.1 % off"),
    ("design-constraint-moment", "src/design_eval.c",
     "v3_cross(mo, p[k % 3], f);",
     "v3_cross(mo, p[k % 3], f);\n    if (k >= 3) v3_scale(mo, 0.999, mo);",
     "design: the constraint wrenches' moments 0.1 % off"),
    ("design-cond-norm", "src/design_eval.c",
     "r->cond_h = sqrt(fro_g * fro_x) / 6.0;",
     "r->cond_h = sqrt(fro_g * fro_x) / 5.994;",
     "design: the normalisation of the Frobenius condition number"),
    ("design-length-scale", "src/design_eval.c",
     "v3_scale(p[i], 1.0 / L, p[i]);", "v3_scale(p[i], 1.001 / L, p[i]);",
     "design: the characteristic length of cond_h, 0.1 % off"),
    ("design-ball-angle", "src/design_eval.c",
     "r->ball[i] = atan2(v3_norm(x), v3_dot(d->phi[i], a));",
     "r->ball[i] = atan2(v3_norm(x), 1.001 * v3_dot(d->phi[i], a));",
     "design: the ball joint angle, its cosine 0.1 % off"),
    ("design-spin", "src/design_eval.c",
     "r->spin = atan2(d->rot[1][0], d->rot[0][0]);",
     "r->spin = atan2(d->rot[1][0], d->rot[1][1]);",
     "design: the parasitic spin from the wrong diagonal entry"),
    ("design-segment-end", "src/design_eval.c",
     "s = (b * t - c) / a;", "s = (b * t - c) / (1.001 * a);",
     "design: the closest point to a segment's end, 0.1 % off"),
    ("design-stroke", "src/design_eval.c",
     "if (!(r->l[i] >= ds->l_min && r->l[i] <= ds->l_max))",
     "if (!(r->l[i] >= ds->l_min && r->l[i] <= 0.999 * ds->l_max))",
     "design: the stroke limit l_max 0.1 % short"),
    ("design-rod-inertia", "src/design.c",
     "*ic = rod * ds->l_max * ds->l_max / 12.0",
     "*ic = rod * ds->l_max * ds->l_max / 12.012",
     "design: the rod's own inertia l^2 / 12, 0.1 % off"),
    ("design-centroid", "src/design.c",
     "ds->actuator_mass * ds->actuator_d + rod * h) / *m",
     "ds->actuator_mass * ds->actuator_d + 1.001 * rod * h) / *m",
     "design: the rod's first moment in the centroid d, 0.1 % off"),
    ("design-volume", "src/design_eval.c",
     "s->volume = (double)s->nreach * cell_volume;",
     "s->volume = (double)s->n * cell_volume;",
     "design: the workspace volume over every pose, not the reachable"),
    ("design-rms", "src/design_task.c",
     "sumsq[j] += F * F;", "sumsq[j] += 1.001 * F * F;",
     "design: a task's RMS force, the square 0.1 % off"),
    ("design-power", "src/design_task.c",
     "res->P_peak[j] = fmax_(res->P_peak[j], fabs(F * v));",
     "res->P_peak[j] = fmax_(res->P_peak[j], 1.001 * fabs(F * v));",
     "design: a task's peak power 0.1 % off"),
    ("design-sample-time", "src/design_task.c",
     "return k + 1 == n ? T : T * (double)k / (double)(n - 1);",
     "return k + 1 == n ? T : T * (double)k / (double)n;",
     "design: a task's sample times k T / n instead of k T / (n - 1)"),
    ("design-link-mass-off", "src/design_task.c",
     "dm->opt.effects &= ~(RPS3_EFF_LINK_GRAVITY | RPS3_EFF_LINK_INERTIA);",
     "dm->opt.effects &= ~(RPS3_EFF_LINK_GRAVITY);",
     "design: a task without link mass keeps the links' inertia"),
    ("lu6-inverse-pivot", "src/linalg.c",
     "double p = 1.0 / LU[7 * i];", "double p = 1.001 / LU[7 * i];",
     "the 6 x 6 inverse's reciprocal pivot 0.1 % off"),

    # the one singularity policy (src/policy.h, src/policy.c) and the
    # calls of it that the default entry points run
    ("policy-quiet-lambda", "src/policy.h",
     "case RPS3_SING_LAMBDA: return m->opt.cond_warn;",
     "case RPS3_SING_LAMBDA: return m->opt.cond_max;",
     "policy: the lambda system's condition number silent up to cond_max"),
    ("policy-warn-bit", "src/policy.c",
     "value > rps3_sing_quiet(m, measure))",
     "value > 2.0 * rps3_sing_quiet(m, measure))",
     "policy: a warning bit only at twice its threshold"),
    ("policy-max", "src/policy.c",
     "return measure == RPS3_SING_TRANS ? m->opt.trans_max : m->opt.cond_max;",
     "return measure == RPS3_SING_TRANS ? m->opt.trans_max"
     " : 10.0 * m->opt.cond_max;",
     "policy: condition numbers refused only at 10 cond_max"),
    ("policy-nan", "src/policy.c",
     "if (value >= 0.0 && value <= max) {",
     "if (!(value > max)) {",
     "policy: a NaN or negative measure accepted"),
    ("policy-certify-cond", "src/policy.h",
     "*cond_lim = (c < m->opt.cond_max ? c : m->opt.cond_max) * (1.0 - margin);",
     "*cond_lim = (c < m->opt.cond_max ? m->opt.cond_max : c)"
     " * (1.0 - margin);",
     "batch certificate: kernel points above cond_warn kept, no warning"),
    ("policy-certify-trans", "src/policy.h",
     "*trans_lim = (t < m->opt.trans_max ? t : m->opt.trans_max) * (1.0 - margin);",
     "*trans_lim = (t < m->opt.trans_max ? m->opt.trans_max : t)"
     " * (1.0 - margin);",
     "batch certificate: kernel points above trans_warn kept, no warning"),
    ("policy-invdyn-trans", "src/invdyn.c",
     "return rps3_sing_check(m, d, RPS3_SING_TRANS, d->transmission);",
     "return RPS3_OK;",
     "rps3_inverse's one-point path: transmission never checked"),
    ("policy-rates-jt", "src/velocity.c",
     "return rps3_sing_check(m, d, RPS3_SING_JT, cond);",
     "return cond < HUGE_VAL ? RPS3_OK"
     " : rps3_sing_decide(m, d, RPS3_SING_JT, cond);",
     "rate stages: df/dtheta refused only when exactly singular"),
    ("policy-fd-jt", "src/fwddyn_plane.h",
     "return rps3_sing_check(m, d, RPS3_SING_JT, cond);",
     "return cond < HUGE_VAL ? RPS3_OK"
     " : rps3_sing_decide(m, d, RPS3_SING_JT, cond);",
     "forward dynamics: df/dtheta refused only when exactly singular"),
    ("policy-fd-trans", "src/fwddyn_plane.h",
     "return rps3_sing_check(m, d, RPS3_SING_TRANS, T);",
     "return RPS3_OK;",
     "controller's state (forward dynamics' limits): transmission unchecked"),
    ("policy-fd-mass", "src/fwddyn.c",
     "st = rps3_sing_check(m, d, RPS3_SING_MQ, d->Mcond);",
     "st = rps3_sing_check(m, d, RPS3_SING_MQ, 1e-3 * d->Mcond);",
     "forward dynamics: Mq's condition number refused only at 1000"
     " cond_max"),
    ("kernel-cond-certificate", "src/batch_kernel.c",
     "(cond <= K->cond_lim) & (trans <= K->trans_lim))",
     "(trans <= K->trans_lim))",
     "batch kernel: a point kept whatever its condition number"),
    ("ksincos-series", "src/batch_trig.h",
     "kmaf(r2, 1.0 / 120.0, -1.0 / 6.0, fu)",
     "kmaf(r2, 1.0 / 120.0, -1.0 / 6.000001, fu)",
     "vector sine: the r^3 term of the series 1.7e-7 off (every kernel)"),
    ("kpose-centre", "src/batch_kmech.h",
     "P.c = kv(-0.5 * r * vb2 * C, 0.5 * r * vb2 * S, z);",
     "P.c = kv(-0.505 * r * vb2 * C, 0.5 * r * vb2 * S, z);",
     "batch kernel and lean pass: x of the platform centre (3), 1 % off"),
    ("lean-cond-certificate", "src/batch_kmech.h",
     "(an + o.cond + o.tbound <= DBL_MAX) & (o.cond <= K->cond_lim) &",
     "(an + o.cond + o.tbound <= DBL_MAX) &",
     "lean pass: a point kept whatever its condition number"),
    ("links-ball-vel", "src/links.h",
     "C(bd, 1) = C(wr, 1) + C(vc, 1);",
     "C(bd, 1) = C(wr, 1) + 1.001 * C(vc, 1);",
     "a ball joint's velocity (26): y of the centre's part, 0.1 % off"
     " (staged route, kernel and lean pass)"),
    ("links-ball-acc-centripetal", "src/links.h",
     "MS(C(w, 2), C(wr, 0), C(w, 0), C(wr, 2)) + C(ac, 1);",
     "1.001 * MS(C(w, 2), C(wr, 0), C(w, 0), C(wr, 2)) + C(ac, 1);",
     "a ball joint's acceleration: y of omega x (omega x rho), 0.1 % off"
     " (staged route, kernel and lean pass)"),
    ("links-theta-acc", "src/links.h",
     "- 2.0 * (dl) * (dth)) * (il))",
     "- 2.002 * (dl) * (dth)) * (il))",
     "theta'' from the ball's acceleration: the 2 l' theta' term, 0.1 %"
     " off (staged route, kernel and lean pass)"),
    ("links-ball-acc-joints", "src/links.h",
     "(ddl) - (l) * (dth) * (dth);",
     "(ddl) - 1.001 * (l) * (dth) * (dth);",
     "b'' from the joint rates: the l theta'^2 term, 0.1 % off (the"
     " Lagrange route's c'', kernel and stages)"),
    ("links-dphi", "src/links.h",
     "C(dphi, 0) = (st) * (ux);",
     "C(dphi, 0) = 1.001 * (st) * (ux);",
     "the direction dphi (29): its x component, 0.1 % off (staged route,"
     " kernel and lean pass)"),
    ("links-ball-offset", "src/links.h",
     "C(rho, 1) = MA((bx), C(rx, 1), (by) * C(ry, 1));",
     "C(rho, 1) = MA((bx), C(rx, 1), 1.001 * (by) * C(ry, 1));",
     "a ball joint (15)-(17): y of its offset from the centre, 0.1 % off"
     " (staged route, kernel and lean pass)"),
    ("links-radial", "src/links.h",
     "(radial) = MA(C(v, 0), (ux), C(v, 1) * (uy));",
     "(radial) = MA(C(v, 0), (ux), 1.001 * C(v, 1) * (uy));",
     "a link's radial component -l cos theta (39): its y term, 0.1 % off"),
    ("links-theta", "src/links.h",
     "ATAN2((vz), -(radial))",
     "ATAN2(1.001 * (vz), -(radial))",
     "theta (39): the height in the arc tangent, 0.1 % off"),
    ("links-sin", "src/links.h",
     "(st) = (vz) * (il);",
     "(st) = 1.001 * (vz) * (il);",
     "sin theta from the height, 0.1 % off (staged route and kernel)"),
    ("links-phi", "src/links.h",
     "C(phi, 1) = -(ct) * (uy);",
     "C(phi, 1) = -1.001 * (ct) * (uy);",
     "the direction phi (29): its y component, 0.1 % off"),
    ("links-theta-rate", "src/links.h",
     "(dth) = DOT(dphi, bd) * (il);",
     "(dth) = DOT(dphi, bd) * 1.001 * (il);",
     "theta' from the ball's velocity (28), 0.1 % off (staged route,"
     " kernel and lean pass)"),
    ("links-l-acc", "src/links.h",
     "DOT(phi, bb) + (l) * (dth) * (dth))",
     "DOT(phi, bb) + 1.001 * (l) * (dth) * (dth))",
     "l'' from the ball's acceleration: the l theta'^2 term, 0.1 % off"),
    ("links-ball-at", "src/links.h",
     "C(b, 1) = C(pin, 1) + (l) * C(phi, 1);",
     "C(b, 1) = C(pin, 1) + 1.001 * (l) * C(phi, 1);",
     "a ball joint from the joint coordinates (12)-(14): y, 0.1 % off"
     " (forward kinematics and dynamics)"),
    ("links-ball-vel-joints", "src/links.h",
     "C(bd, 1) = (dl) * C(phi, 1) + s_ * C(dphi, 1);",
     "C(bd, 1) = (dl) * C(phi, 1) + 1.001 * s_ * C(dphi, 1);",
     "a ball joint's velocity from the joint rates: y of its theta' part,"
     " 0.1 % off"),
    ("lean-ball-weight", "src/batch_kmech.h",
     "kma(K->m6, ac.z + bb.z, K->g3, fu));",
     "kma(K->m6, ac.z + bb.z, 1.001 * K->g3, fu));",
     "lean pass: the platform's weight in its summed ball force, 0.1 % off"),

    ("regressor-disc-column", "src/ident.c",
     "u.Ip[2] = 0.5 * m->r * m->r;",
     "u.Ip[2] = 0.505 * m->r * m->r;",
     "identification: the regressor's disc column, its polar moment per"
     " unit mass 1 % off"),
    ("wls-covariance-scale", "src/ident_fit.c",
     "res->cov[j * p + k] = res->s2 * gsl_matrix_get(L.cov, j, k);",
     "res->cov[j * p + k] = gsl_matrix_get(L.cov, j, k);",
     "identification: WLS covariance not scaled by the residual variance"),
    ("consistent-pseudo-mass", "src/ident_cfit.c",
     "J[3][3] = s[0];",
     "J[3][3] = 1.01 * s[0];",
     "identification: the consistent fit's pseudo-inertia mass entry 1 %"
     " off"),
    ("consistent-barrier-logdet", "src/ident_cbar.c",
     "s -= log(gsl_vector_get(c->lam, k));",
     "s -= 0.5 * log(gsl_vector_get(c->lam, k));",
     "identification: the consistent fit's barrier stage, -log det J_b"
     " halved in the line search's value (its gradient and Hessian as"
     " they are)"),
    # the general bodies (src/bodies.c, their loads in both formulations,
    # the certificate, the regressor of the standard parameters)
    ("bodies-mass", "src/bodies.c",
     "Wf[r][0] = a[r];",
     "Wf[r][0] = 1.001 * a[r];",
     "a general body's force m a, 0.1 % off"),
    ("bodies-centripetal", "src/bodies.c",
     "Wf[r][1 + j] = t[r] + x[r];",
     "Wf[r][1 + j] = t[r] + 1.001 * x[r];",
     "a general body's centripetal force omega x (omega x h), 0.1 % off"),
    ("bodies-first-moment", "src/bodies.c",
     "Wn[r][1 + j] = y[r];",
     "Wn[r][1 + j] = 1.001 * y[r];",
     "a general body's moment h x a, 0.1 % off"),
    ("bodies-gyroscopic", "src/bodies.c",
     "Wn[r][4 + k] = Id[r] + t[r];",
     "Wn[r][4 + k] = Id[r] + 1.001 * t[r];",
     "a general body's gyroscopic moment omega x I omega, 0.1 % off"),
    ("bodies-products", "src/bodies.c",
     "v3_axpy(Io, Io, v3_dot(e[p], om), e[q]);",
     "v3_axpy(Io, Io, 1.001 * v3_dot(e[p], om), e[q]);",
     "a product of inertia's symmetric half in I omega, 0.1 % off"),
    ("bodies-piston-arm", "src/bodies.c",
     "WT[10 + k] = l * v3_dot(dphi, fk)",
     "WT[10 + k] = 1.001 * l * v3_dot(dphi, fk)",
     "a piston's force on theta through the arm l dphi, 0.1 % off"),
    ("bodies-cylinder-axis", "src/bodies.c",
     "WT[k] = w[0] * Wn[0][k] + w[1] * Wn[1][k] + w[2] * Wn[2][k];",
     "WT[k] = w[0] * Wn[0][k] + 1.001 * w[1] * Wn[1][k] + w[2] * Wn[2][k];",
     "a cylinder's moment about its pin axis, one component 0.1 % off"),
    ("bodies-power-translation", "src/bodies.c",
     "tt = m * v3_dot(vG, aG);",
     "tt = 1.001 * m * v3_dot(vG, aG);",
     "the certificate: a general body's m v . a, 0.1 % off"),
    ("bodies-power-rotation", "src/bodies.c",
     "tr += ob[j] * I[j][k] * db[k];",
     "tr += 1.001 * ob[j] * I[j][k] * db[k];",
     "the certificate: a general body's omega . I omega', 0.1 % off"),
    ("bodies-platform-moment", "src/invdyn.c",
     "S[i][j] = (i == j ? tr : 0.0) - I[i][j];",
     "S[i][j] = (i == j ? tr : 0.0) - 1.001 * I[i][j];",
     "Lagrange: the general platform's second moment, 0.1 % off"),
    ("bodies-certify-ball", "src/invdyn_certify.c",
     "v3_axpy(vb, d->vc, 1.0, t);",
     "v3_axpy(vb, d->vc, 1.001, t);",
     "the certificate: a piston's origin velocity, 0.1 % off"),
    ("prismatic-lagrange", "src/invdyn.c",
     "w[i] = rps3_friction_law(&m->leg[i].prismatic, d->dl[i]);",
     "w[i] = 1.001 * rps3_friction_law(&m->leg[i].prismatic, d->dl[i]);",
     "Lagrange: the prismatic joints' friction, 0.1 % off"),
    ("prismatic-certify", "src/invdyn_certify.c",
     "p = -rps3_friction_law(&m->leg[i].prismatic, d->dl[i]) * d->dl[i];",
     "p = -1.001 * rps3_friction_law(&m->leg[i].prismatic, d->dl[i]) * "
     "d->dl[i];",
     "the certificate: the prismatic joints' friction power, 0.1 % off"),
    ("bodies-ne-platform-weight", "src/invdyn_ne.c",
     "a[0] = a[1] = 0.0, a[2] = m->g;",
     "a[0] = a[1] = 0.0, a[2] = 1.001 * m->g;",
     "Newton-Euler: the general platform's weight, 0.1 % off"),
    ("bodies-ne-piston", "src/invdyn_ne.c",
     "v3_axpy(wf, wf, p[i], d->phi[i]);",
     "v3_axpy(wf, wf, 1.001 * p[i], d->phi[i]);",
     "Newton-Euler: the actuator's own share in the ball force, 0.1 % off"),
    ("prismatic-ne", "src/invdyn_ne.c",
     "p[i] = rps3_friction_law(&m->leg[i].prismatic, d->dl[i]);",
     "p[i] = 1.001 * rps3_friction_law(&m->leg[i].prismatic, d->dl[i]);",
     "Newton-Euler: the prismatic joints' friction, 0.1 % off"),
    ("bodies-ne-leg-basis", "src/invdyn_ne.c",
     "s[i] = -w[3 + i] / d->l[i];",
     "s[i] = -1.001 * w[3 + i] / d->l[i];",
     "Newton-Euler: a unit leg load's ball force (the regressor), 0.1 % off"),
    ("bodies-parallel-axes", "src/model.c",
     "p[4] = b->inertia[0] + m * (cc - c[0] * c[0]);",
     "p[4] = b->inertia[0] + 1.001 * m * (cc - c[0] * c[0]);",
     "a body's Ixx about its origin, parallel axes 0.1 % off"),
    ("bodies-parallel-product", "src/model.c",
     "p[5] = b->inertia[1] - m * c[0] * c[1];",
     "p[5] = b->inertia[1] + m * c[0] * c[1];",
     "a body's Ixy about its origin, the parallel-axis term's sign"),
    ("bodies-triangle-rule", "src/model.c",
     "if (S[i][i] < -1e-12 * s)",
     "if (S[i][i] < -1e-1 * s)",
     "a body's triangle inequality 10 % slack: an unreal body accepted"),
    ("std-unit-law", "src/ident_std.c",
     "u.viscous = k == 0 ? 1.0 : 0.0;",
     "u.viscous = k == 0 ? 1.001 : 0.0;",
     "the standard regressor's viscous columns, 0.1 % off"),
    ("std-leg-column", "src/ident_std.c",
     "Y[r][col] = Fb[r][i] * wl[k] + Fb[r][3 + i] * wt[k];",
     "Y[r][col] = Fb[r][i] * wl[k] + 1.001 * Fb[r][3 + i] * wt[k];",
     "the standard regressor: a leg column's theta part, 0.1 % off"),
    ("std-platform-column", "src/ident_std.c",
     "u.std[0][k] = 1.0;",
     "u.std[0][k] = 1.001;",
     "the standard regressor's platform columns, 0.1 % off"),
    ("std-params-prismatic", "src/ident_std.c",
     "pi[NBODYCOL + 2 * i] = m->leg[i].prismatic.viscous;",
     "pi[NBODYCOL + 2 * i] = 1.001 * m->leg[i].prismatic.viscous;",
     "the standard parameters: prismatic viscous friction, 0.1 % off"),
    ("std-params-paper-link", "src/ident_std.c",
     "std_of(m->m, cd, link, pi + 10 * (1 + 2 * i));",
     "std_of(1.001 * m->m, cd, link, pi + 10 * (1 + 2 * i));",
     "the paper bodies' standard parameters: a link's mass, 0.1 % off"),
    ("prismatic-fwddyn", "src/fwddyn_plane.h",
     "if (pfric) wl[i] += rps3_friction_law(&m->leg[i].prismatic, p->dl[i]);",
     "if (pfric) wl[i] += 1.001 * rps3_friction_law(&m->leg[i].prismatic, "
     "p->dl[i]);",
     "forward dynamics: the prismatic joints' friction, 0.1 % off"),
    ("prismatic-sim-power", "src/sim.c",
     "fric -= rps3_friction_law(&s->plant.leg[i].prismatic, y[3 + i]) *",
     "fric -= 1.001 * rps3_friction_law(&s->plant.leg[i].prismatic, y[3 + i]) *",
     "simulation: the prismatic joints' friction work, 0.1 % off"),
    ("base-grouping", "src/ident_base.c",
     "for (r = 0; r < (size_t)nb; r++) K[r * p + j] = gsl_vector_get(x, r);",
     "for (r = 0; r < (size_t)nb; r++) K[r * p + j] = 1.001 * gsl_vector_get(x, r);",
     "base parameters: a dependent column's grouping coefficients, 0.1 % off"),
    ("base-zero-columns", "src/ident_base.c",
     "zero[j] = !(s > tol * cmax);",
     "zero[j] = !(s > 1e-3 * cmax);",
     "base parameters: weak columns (below 1e-3 of the largest) dropped as"
     " acting on nothing"),
]


def sh(cmd, cwd, timeout=None, env=None):
    try:
        return subprocess.run(cmd, cwd=cwd, capture_output=True, text=True,
                              timeout=timeout, env=env)
    except subprocess.TimeoutExpired:
        return None


def copy_tree(dst):
    """The tracked files as they are in the worktree, and the shared .venv."""
    files = sh(["git", "ls-files", "-z"], ROOT).stdout.split("\0")
    for f in filter(None, files):
        src = os.path.join(ROOT, f)
        if not os.path.isfile(src):
            continue  # deleted in the worktree, not yet committed
        os.makedirs(os.path.join(dst, os.path.dirname(f)), exist_ok=True)
        shutil.copy2(src, os.path.join(dst, f))
    os.symlink(os.path.join(ROOT, ".venv"), os.path.join(dst, ".venv"))


def c_tests(tree):
    return sorted(f[:-2] for f in os.listdir(os.path.join(tree, "tests"))
                  if f.startswith("test_") and f.endswith(".c"))


# what the pytest files run: the runner, rps3-study, build/anchor-check,
# and the oracles' shims link build/librps3.so
PY_TARGETS = ["lib", "runner", "study-bin", "build/anchor-check"]


def make(tree, targets):
    """Bring targets up to date in the copy; (ok, the end of stderr)."""
    b = sh(["make", "-s", "-j2"] + list(targets), tree)
    return b.returncode == 0, b.stderr[-2000:]


def check_originals(tree, muts):
    """Every mutation's original text occurs exactly once in its file."""
    bad = []
    for name, path, old, _new, _what in muts:
        f = os.path.join(tree, path)
        n = open(f).read().count(old) if os.path.isfile(f) else 0
        if n != 1:
            bad.append(f"{name}: the original text occurs {n} times in {path}")
    return bad


def py_id(case):
    """A junit testcase as (label file::name, pytest node id), parameters
    dropped: the label is what the page shows, the node runs the test with
    all its parameters."""
    parts = case.get("classname", "").split(".")
    mods = [i for i, x in enumerate(parts) if x.startswith("test_")]
    i = mods[0] if mods else len(parts) - 1
    name = case.get("name").split("[")[0]
    rest = "::".join(parts[i + 1:] + [name])
    return f"{parts[i]}::{rest}", f"tests/{parts[i]}.py::{rest}"


def run_c(tree, t, times=None):
    """Run one C test program (built first); a failure's label or None."""
    ok, _ = make(tree, [f"build/tests/{t}"])
    if not ok:
        return "the build (-Werror)"
    t0 = time.monotonic()
    p = sh([f"build/tests/{t}"], tree, C_TIMEOUT)
    if times is not None:
        times[t] = time.monotonic() - t0
    if p is None:
        return t + " (timeout)"
    return t if p.returncode != 0 else None


def run_pytest(tree, args, stop, times=None, nodes=None):
    """Run pytest on files or node ids; the labels of the failed tests.
    stop: stop at the first failure (-x); times and nodes, when given,
    collect each file's time and the node ids that ran."""
    xml = os.path.join(tree, "junit.xml")
    if os.path.exists(xml):
        os.remove(xml)
    p = sh([VPY, "-m", "pytest", "-q", "-p", "no:cacheprovider"]
           + (["-x"] if stop else []) +
           ["-k", PYTEST_DESELECT, f"--junitxml={xml}"] + list(args), tree,
           PY_TIMEOUT)
    if p is None or not os.path.exists(xml):
        return ["pytest (timeout or crash)"]
    failed = []
    for case in ET.parse(xml).getroot().iter("testcase"):
        label, node = py_id(case)
        if nodes is not None:
            nodes.add(node)
        if times is not None:
            f = label.split("::")[0]
            times[f] = times.get(f, 0.0) + float(case.get("time", 0))
        if case.find("failure") is None and case.find("error") is None:
            continue
        if label not in failed:
            failed.append(label)
    if p.returncode not in (0, 1, 5) and not failed:
        failed.append(f"pytest (exit {p.returncode})")
    return failed


def previous_kills(page):
    """{mutation name: [tests]} from the tables of a page this script
    wrote (a missing page: none)."""
    kills = {}
    if not page or not os.path.exists(page):
        return kills
    for line in open(page):
        cells = line.split("|")
        if len(cells) < 5 or ":" not in cells[1]:
            continue
        name = cells[1].strip().split(":")[0]
        tests = [t.replace(" (timeout)", "")
                 for t in re.findall(r"`([^`]+)`", cells[3])]
        kills[name] = [t for t in tests if t.startswith("test_")]
    return kills


def order(ctests, pyfiles, previous, times, nodes):
    """The plan of one mutation: ("c", program) and ("py", [args])
    steps, the previous killers first (C before pytest), then every other
    C program, then the pytest files; the fastest first in each group.
    A previous pytest killer runs first only if it is among the nodes that
    ran in the unmutated copy (a renamed test is not an error)."""
    fast = lambda x: times.get(x, 0.0)  # noqa: E731
    prev_c = sorted((t for t in previous if t in ctests), key=fast)
    prev_py = []
    for t in previous:
        mod, _, rest = t.partition("::")
        node = f"tests/{mod}.py::{rest}"
        if f"tests/{mod}.py" in pyfiles and node in nodes:
            prev_py.append(node)
    plan = [("c", t) for t in prev_c]
    if prev_py:
        plan.append(("py", prev_py))
    plan += [("c", t) for t in sorted(ctests, key=fast) if t not in prev_c]
    files = sorted(pyfiles, key=lambda f: fast(os.path.basename(f)[:-3]))
    plan.append(("py", files))
    return plan


def run_plan(tree, plan, stop):
    """The labels of the tests of the plan that fail in the tree as it is,
    up to the first one when stop.  The library is built first: a change
    that does not compile is killed by the build."""
    ok, _ = make(tree, ["build/librps3.a"])
    if not ok:
        return ["the build (-Werror)"]
    killed, built_py = [], False
    for kind, what in plan:
        if kind == "c":
            k = run_c(tree, what)
            if k:
                killed.append(k)
        else:
            if not built_py:
                ok, _ = make(tree, PY_TARGETS)
                if not ok:
                    return killed + ["the build (-Werror)"]
                built_py = True
            killed += [k for k in run_pytest(tree, what, stop)
                       if k not in killed]
        if killed and stop:
            break
    return killed


def baseline(tree, ctests):
    """Build everything, run every test of the unmutated copy; the failed
    tests, each test's time (s) and the pytest node ids."""
    ok, err = make(tree, PY_TARGETS + [f"build/tests/{t}" for t in ctests])
    if not ok:
        sys.exit(f"the unmutated tree does not build:\n{err}")
    times, failed, nodes = {}, [], set()
    for t in ctests:
        k = run_c(tree, t, times)
        if k:
            failed.append(k)
    failed += run_pytest(tree, PYTESTS, False, times, nodes)
    return failed, times, nodes


def where(tree, path, old):
    text = open(os.path.join(tree, path)).read()
    return f"{path}:{text[:text.index(old)].count(chr(10)) + 1}"


def table(rows, elapsed, stop):
    out = ["| mutation | where | killed by | survived? |", "|---|---|---|---|"]
    for name, what, loc, killed in rows:
        cell = ", ".join(f"`{k}`" for k in killed) if killed else "nothing"
        out.append(f"| {name}: {what} | `{loc}` | {cell} | "
                   f"{'no' if killed else '**YES**'} |")
    n = sum(1 for r in rows if r[3])
    out.append("")
    out.append(f"{n} of {len(rows)} mutations killed "
               f"({elapsed / 60:.0f} min"
               f"{', stopping at the first kill' if stop else ', every test'}"
               ").")
    return "\n".join(out) + "\n"


HEADER = """# Mutations: which test kills which wrong model

`make mutation` (tests/mutation.py; not part of `make check`) copies the
tracked tree into a temporary directory, checks that every test passes
there, then writes one hand-made mutation of `src/` at a time into the
copy and runs the tests until one fails: every C test program and the
pytest files that compare the library with truths it did not compute
(SymPy, MuJoCo, the generated anchor, the paper's tables, the golden file,
the accuracy study's long-double reference).  Each row names the test that
killed the mutation: the first to fail, in an order that puts the test
named here by the last run first, then the C test programs, then pytest
(only what a test needs is rebuilt before it runs).  A mutation that no
test kills has run the whole suite; every mutation must be killed (the
script exits 1 when one survives).  Tests named `test_x` are the C
programs `tests/test_x.c`; `file::test` are pytest tests.  The table below
is the output of the last run.

One test per row says that the mutation is caught, not by what alone:
`tests/mutation.py --all` runs every test on every mutation and names them
all.  A mutation caught only by oracles that read the model's inputs
(`test_study_ref`, `test_oracles`, `test_anchor`, `test_trans`,
`test_jacobian`) is one the library's own identities cannot see: the
energy balance holds for any link inertia, Lagrange and Newton-Euler read
the same derived fields, and a Newton solve converges with a Jacobian
0.1 % off.

"""


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("-o", "--output", help="write the markdown page here; "
                    "the tests it names run first")
    ap.add_argument("--all", action="store_true",
                    help="run every test on every mutation, not only up to "
                    "the first that kills it")
    ap.add_argument("-k", "--keep", action="store_true",
                    help="keep the temporary copy (its path is printed)")
    ap.add_argument("names", nargs="*", help="mutations to run (default all)")
    a = ap.parse_args()
    unknown = set(a.names) - {m[0] for m in MUTATIONS}
    if unknown:
        sys.exit(f"unknown mutations: {', '.join(sorted(unknown))}")
    bad = check_originals(ROOT, MUTATIONS)
    if bad:
        sys.exit("\n".join(bad))
    muts = [m for m in MUTATIONS if not a.names or m[0] in a.names]
    previous = previous_kills(a.output)
    stop = not a.all
    t0 = time.monotonic()
    tree = tempfile.mkdtemp(prefix="rps3-mutation-")
    rows = []
    try:
        copy_tree(tree)
        ctests = c_tests(tree)
        base, times, nodes = baseline(tree, ctests)
        if base:
            sys.exit(f"the unmutated tree fails: {', '.join(base)}")
        print(f"unmutated tree passes ({time.monotonic() - t0:.0f} s)",
              flush=True)
        for name, path, old, new, what in muts:
            p = os.path.join(tree, path)
            src = open(p).read()
            if src.count(old) != 1:
                sys.exit(f"{name}: the original text is not in {path} once")
            loc = where(tree, path, old)
            plan = order(ctests, PYTESTS,
                         previous.get(name, []) if stop else [], times,
                         nodes)
            t1 = time.monotonic()
            with open(p, "w") as fh:
                fh.write(src.replace(old, new))
            try:
                killed = run_plan(tree, plan, stop)
            finally:
                with open(p, "w") as fh:
                    fh.write(src)
            rows.append((name, what, loc, killed))
            print(f"{name} ({loc}): "
                  f"{', '.join(killed) if killed else 'SURVIVES'} "
                  f"({time.monotonic() - t1:.0f} s)", flush=True)
    finally:
        if a.keep:
            print(f"kept {tree}")
        else:
            shutil.rmtree(tree, ignore_errors=True)
    page = table(rows, time.monotonic() - t0, stop)
    if a.output:
        with open(a.output, "w") as fh:
            fh.write(HEADER + page)
    else:
        print(page)
    sys.exit(1 if any(not r[3] for r in rows) else 0)


if __name__ == "__main__":
    main()
