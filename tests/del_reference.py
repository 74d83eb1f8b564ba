"""An independent evaluation of the DEL equations (paper eq. DEL_general) for the tests.

The discrete Lagrangian L_d = sum_a w^a dt (K - V)(q^a, q̇^a) is assembled from the model's
energies (checked against Pinocchio in test_model_vs_pinocchio.py) and differentiated by a
fourth-order central difference; the discrete forces F_d^a = w^a dt Q(q^a, q̇^a, u^a) are built
from the documented force laws, with body wrenches mapped to joint space through body Jacobians
read off `spatial_velocities` (v̄_b = J_b q̇ is linear in q̇).
"""
import numpy as np

import hovi


def fd4(f, x, h):
    """Gradient of scalar f at array x by the fourth-order central difference."""
    g = np.zeros_like(x)
    for idx in np.ndindex(x.shape):
        e = np.zeros_like(x)
        e[idx] = h
        g[idx] = (-f(x + 2 * e) + 8 * f(x + e) - 8 * f(x - e) + f(x - 2 * e)) / (12 * h)
    return g


def hat(w):
    return np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])


class ForcedScene:
    """A model with every kind of force element, and their laws re-implemented in numpy; and joint
    armature on every other joint (it enters L_d through model.kinetic_energy)."""

    def __init__(self, model, rng):
        self.model = model
        n = model.n
        self.k = rng.uniform(0.5, 2.0, n)
        self.rest = rng.uniform(-0.5, 0.5, n)
        self.c = rng.uniform(0.1, 0.5, n)
        for j in range(n):
            model.add_spring(j, self.k[j], self.rest[j])
            model.add_damper(j, self.c[j])
        self.gear = {}
        for j in range(0, n, 2):
            self.gear[model.add_actuator(j, gear=1.5)] = j
        self.thrust = model.add_control()
        self.wrenches = []
        bodies = [n - 1, n // 2]
        # world-frame force at a body point, constant
        f, tau, r = rng.normal(size=3), rng.normal(size=3), rng.normal(size=3) * 0.1
        model.add_point_wrench(bodies[0], force=f, torque=tau, point=r, frame="world")
        self.wrenches.append(("world", bodies[0], f, tau, r, None))
        # body-frame (follower) force scaled by a control
        f, tau, r = rng.normal(size=3), rng.normal(size=3), rng.normal(size=3) * 0.1
        model.add_point_wrench(bodies[1], force=f, torque=tau, point=r, frame="body", control=self.thrust)
        self.wrenches.append(("body", bodies[1], f, tau, r, self.thrust))
        # drag on two bodies
        self.drag = [(bodies[0], 0.7, 0.2), (bodies[1], 0.3, 0.05)]
        for b, lin, ang in self.drag:
            model.add_drag(b, linear=lin, angular=ang)
        self.armature = np.where(np.arange(n) % 2 == 0, rng.uniform(0.05, 0.2, n), 0.0)
        model.armature = self.armature

    def generalized_force(self, q, qd, u):
        model, n = self.model, self.model.n
        Q = -self.k * (q - self.rest) - self.c * qd
        for ctrl, j in self.gear.items():
            Q[j] += 1.5 * u[ctrl]
        X = model.joint_placements(q)          # joint frames
        G = model.body_poses(q)                # COM frames
        V = model.spatial_velocities(q, qd)    # (angular, linear at the world origin)
        J = np.stack([model.spatial_velocities(q, np.eye(n)[j]) for j in range(n)], axis=-1)  # (n, 6, n)
        for kind, b, f, tau, r, ctrl in self.wrenches:
            R, x = X[b][:3, :3], X[b][:3, :3] @ r + X[b][:3, 3]
            fw, tw = (f, tau) if kind == "world" else (R @ f, R @ tau)
            scale = 1.0 if ctrl is None else u[ctrl]
            F = scale * np.concatenate([tw + np.cross(x, fw), fw])
            Q += J[b].T @ F
        for b, lin, ang in self.drag:
            w, v0 = V[b][:3], V[b][3:]
            p = G[b][:3, 3]
            v_com = v0 + np.cross(w, p)
            fw, tw = -lin * v_com, -ang * w
            Q += J[b].T @ np.concatenate([tw + np.cross(p, fw), fw])
        return Q


def reference_del(integ: hovi.Integrator, qc, p, u=None, scene=None, h=1e-4):
    """(r, p_next) by finite differences of L_d plus the discrete forces."""
    model, s = integ.model, integ.s
    w, b, dt = integ.weights, integ.differentiation_matrix, integ.dt

    def Ld(x):
        qd = b @ x / dt
        return sum(w[a] * dt * (model.kinetic_energy(x[a], qd[a]) - model.potential_energy(x[a])) for a in range(s + 1))

    D = fd4(Ld, qc, h)
    if scene is not None:
        # potential_energy includes the springs, whose force the scene adds again: remove it.
        qd = b @ qc / dt
        for a in range(s + 1):
            ua = np.zeros(model.n_controls) if u is None else u[a]
            D[a] += w[a] * dt * (scene.generalized_force(qc[a], qd[a], ua) + scene.k * (qc[a] - scene.rest))
    r = D[:s].copy()
    r[0] += p
    return r, D[s]


def fd_jacobian(integ, qc, p, u=None, h=1e-6):
    """Dense Jacobian of r (flattened (s, n)) with respect to q^{k,1..s} by central differences."""
    s, n = integ.s, integ.n

    def R(x):
        q2 = qc.copy()
        q2[1:] = x.reshape(s, n)
        return integ.del_residual(q2, p, u)[0].ravel()

    x0 = qc[1:].ravel()
    J = np.zeros((s * n, s * n))
    for j in range(s * n):
        e = np.zeros(s * n)
        e[j] = h
        J[:, j] = (-R(x0 + 2 * e) + 8 * R(x0 + e) - 8 * R(x0 - e) + R(x0 - 2 * e)) / (12 * h)
    return J
