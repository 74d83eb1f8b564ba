"""The free body's rotation on SO(3) by a moving chart: the design study of a free base on SE(3), run
on today's Euler-angle joints with the chart changed between C++ steps.

hovi's floating base turns on yaw (z), pitch (y) and roll (x) joints: a chart of SO(3) that is
singular at pitch +-90 deg (the map E(theta) from the Euler rates to the body's angular velocity
loses rank). A chart re-centred at every step never gets near it: step k is taken in the coordinates
about the body's own attitude R^k, R = R^k Rz(a) Ry(b) Rx(c) with theta = (a, b, c) = 0 at the step's
start, so a step turns the chart by omega dt only. Between steps the momentum moves to the chart
about R^{k+1} by the cotangent lift of the change of coordinates, p_new = E(0)^T E(theta_end)^-T p_old.

Two steps are compared:

- 'chart': the product's Galerkin step of order 2s in the chart, held fixed while the step is taken.
  It keeps the order and never meets the singularity, but it is not symplectic as a whole (the chart
  depends on the state) and the world angular momentum drifts at O(dt^2s).
- 'group': the variational integrator on the group. Its discrete Lagrangian is L_d(R0, R1), the chart
  step's about R0; its first DEL equation p^k = -D1 L_d moves the chart's centre with R0, which
  adds to the chart step's first residual the action's derivative along the path's motion in the
  fixed chart (``ChartStepper``; the derivation: bench/README.md). It is left-invariant, so Noether's theorem
  keeps the world angular momentum to round-off.

Measured: the order against the rigid-body equations on quaternions integrated by DOP853 at rtol
1e-13 (written here, apart from hovi), attitude error at T = 1 s, for s = 1, 2, 3; and the
Dzhanibekov flip (principal moments 1, 2, 3, spun at 2 rad/s about the intermediate axis with 0.05
rad/s about the others, zero gravity): the world angular momentum and the energy at every step, and
the Euler-angle joints from the same state in one chart. The group's residual term is taken by
differences here (the study's floor, about 1e-12); the product's free joint will compute it exactly
in C++. Results: bench/results/se3_chart.json; bench/README.md, "Free bodies on SO(3): the moving
chart"."""
from __future__ import annotations

import time

import numpy as np
from scipy.integrate import solve_ivp

import hovi
from common import study_parser, write_json

INERTIA = np.array([1.0, 2.0, 3.0])  # principal moments (kg m^2) of the asymmetric body


def spinning_body() -> hovi.Model:
    """A rigid body of principal moments INERTIA (kg m^2) turning about a fixed point on the Euler-angle
    joints (yaw z, pitch y, roll x: the rotation of hovi's floating base), zero gravity. Its translation
    decouples (the centre of mass is the fixed point) and is left out."""
    model = hovi.Model()
    model.add_body("yaw", None, "revolute", axis=(0, 0, 1))
    model.add_body("pitch", "yaw", "revolute", axis=(0, 1, 0))
    model.add_body("body", "pitch", "revolute", axis=(1, 0, 0), mass=1.0, inertia=np.diag(INERTIA))
    model.gravity = np.zeros(3)
    return model


def rotation(axis: int, angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    R = np.eye(3)
    R[i, i], R[i, j], R[j, i], R[j, j] = c, -s, s, c
    return R


def euler_rotation(theta: np.ndarray) -> np.ndarray:
    """Rz(a) Ry(b) Rx(c) of theta = (a, b, c), the base's yaw, pitch and roll."""
    return rotation(2, theta[0]) @ rotation(1, theta[1]) @ rotation(0, theta[2])


def rates_to_omega(theta: np.ndarray) -> np.ndarray:
    """E(theta) (3, 3): the body's angular velocity (its own frame) from the Euler rates."""
    Rx, Ry = rotation(0, theta[2]), rotation(1, theta[1])
    return np.column_stack([Rx.T @ Ry.T @ [0.0, 0.0, 1.0], Rx.T @ [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]])


E0 = rates_to_omega(np.zeros(3))  # E(0): the Euler rates at theta = 0 are the body's (z, y, x) rates


def centre_shift(theta: np.ndarray) -> np.ndarray:
    """A(theta) = E(theta)^-1 R(theta)^T E(0): how the coordinates theta (in a chart about R0 phi(delta))
    of a fixed attitude move in the chart about R0 as the centre moves by delta, at delta = 0."""
    return np.linalg.solve(rates_to_omega(theta), euler_rotation(theta).T @ E0)


def derivative(f, h: float):
    """f'(0) by the fourth-order central difference of step h."""
    return (8 * (f(h) - f(-h)) - (f(2 * h) - f(-2 * h))) / (12 * h)


class ChartStepper:
    """The spinning body stepped in a chart re-centred at every step (module docstring): the attitude R
    and the momentum p (3,) in the chart about R (the Euler momenta at theta = 0).

    group=False: the product's step in the chart (fixed while it is taken) and the momentum carried to
    the next chart. group=True: the variational integrator on the group, L_d(R0, R1) = the chart step's
    discrete Lagrangian in the chart about R0, whose first DEL equation, p^k = -D1 L_d, takes the
    chart's centre along with R0: the residual of the chart step gains

        C = sum_a w_a dt [dL/dq(a) . Y(a) + dL/dqdot(a) . Ydot(a)],
        Y(t) = A(theta(t)) - l_0(t) 1 - l_s(t) A(theta^s),

    the action's derivative along how the path moves in the fixed chart when its centre moves with
    the start (A: ``centre_shift``; l_0, l_s the Lagrange polynomials of the step's ends). The study
    solves it by Newton's method on differences in Python; the product's free joint will do it in C++."""

    def __init__(self, s: int, dt: float, group: bool) -> None:
        self.model = spinning_body()
        self.integ = hovi.Integrator(self.model, s=s, dt=dt, step_tol=1e-15)
        self.group = group

    def start(self, R: np.ndarray, omega: np.ndarray) -> tuple:
        return R.copy(), self.integ.momentum(np.zeros(3), np.linalg.solve(E0, omega))

    def _centre_term(self, cp: np.ndarray) -> np.ndarray:
        s, dt, D, w = self.integ.s, self.integ.dt, self.integ.differentiation_matrix, self.integ.weights
        rates = D @ cp / dt
        end = centre_shift(cp[s])
        C = np.zeros(3)
        for a in range(s + 1):
            th, thd = cp[a], rates[a]
            Y = centre_shift(th) - (a == 0) * np.eye(3) - (a == s) * end
            Ydot = derivative(lambda h: centre_shift(th + h * thd), 1e-3) - (D[a, 0] * np.eye(3) + D[a, s] * end) / dt
            Lq = np.array([derivative(lambda h: self.model.kinetic_energy(th + h * e, thd), 1e-3) for e in np.eye(3)])
            C += w[a] * dt * (Lq @ Y + (self.model.mass_matrix(th) @ thd) @ Ydot)
        return C

    def _residual(self, x: np.ndarray, p: np.ndarray) -> tuple:
        cp = np.vstack([np.zeros(3), x.reshape(-1, 3)])
        r, p_next = self.integ.del_residual(cp, p)
        r = r.copy()
        r[0] += self._centre_term(cp)
        return r.ravel(), p_next

    def step(self, R: np.ndarray, p: np.ndarray) -> tuple:
        _, p_next, info = self.integ.step(np.zeros(3), p)
        x = info.control_points[1:].ravel()
        if self.group:  # Newton on the corrected residual from the chart step's solution
            for _ in range(20):
                r, p_next = self._residual(x, p)
                J = np.column_stack([(self._residual(x + 1e-6 * e, p)[0] - self._residual(x - 1e-6 * e, p)[0]) / 2e-6
                                     for e in np.eye(len(x))])
                dx = np.linalg.solve(J, -r)
                x = x + dx
                if np.abs(dx).max() <= 1e-15 * (1 + np.abs(x).max()):
                    break
            p_next = self._residual(x, p)[1]
        theta = x[-3:]
        return R @ euler_rotation(theta), E0.T @ np.linalg.solve(rates_to_omega(theta).T, p_next)

    def angular_momentum(self, R: np.ndarray, p: np.ndarray) -> np.ndarray:
        """The world angular momentum of the discrete momentum p: Noether's momentum map, R E(0)^-T p."""
        return R @ np.linalg.solve(E0.T, p)

    def energy(self, p: np.ndarray) -> float:
        return float(self.integ.energy(np.zeros(3), p))


def reference(R0: np.ndarray, omega0: np.ndarray, T: float) -> np.ndarray:
    """R at T of the rigid-body equations on a unit quaternion (w, x, y, z), DOP853 at rtol 1e-13."""
    w = np.sqrt(1 + np.trace(R0)) / 2
    q0 = np.array([w, (R0[2, 1] - R0[1, 2]) / (4 * w), (R0[0, 2] - R0[2, 0]) / (4 * w), (R0[1, 0] - R0[0, 1]) / (4 * w)])

    def rhs(t, y):
        qw, qv, om = y[0], y[1:4], y[4:7]
        return np.concatenate([0.5 * np.concatenate([[-qv @ om], qw * om + np.cross(qv, om)]),
                               np.cross(INERTIA * om, om) / INERTIA])

    y = solve_ivp(rhs, (0.0, T), np.concatenate([q0, omega0]), method="DOP853", rtol=1e-13, atol=1e-14).y[:4, -1]
    qw, a, b, c = y / np.linalg.norm(y)
    return np.array([[1 - 2 * (b * b + c * c), 2 * (a * b - c * qw), 2 * (a * c + b * qw)],
                     [2 * (a * b + c * qw), 1 - 2 * (a * a + c * c), 2 * (b * c - a * qw)],
                     [2 * (a * c - b * qw), 2 * (b * c + a * qw), 1 - 2 * (a * a + b * b)]])


def order_study(orders, dts, T=1.0) -> list:
    R0, omega0 = euler_rotation(np.array([0.3, -0.4, 0.5])), np.array([1.0, -2.0, 1.5])
    R_ref = reference(R0, omega0, T)
    rows = []
    for group in (False, True):
        for s in orders:
            errors = []
            for dt in dts:
                st = ChartStepper(s, dt, group)
                R, p = st.start(R0, omega0)
                for _ in range(int(round(T / dt))):
                    R, p = st.step(R, p)
                errors.append(float(np.abs(R - R_ref).max()))
            slopes = np.diff(np.log(errors)) / np.diff(np.log(dts))
            above = [k for k in range(len(slopes)) if errors[k + 1] > 1e-10]  # above the floor of the reference
            order = float(slopes[above[-1]] if above else slopes[0])
            rows.append({"group": group, "s": s, "dt": list(dts), "error": errors, "order": order})
            print(f"{'group' if group else 'chart'} s = {s}: attitude errors {', '.join(f'{e:.2e}' for e in errors)}; "
                  f"observed order {order:.2f} (2s = {2 * s})", flush=True)
    return rows


def flip_study(orders, dt: float, T: float) -> list:
    """The Dzhanibekov flip: spin about the intermediate axis; momentum and energy along T."""
    R0, omega0 = np.eye(3), np.array([0.05, 2.0, 0.05])
    rows = []
    for group in (False, True):
        for s in orders:
            st = ChartStepper(s, dt, group)
            R, p = st.start(R0, omega0)
            L0, energy0 = st.angular_momentum(R, p), st.energy(p)
            dL = dE = 0.0
            flips, sign, K, t0 = 0, 1.0, int(round(T / dt)), time.perf_counter()
            for k in range(K):
                R, p = st.step(R, p)
                dL = max(dL, np.abs(st.angular_momentum(R, p) - L0).max() / np.abs(L0).max())
                dE = max(dE, abs(st.energy(p) - energy0) / energy0)
                omega_y = (E0 @ st.integ.velocity(np.zeros(3), p))[1]
                if np.sign(omega_y) != sign:
                    flips, sign = flips + 1, np.sign(omega_y)
            rows.append({"group": group, "s": s, "dt": dt, "T": T, "flips": flips, "angular_momentum_error": dL,
                         "energy_error": dE, "seconds": time.perf_counter() - t0})
            print(f"flip, {'group' if group else 'chart'} s = {s}, dt = {dt}: {flips} flips in {T:g} s; world angular "
                  f"momentum kept to {dL:.1e} (relative), energy to {dE:.1e}", flush=True)
    integ = hovi.Integrator(spinning_body(), s=1, dt=dt)  # the Euler-angle joints from the same state, one chart
    traj = integ.rollout(np.zeros(3), int(round(T / dt)), qdot0=np.linalg.solve(E0, omega0), raise_on_failure=False)
    L = np.array([euler_rotation(q) @ (INERTIA * (rates_to_omega(q) @ qd)) for q, qd in zip(traj.q, traj.qdot)])
    euler = {"steps": traj.steps, "of": int(round(T / dt)), "status": traj.status[-1],
             "pitch_max_deg": float(np.degrees(np.abs(traj.q[:, 1]).max())),
             "angular_momentum_error": float(np.abs(L - L[0]).max() / np.abs(L[0]).max()),
             "energy_error": float(np.abs(traj.energy - traj.energy[0]).max() / traj.energy[0])}
    print(f"the Euler-angle joints (s = 1, one chart) from the same state: {traj.steps} of {euler['of']} steps "
          f"({traj.status[-1]}), pitch up to {euler['pitch_max_deg']:.1f} deg; angular momentum kept to "
          f"{euler['angular_momentum_error']:.1e}, energy to {euler['energy_error']:.1e}", flush=True)
    rows.append({"euler_joints": euler})
    return rows


def main() -> None:
    args = study_parser(__doc__, "orders 1 and 2 on two step sizes, 5 s of the flip").parse_args()
    orders = (1, 2) if args.quick else (1, 2, 3)
    dts = (0.05, 0.025) if args.quick else (0.1, 0.05, 0.025, 0.0125)
    order = order_study(orders, dts)
    flip = flip_study(orders, 0.02, 5.0 if args.quick else 20.0)
    write_json("se3_chart_quick.json" if args.quick else "se3_chart.json", {"order": order, "flip": flip})


if __name__ == "__main__":
    main()
