"""
hovi C++ core: higher-order variational integrators for robots
"""
from __future__ import annotations
import collections.abc
import numpy
import numpy.typing
import os
import typing
from . import trajopt
from . import control
__all__: list[str] = ['ContactModel', 'Integrator', 'Linearizer', 'Model', 'ModelError', 'Terrain', 'URDFError', 'body_point_kinematics', 'control', 'lagrange_basis', 'march', 'pendulum', 'real_array', 'trajopt']
class ModelError(ValueError):
    """
    An invalid model or model input (a ValueError): a bad body, joint, force or constraint, an unknown joint or body name, or a call on an Integrator or Linearizer whose model changed after it was made.
    """
class URDFError(ModelError):
    """
    A URDF that cannot be loaded (a ModelError); the message names the link or joint at fault.
    """
class Model:
    """
    A tree of rigid bodies joined by 1-DoF revolute or prismatic joints (parents before children).
    
    Body frames sit at each body's centre of mass with the joint frame's orientation (docs/paper.md C-3);
    ``joint_placements`` gives the joint frames (Pinocchio's ``oMi``). Twists are ordered
    (angular, linear) as in the paper. Build one with ``Model.from_urdf``, ``hovi.models``, or
    ``Model()`` followed by ``add_body``.
    """
    @staticmethod
    def from_urdf(source: str | os.PathLike[str], base: str = 'fixed', expand_joints: bool = False, planar_normal: numpy.typing.ArrayLike = (0.0, 1.0, 0.0)) -> Model:
        """
        Load a URDF file (source: a path) or XML string (source: the text); returns a Model.
        
        base: 'fixed' (root link welded to the world), 'floating' (the free joint, as Pinocchio's free
        flyer: q = (x, y, z, qx, qy, qz, qw, joints...), nq = n + 1, the base's velocity (linear, angular) in
        its own frame; integrated on the group, no singular attitude), 'euler' (6 joints x, y, z, yaw, pitch,
        roll: Z-Y-X Euler angles, singular at pitch = ±pi/2; the paper's robots) or 'planar' (2 prismatic + 1
        revolute about planar_normal (3,), default the x-z plane). expand_joints: expand URDF floating/planar joints the
        same way instead of raising. Fixed joints are merged (inertia lumped into the parent);
        continuous joints become revolute joints without limits; mimic joints are kept as metadata
        (integrated as independent joints). Raises hovi.URDFError naming the link or joint at fault. A link
        whose rotational inertia violates the triangle inequality (no rigid body has it; add_body refuses it)
        is loaded as given with a UserWarning naming the link (URDF files in use carry such inertias).
        """
    def __copy__(self) -> Model:
        """
        The same as copy().
        """
    def __deepcopy__(self, memo: typing.Any) -> Model:
        """
        The same as copy().
        """
    def __getstate__(self) -> bytes:
        ...
    def __init__(self) -> None:
        """
        An empty model (add bodies with add_body).
        """
    def __repr__(self) -> str:
        ...
    def __setstate__(self, arg0: bytes) -> None:
        ...
    def add_actuator(self, joint: int | str, gear: typing.SupportsFloat | typing.SupportsIndex = 1.0) -> int:
        """
        A new control input u[k] acting on the joint as Q += gear u[k]; returns k.
        """
    def add_body(self, name: str, parent: int | str | None, joint_type: str = 'revolute', axis: numpy.typing.ArrayLike = (0.0, 0.0, 1.0), placement: numpy.typing.ArrayLike | None = None, mass: typing.SupportsFloat | typing.SupportsIndex = 0.0, com: numpy.typing.ArrayLike = (0.0, 0.0, 0.0), inertia: numpy.typing.ArrayLike = ..., joint_name: str = '', lower: typing.SupportsFloat | typing.SupportsIndex = ..., upper: typing.SupportsFloat | typing.SupportsIndex = ...) -> int:
        """
        Append a body; returns its index. parent: index or body name, None for the world. joint_type:
        'revolute', 'prismatic' or 'free' (the first body only: the free joint, as URDF base='floating' gives;
        six joints, the body the last, q as Pinocchio's free flyer).
        placement: (4, 4) pose of the joint frame in the parent's joint frame at q = 0 (default identity).
        axis: (3,) joint axis in the joint frame. com: (3,) centre of mass in the joint frame. inertia:
        (3, 3) rotational inertia about the COM (joint-frame axes): symmetric, no negative principal moment, and
        none above the sum of the other two (the triangle inequality, e.g. izz <= ixx + iyy). lower, upper: joint
        position limits. Raises hovi.ModelError naming the body on invalid input.
        """
    def add_control(self) -> int:
        """
        A new control input with no joint actuation (for control-scaled wrenches); returns its index.
        """
    def add_damper(self, joint: int | str, damping: typing.SupportsFloat | typing.SupportsIndex) -> None:
        """
        Linear joint damper Q = -damping q̇ on a joint (index or name); ModelError naming the joint unless damping is finite and non-negative.
        """
    def add_drag(self, body: int | str, linear: typing.SupportsFloat | typing.SupportsIndex, angular: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> None:
        """
        Linear drag on a body (index or name) at its centre of mass, in the body frame: F = -(angular w, linear v_com); ModelError unless both coefficients are finite and non-negative.
        """
    def add_joint_coupling(self, coefficients: numpy.typing.ArrayLike, offset: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> None:
        """
        A linear coupling of joint coordinates: coefficients (n,) . q = offset (1 equation).
        """
    def add_loop_constraint(self, body1: int | str, point1: numpy.typing.ArrayLike, body2: int | str, point2: numpy.typing.ArrayLike, axes: str = 'xyz') -> None:
        """
        Make point1 (3,) of body1 and point2 (3,) of body2 (each in its body's joint frame) coincide: a loop closure (the rows of `axes`).
        """
    def add_orientation_constraint(self, body: int | str, rotation: numpy.typing.ArrayLike) -> None:
        """
        Hold a body's orientation at the world rotation `rotation` (3, 3) (3 equations).
        """
    def add_point_constraint(self, body: int | str, point: numpy.typing.ArrayLike | None = None, target: numpy.typing.ArrayLike | None = None, axes: str = 'xyz') -> None:
        """
        Hold a point (3,) of a body (in its joint frame; default the centre of mass) at a world point target (3,):
        h = P (x(q) - target) with P the rows of `axes` ('xyz', or e.g. 'xz' for planar use).
        """
    def add_point_wrench(self, body: int | str, force: numpy.typing.ArrayLike = (0.0, 0.0, 0.0), torque: numpy.typing.ArrayLike = (0.0, 0.0, 0.0), point: numpy.typing.ArrayLike | None = None, frame: str = 'world', control: int | None = None) -> None:
        """
        A force (3,) (and torque (3,)) on a body (index or name), applied at `point` (3,) (in the body's
        joint frame; default: its centre of mass). frame='world': components fixed in the world; frame='body': components turn with the
        body (a follower force). control=k scales the wrench by the control input u[k].
        """
    def add_spring(self, joint: int | str, stiffness: typing.SupportsFloat | typing.SupportsIndex, rest: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> None:
        """
        Linear joint spring Q = -stiffness (q - rest) on a joint (index or name); adds 1/2 k (q - rest)^2 to V. stiffness and rest finite (a negative stiffness is allowed: still conservative); ModelError otherwise.
        """
    def add_visual(self, body: int | str | None, shape: str, size: numpy.typing.ArrayLike | None = None, origin: numpy.typing.ArrayLike | None = None, rgba: numpy.typing.ArrayLike | None = None, filename: str = '', scale: numpy.typing.ArrayLike = (1.0, 1.0, 1.0), link: str = '') -> None:
        """
        Attach a visual shape to a body (index or name; None = the world). shape: 'box' (size: x, y, z),
        'cylinder' (size: radius, length; axis z), 'sphere' (size: radius) or 'mesh' (filename, scale).
        origin: (4, 4) pose in the body's joint frame (default identity); rgba: (4,) in [0, 1].
        Metadata only: the dynamics and existing integrators are unaffected. Raises ModelError on bad input.
        """
    def body_index(self, name: str) -> int:
        """
        Index of the body (link) called `name`; KeyError if there is none.
        """
    def body_poses(self, q: numpy.typing.ArrayLike) -> numpy.typing.NDArray[numpy.float64]:
        """
        q: (n,) joint positions; returns (n, 4, 4) world poses g_i of the body frames (at each centre of mass).
        """
    def constraint_jacobian(self, q: numpy.typing.ArrayLike) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        """
        q: (nq,); returns Dh(q), (n_constraints, n) (a free base: in its velocity's coordinates).
        """
    def constraint_values(self, q: numpy.typing.ArrayLike) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        q: (nq,); returns h(q), (n_constraints,), of all constraints stacked.
        """
    def copy(self) -> Model:
        """
        An independent copy (later changes to either do not affect the other).
        """
    def difference(self, q0: numpy.typing.ArrayLike, q1: numpy.typing.ArrayLike) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        q1 ⊖ q0 (n,): the velocity v with integrate(q0, v) = q1 (Pinocchio's difference; a free base by the logarithm of SE(3)).
        """
    def energy(self, q: numpy.typing.ArrayLike, qdot: numpy.typing.ArrayLike) -> float:
        """
        Total mechanical energy K + V; q, qdot: (n,); returns a float.
        """
    def force_jacobians(self, q: numpy.typing.ArrayLike, qdot: numpy.typing.ArrayLike, u: numpy.typing.ArrayLike | None = None) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"], typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"], typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"], typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]]:
        """
        q: (nq,), qdot: (n,), u: (m,) (default zero); returns (Q (n,), dQ/dq (n, n), dQ/dq̇ (n, n), dQ/du (n, m))
        of the generalized non-conservative force: joint springs, dampers and actuators plus the body wrench
        elements mapped to joint space (gravity not included). A free base: in its velocity's coordinates,
        dQ/dq by a tangent δ of q (q ⊕ δ).
        """
    def forward_dynamics(self, q: numpy.typing.ArrayLike, qdot: numpy.typing.ArrayLike, tau: numpy.typing.ArrayLike | None = None) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        q, qdot, tau: (n,) (tau default zero); returns q̈ = FD(q, q̇, tau), (n,), by the articulated-body algorithm (O(n)), gravity and the model's forces included.
        """
    def gravity_hessian(self, q: numpy.typing.ArrayLike) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        """
        Algorithm 3, O(n^2). q: (n,); returns d2V_g/dq2 (n, n) of the gravitational potential (springs not included).
        """
    def integrate(self, q: numpy.typing.ArrayLike, v: numpy.typing.ArrayLike) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        q ⊕ v (nq,): the configuration reached from q (nq,) along the velocity v (n,) in unit time; a free base moves along its body twist (Pinocchio's integrate), the other joints by q + v.
        """
    def inverse_dynamics(self, q: numpy.typing.ArrayLike, qdot: numpy.typing.ArrayLike, qddot: numpy.typing.ArrayLike) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        q, qdot, qddot: (n,); returns tau = M(q) q̈ + C(q, q̇) q̇ + G(q), (n,), by recursive Newton-Euler (O(n)).
        """
    def joint_index(self, name: str) -> int:
        """
        Index of the joint called `name`; KeyError if there is none.
        """
    def joint_placements(self, q: numpy.typing.ArrayLike) -> numpy.typing.NDArray[numpy.float64]:
        """
        q: (n,) joint positions; returns (n, 4, 4) world poses of the joint frames (Pinocchio's oMi).
        """
    def kinetic_energy(self, q: numpy.typing.ArrayLike, qdot: numpy.typing.ArrayLike) -> float:
        """
        Kinetic energy K = 1/2 q̇^T M(q) q̇ (joint armature included); q, qdot: (n,); returns a float.
        """
    def kinetic_energy_hessians(self, q: numpy.typing.ArrayLike, qdot: numpy.typing.ArrayLike) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"], typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"], typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"], typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]]:
        """
        Algorithm 2, O(n^2). q, qdot: (n,); returns (Kvv, Kvq, Kqv, Kqq), each (n, n), with Kvv = d2K/dq̇2, Kvq[i, j] = d/dq_j (dK/dq̇_i),
        Kqv[i, j] = d/dq̇_j (dK/dq_i) = Kvq.T, Kqq = d2K/dq2.
        """
    def mass_matrix(self, q: numpy.typing.ArrayLike) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        """
        q: (nq,); returns the joint-space mass matrix M(q), (n, n), the joint armature on its diagonal (a free base: in its velocity's coordinates).
        """
    def neutral(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        The zero configuration (nq,): the joints at 0, a free base at the origin with the identity attitude.
        """
    def potential_energy(self, q: numpy.typing.ArrayLike) -> float:
        """
        q: (n,); the gravitational potential -sum m_i g^T p_i (p_i the centre of mass) plus the springs' 1/2 k (q - rest)^2.
        """
    def scale_mass(self, body: int | str, factor: float) -> None:
        """
        Multiply a body's (index or name) mass and rotational inertia by factor > 0 (its density; shape and
        centre of mass kept): a plant that differs from the model a controller was made on
        (``model.copy()`` first). Raises hovi.ModelError for an unknown body or a factor outside
        [1e-12, 1e12], and ValueError for a factor that is not a number.
        """
    def set_armature(self, joint: int | str, armature: typing.SupportsFloat | typing.SupportsIndex) -> None:
        """
        Joint armature (rotor inertia reflected through the transmission, Pinocchio's model.armature,
        MuJoCo's joint armature) on a joint (index or name): adds 1/2 armature q̇_joint^2 to the kinetic
        energy, i.e. armature to the joint's diagonal entry of the mass matrix. Replaces the joint's
        previous value. Raises hovi.ModelError unless armature is finite and non-negative.
        """
    def spatial_twists(self, q: numpy.typing.ArrayLike) -> numpy.typing.NDArray[numpy.float64]:
        """
        q: (n,) joint positions; returns (n, 6) spatial joint twists S̄_i = Ad_{g_i} S_i, (angular, linear).
        """
    def spatial_velocities(self, q: numpy.typing.ArrayLike, qdot: numpy.typing.ArrayLike) -> numpy.typing.NDArray[numpy.float64]:
        """
        q, qdot: (n,); returns (n, 6) spatial velocities v̄_i = (ġ g^{-1})^∨, (angular, linear).
        """
    def summary(self) -> str:
        """
        A table of bodies and joints.
        """
    @property
    def actuation(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        """
        (n, m) actuation map B: joint forces Q += B u.
        """
    @property
    def armature(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        (n,) joint armature per joint (see set_armature; 0 where none). Set it whole with an (n,) array of finite, non-negative values.
        """
    @armature.setter
    def armature(self, arg1: numpy.typing.ArrayLike) -> None:
        ...
    @property
    def body_names(self) -> list[str]:
        """
        (n,) list of the body (link) names, body i moved by joint i.
        """
    @property
    def damping(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        (n,) URDF <dynamics damping> per joint (metadata; see add_damper for a damper).
        """
    @property
    def effort_limits(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        (n,) joint effort limits (URDF metadata, the default control bounds of trajopt; inf where none).
        """
    @property
    def free_base(self) -> bool:
        """
        True if joints 0-5 are the free joint (URDF base='floating'): q as Pinocchio's free flyer.
        """
    @property
    def friction(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        (n,) URDF <dynamics friction> per joint (metadata).
        """
    @property
    def gravity(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        """
        Gravity in the world frame (default (0, 0, -9.81)).
        """
    @gravity.setter
    def gravity(self, arg1: numpy.typing.ArrayLike) -> None:
        ...
    @property
    def joint_damping(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        (n,) joint damper coefficient per joint (add_damper; 0 where none).
        """
    @property
    def joint_names(self) -> list[str]:
        """
        (n,) list of the joint names.
        """
    @property
    def joint_types(self) -> list[str]:
        """
        (n,) list of the joint types, 'revolute' or 'prismatic'.
        """
    @property
    def lower_limits(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        (n,) lower joint position limits (URDF <limit>; -inf where none).
        """
    @property
    def masses(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        (n,) body masses (kg).
        """
    @property
    def mimic(self) -> dict[str, tuple[str, float, float]]:
        """
        {joint: (leader, multiplier, offset)} for URDF mimic joints (metadata only).
        """
    @property
    def n(self) -> int:
        """
        Number of joints = DoF = bodies.
        """
    @property
    def n_constraints(self) -> int:
        """
        Number of constraint equations.
        """
    @property
    def n_controls(self) -> int:
        """
        Number m of control inputs (add_actuator, add_control).
        """
    @property
    def n_wrenches(self) -> int:
        """
        Number of body wrench elements (add_point_wrench, add_drag).
        """
    @property
    def nq(self) -> int:
        """
        The configuration's size: n, or n + 1 with a free base (its attitude a quaternion).
        """
    @property
    def nv(self) -> int:
        """
        The velocity's size: the degrees of freedom, n.
        """
    @property
    def parents(self) -> list[int]:
        """
        (n,) list of the parent body index per body, -1 for the world.
        """
    @property
    def stiffness(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        (n,) joint spring stiffness per joint (the sum of its add_spring springs; 0 where none).
        """
    @property
    def total_mass(self) -> float:
        """
        Sum of the body masses (kg).
        """
    @property
    def upper_limits(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        (n,) upper joint position limits (URDF <limit>; inf where none).
        """
    @property
    def velocity_limits(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        (n,) joint velocity limits (URDF metadata; inf where none).
        """
    @property
    def visuals(self) -> list[dict[str, typing.Any]]:
        """
        (V,) list of the visual shapes (URDF ``<visual>``, or add_visual), metadata for viewers, as dicts
        with body (index, -1 = the world), link, shape ('box', 'cylinder', 'sphere', 'mesh'), size (3,)
        (box: x, y, z; cylinder: radius, length, 0 along z; sphere: radius, 0, 0), filename (meshes:
        package://..., or absolute), scale (3,), origin (4, 4) (the shape in the body's joint frame,
        see joint_placements) and rgba ((4,) or None).
        """
class Terrain:
    """
    The terrain of the contact model (model/contact_model.hpp): a ground plane with gaps and boxes, all
    with horizontal top faces; the one home of its height. hovi.contact.Terrain makes it (Terrain.core()).
    """
    def __init__(self, ground: typing.SupportsFloat | typing.SupportsIndex, gaps: numpy.typing.ArrayLike, boxes: numpy.typing.ArrayLike) -> None:
        """
        The ground height, gaps (G, 3) rows (x0, x1, depth), boxes (B, 5) rows (x0, x1, top, y0, y1) (y0, y1 may
        be infinite); ValueError naming the field of a bad one.
        """
    def heights(self, xy: numpy.typing.ArrayLike) -> numpy.typing.NDArray[numpy.float64]:
        """
        The height h(x, y) of the surface below points xy (..., 2): (...).
        """
class ContactModel:
    """
    Point contacts with a terrain and Coulomb friction on a polyhedral cone (model/contact_model.hpp),
    fixed once made: hovi.contact.Contacts makes it (Contacts.core_model()) for hovi.Integrator(...,
    contacts=...) and the trajectory optimiser's complementarity rows.
    """
    def __init__(self, bodies: collections.abc.Sequence[typing.SupportsInt | typing.SupportsIndex], points: numpy.typing.ArrayLike, terrain: Terrain, mu: typing.SupportsFloat | typing.SupportsIndex, directions: numpy.typing.ArrayLike, radii: numpy.typing.ArrayLike | None = None) -> None:
        """
        bodies (C,) indices, points (C, 3) in the bodies' joint frames; the terrain; friction mu; directions (d, 3)
        horizontal unit vectors; radii (C,) of the contacts (spheres centred at the points, default 0: points).
        """
    def gaps(self, X: numpy.typing.ArrayLike) -> numpy.typing.NDArray[numpy.float64]:
        """
        The gaps φ (K, C) of the contacts with their points at world positions X (K, C, 3) (any leading shape).
        """
    def index(self, c: typing.SupportsInt | typing.SupportsIndex, what: str, i: typing.SupportsInt | typing.SupportsIndex = 0) -> int:
        """
        The index among a step's unknowns (C (2 + d),) of contact c's 'normal' impulse, 'friction' impulse
        along direction i, or 'slack'; as a control of with_inputs(model), it is model.n_controls + index.
        """
    def with_inputs(self, model: Model) -> Model:
        """
        A copy of `model` with the contacts' unknowns appended as controls (contact-implicit trajectory
        optimisation), at model.n_controls + index(c, what, i): each normal and friction input scales a world
        force (+z, or the friction direction) at the contact point; the slack has no force.
        """
    def world_impulses(self, z: numpy.typing.ArrayLike) -> numpy.typing.NDArray[numpy.float64]:
        """
        The world impulses (or forces) (K, C, 3) of the contact unknowns z (K, C (2 + d)), per contact
        λ e_z + D^T β (the slack γ carries none).
        """
    @property
    def n_contacts(self) -> int:
        """
        The number of contact points C.
        """
    @property
    def per_contact(self) -> int:
        """
        The unknowns per contact, 2 + d: the normal impulse, d friction impulses, the sliding slack.
        """
class Integrator:
    """
    The core of hovi.Integrator (use that: it normalises arguments and returns Trajectory and
    StepInfo objects). Arrays: q, p (n,); control points (s+1, n), row a = q^{k,a}; controls u (m,)
    held over the step or (s+1, m) per control point; multipliers (s, n_constraints).
    """
    def __init__(self, model: Model, s: typing.SupportsInt | typing.SupportsIndex, dt: typing.SupportsFloat | typing.SupportsIndex, tol: typing.SupportsFloat | typing.SupportsIndex, step_tol: typing.SupportsFloat | typing.SupportsIndex, max_iterations: typing.SupportsInt | typing.SupportsIndex, max_backtracks: typing.SupportsInt | typing.SupportsIndex, line_search: bool, direction: str, reuse_jacobian: bool, reuse_contraction: typing.SupportsFloat | typing.SupportsIndex, predictor: str, contacts: ContactModel | None = None, contact_tol: typing.SupportsFloat | typing.SupportsIndex = 1e-10, locate_impacts: bool = False) -> None:
        """
        A Galerkin integrator of order 2s with step dt on a copy of `model` (options as hovi.Integrator's); with `contacts` (a ContactModel) its steps have the contact stages (galerkin_integrator.hpp).
        """
    def constrained_direction(self, control_points: numpy.typing.ArrayLike, multipliers: numpy.typing.ArrayLike, p: numpy.typing.ArrayLike, u: numpy.typing.ArrayLike | None = None) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"], typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]]:
        """
        control_points (s+1, n), multipliers (s, m_c), p (n,); returns the Newton direction (dq (s, n), dλ (s, m_c)).
        """
    def constrained_residual(self, control_points: numpy.typing.ArrayLike, multipliers: numpy.typing.ArrayLike, p: numpy.typing.ArrayLike, u: numpy.typing.ArrayLike | None = None) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"], typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"], typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]]:
        """
        control_points (s+1, n), multipliers (s, m_c), p (n,); returns (r (s, n), h (s, m_c), p_next (n,)).
        """
    def del_residual(self, control_points: numpy.typing.ArrayLike, p: numpy.typing.ArrayLike, u: numpy.typing.ArrayLike | None = None) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"], typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]]:
        """
        Algorithm 1. control_points (s+1, n), p (n,); returns (r (s, n), p_next (n,)).
        """
    def energies(self, q: numpy.typing.ArrayLike, p: numpy.typing.ArrayLike) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        q (K, nq), p (K, n); returns (K,) energy of every row, in C++ (GIL released).
        """
    def energy(self, q: numpy.typing.ArrayLike, p: numpy.typing.ArrayLike) -> float:
        """
        q (nq,), p (n,); returns K + V at (q, velocity(q, p)), a float.
        """
    def momentum(self, q: numpy.typing.ArrayLike, qdot: numpy.typing.ArrayLike) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        q (nq,), qdot (n,); returns p = M(q) q̇, (n,).
        """
    def newton_direction(self, control_points: numpy.typing.ArrayLike, p: numpy.typing.ArrayLike, u: numpy.typing.ArrayLike | None = None) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        """
        control_points (s+1, n), p (n,); returns the Newton direction dq (s, n) with J dq = -r.
        """
    def project(self, q: numpy.typing.ArrayLike, qdot: numpy.typing.ArrayLike, tol: typing.SupportsFloat | typing.SupportsIndex = 1e-12) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"], typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]]:
        """
        q, qdot: (n,); returns (q, qdot), each (n,), projected onto h(q) = 0 and Dh(q) q̇ = 0.
        """
    def rollout(self, q0: numpy.typing.ArrayLike, p0: numpy.typing.ArrayLike, steps: typing.SupportsInt | typing.SupportsIndex, u: numpy.typing.ArrayLike | None = None, previous: numpy.typing.ArrayLike | None = None, multipliers: numpy.typing.ArrayLike | None = None, impulses: numpy.typing.ArrayLike | None = None) -> dict[str, typing.Any]:
        """
        `steps` steps from q0 (nq,), p0 (n,) in C++ (GIL released); u (steps, (s+1) m); what the step before left:
        previous, its control points (s+1, n) (for the predictor), multipliers (s, m_c), impulses (C (2 + d),)
        (default none active). Returns a dict: q, p (K+1, n), control_points (K, (s+1) n), iterations,
        factorizations, residual, status (per attempted step), multipliers (K, s m_c), steps K, seconds (a
        free base: q (K+1, nq), step k's control points in the chart about q^k's attitude), and
        with contacts pivots, impulses (K, C (2 + d)), gaps (K, C), impact (K,) and step_p (K+1, n).
        """
    def rollout_batch(self, q0s: numpy.typing.ArrayLike, second: numpy.typing.ArrayLike, velocities: bool, steps: typing.SupportsInt | typing.SupportsIndex, u: numpy.typing.ArrayLike | None = None, threads: int | None = None) -> dict[str, typing.Any]:
        """
        `steps` steps from each of B initial states, q0s (B, nq) with second (B, n) the momenta p0 or, if
        velocities, the velocities q̇0 (p0 = M(q0) q̇0 per state); u (B steps, (s+1) m), state b's controls
        in rows b steps .. (b+1) steps - 1. In C++ on `threads` threads (None: HOVI_NUM_THREADS or every
        core), GIL released; each state exactly as rollout. Returns a dict: q (B, steps+1, nq), p (B, steps+1, n) and
        control_points (B, steps, (s+1) n), multipliers (B, steps, s m_c), residual (B, steps) (NaN
        where not reached), iterations, factorizations (B, steps) (-1 where not attempted), steps (B,)
        completed, status (B,) ('converged', the failed step's status, or 'error'), seconds (B,) and
        errors (B,) (an exception's message, or None); with contacts impulses (B, steps, C (2 + d)), gaps (B,
        steps, C), impact (B, steps) (NaN where not reached) and pivots (B, steps) (-1 where not attempted).
        """
    def rollout_controls(self, u: numpy.typing.ArrayLike | None, steps: typing.SupportsInt | typing.SupportsIndex, batch: typing.SupportsInt | typing.SupportsIndex | None = None) -> typing.Any:
        """
        The controls of `steps` steps as rollout and rollout_batch take them: u of shape lead + (m,)
        (held throughout), lead + (steps, m) (held per step) or lead + (steps, s+1, m) (per control point),
        lead = () or (batch,), as an array lead + (steps, (s+1) m); None for None. Raises ValueError for a
        model without controls, another shape, NaN or infinity.
        """
    def step(self, q: numpy.typing.ArrayLike, p: numpy.typing.ArrayLike, u: numpy.typing.ArrayLike | None = None, guess: numpy.typing.ArrayLike | None = None, multipliers: numpy.typing.ArrayLike | None = None, impulses: numpy.typing.ArrayLike | None = None) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"], typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"], dict[str, typing.Any]]:
        """
        One step from q (nq,), p (n,) (GIL released): guess (s+1, n) for a single Newton solve of the DEL equations
        (no contacts), else every stage with its fallbacks (hovi.Integrator.step); multipliers (s, m_c) and
        impulses (C (2 + d),) the first guesses. A free base: the control points in the chart about q's
        attitude and the end state q_next (nq,) in the dict. Returns (control points (s+1, n), p_next (n,), info dict with
        status, converged, iterations, factorizations, residual_evaluations, residual, multipliers (s, m_c), and
        with contacts impulses (C (2 + d),), gaps at the end (C,), pivots and impact).
        """
    def step_batch(self, qs: numpy.typing.ArrayLike, second: numpy.typing.ArrayLike, velocities: bool, u: numpy.typing.ArrayLike | None = None, threads: int | None = None) -> dict[str, typing.Any]:
        """
        One step (the fallbacks of step without a guess) from each of B states, qs (B, nq) with second
        (B, n) the momenta p or, if velocities, the velocities q̇; u (B, (s+1) m), row b = state b's
        controls per control point. In C++ on `threads` threads (None: HOVI_NUM_THREADS or every core),
        GIL released; each state exactly as step. Returns a dict: control_points (B, s+1, n) (the last
        iterate where a solve failed; a free base: in the chart about q's attitude), q_next (B, nq), p_next
        (B, n), multipliers (B, s, m_c), residual (B,), iterations,
        factorizations, residual_evaluations (B,), converged (B,), status (B,) (or 'error'), seconds (B,)
        and errors (B,) (an exception's message, or None); with contacts impulses (B, C (2 + d)), gaps (B, C)
        and pivots (B,).
        """
    def step_controls(self, u: numpy.typing.ArrayLike | None, count: typing.SupportsInt | typing.SupportsIndex) -> typing.Any:
        """
        The controls of one step from each of `count` states as step_batch takes them: u of shape
        (count, m) (held) or (count, s+1, m) (per control point) as an array (count, (s+1) m); None for
        None. Raises ValueError as rollout_controls.
        """
    def velocity(self, q: numpy.typing.ArrayLike, p: numpy.typing.ArrayLike) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        q (nq,), p (n,); returns the velocity q̇ (n,) of momentum p (see hovi.Integrator.velocity).
        """
    @property
    def differentiation_matrix(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        """
        (s+1, s+1) b^{ab} = l_b'(c^a): q̇^a = (1/dt) sum_b b^{ab} q^b.
        """
    @property
    def direction_path(self) -> str:
        """
        The Newton direction computed: 'dense' or 'recursive'.
        """
    @property
    def dt(self) -> float:
        """
        The time step (s).
        """
    @property
    def n(self) -> int:
        """
        Number of joints n of the model (the velocity's size, nv).
        """
    @property
    def n_constraints(self) -> int:
        """
        Number of constraint equations m_c of the model.
        """
    @property
    def n_contacts(self) -> int:
        """
        The number of contact points C (0 without contacts).
        """
    @property
    def n_controls(self) -> int:
        """
        Number of control inputs m of the model.
        """
    @property
    def nodes(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        (s+1,) Lobatto nodes c^a on [0, 1].
        """
    @property
    def nq(self) -> int:
        """
        The configuration's size: n, or n + 1 with a free base.
        """
    @property
    def per_contact(self) -> int:
        """
        The unknowns per contact, 2 + d (with contacts).
        """
    @property
    def s(self) -> int:
        """
        Number of Lobatto intervals; s+1 control points.
        """
    @property
    def weights(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        (s+1,) Lobatto weights w^a.
        """
class Linearizer:
    """
    The core of hovi.Linearizer (use that): exact Jacobians of the DEL equations and of the step map
    of an Integrator; arrays as for hovi._core.Integrator.
    """
    def __init__(self, integrator: Integrator) -> None:
        """
        The linearisation of `integrator`'s DEL equations (the integrator is kept alive).
        """
    def del_jacobian(self, control_points: numpy.typing.ArrayLike, u: numpy.typing.ArrayLike | None = None, with_u: bool = True, multipliers: numpy.typing.ArrayLike | None = None) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"], typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"] | None, typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"] | None]:
        """
        control_points (s+1, n), u (m,) or (s+1, m), multipliers (s, m_c) of a constrained model; returns
        (dq ((s+1) n, (s+1) n), du ((s+1) n, (s+1) (m + m_c)) or None, dh (s m_c, (s+1) n) or None).
        """
    def rollout_jacobians(self, control_points: numpy.typing.ArrayLike, u: numpy.typing.ArrayLike | None = None, want_A: bool = True, want_B: bool = True, multipliers: numpy.typing.ArrayLike | None = None, impulses: numpy.typing.ArrayLike | None = None, smoothing: typing.SupportsFloat | typing.SupportsIndex = 0.0, starts: numpy.typing.ArrayLike | None = None) -> tuple[numpy.typing.NDArray[numpy.float64] | None, numpy.typing.NDArray[numpy.float64] | None]:
        """
        control_points (K, (s+1) n) of K converged steps, u (K, (s+1) m), multipliers (K, s m_c) of a
        constrained model, or with contacts impulses (K, C (2 + d)) and smoothing (the central-path parameter,
        in (N s)^2; 0 holds each contact's state), with a free base the steps' starts q^k (K, nq); returns (A (K, 2n, 2n) or None, B (K, 2n, (s+1) m) or
        None), computed in C++ (GIL released).
        """
    def rollout_jacobians_batch(self, control_points: numpy.typing.ArrayLike, steps: typing.SupportsInt | typing.SupportsIndex, u: numpy.typing.ArrayLike | None = None, want_A: bool = True, want_B: bool = True, multipliers: numpy.typing.ArrayLike | None = None, impulses: numpy.typing.ArrayLike | None = None, smoothing: typing.SupportsFloat | typing.SupportsIndex = 0.0, threads: int | None = None, starts: numpy.typing.ArrayLike | None = None) -> tuple[numpy.typing.NDArray[numpy.float64] | None, numpy.typing.NDArray[numpy.float64] | None, list]:
        """
        rollout_jacobians of B trajectories of `steps` converged steps each: control_points (B steps, (s+1) n),
        u (B steps, (s+1) m), multipliers (B steps, s m_c) or impulses (B steps, C (2 + d)), starts (B steps, nq)
        with a free base, trajectory b in
        rows b steps .. (b+1) steps - 1; in C++ on `threads` threads (None: HOVI_NUM_THREADS or every core),
        GIL released. Returns (A (B, steps, 2n, 2n) or None, B (B, steps, 2n, (s+1) m) or None, errors (B,):
        None, or the message for a trajectory with a singular step, whose blocks are left unset).
        """
    def step_jacobians(self, control_points: numpy.typing.ArrayLike, u: numpy.typing.ArrayLike | None = None, want_A: bool = True, want_B: bool = True, multipliers: numpy.typing.ArrayLike | None = None, impulses: numpy.typing.ArrayLike | None = None, smoothing: typing.SupportsFloat | typing.SupportsIndex = 0.0, start: numpy.typing.ArrayLike | None = None) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"] | None, typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"] | None]:
        """
        At a converged step's control points (s+1, n) (and multipliers (s, m_c), or with contacts its impulses
        (1, C (2 + d)) and the smoothing; with a free base its start q^k (nq,)): returns (A (2n, 2n) or None,
        B (2n, (s+1) m) or None), the Jacobians of (q^{k+1}, p^{k+1}) by (q^k, p^k) and u^{k,0..s} (a free
        base: in tangent coordinates, (q ⊖ q_ref, p)).
        """
def body_point_kinematics(model: Model, q: numpy.typing.ArrayLike, bodies: collections.abc.Sequence[typing.SupportsInt | typing.SupportsIndex], points: numpy.typing.ArrayLike) -> tuple[numpy.typing.NDArray[numpy.float64], numpy.typing.NDArray[numpy.float64]]:
    """
    World positions (P, m, 3) and Jacobians (P, m, 3, n) of m body points at P configurations q (P, nq)
    (a free base: the Jacobians in its velocity, v):
    point i is points[i] (in the body's joint frame, as for add_point_constraint) of body bodies[i].
    One forward kinematics per configuration serves all the points.
    """
def lagrange_basis(s: typing.SupportsInt | typing.SupportsIndex, x: numpy.typing.ArrayLike, derivative: bool = False) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
    """
    x: (K,) points (on [0, 1] or beyond); returns (K, s+1): l_b(x_k), the Lagrange polynomials through the s+1 Lobatto nodes (Integrator.nodes), or their derivatives l_b'(x_k).
    """
def pendulum(n: typing.SupportsInt | typing.SupportsIndex, length: typing.SupportsFloat | typing.SupportsIndex = 0.5, mass: typing.SupportsFloat | typing.SupportsIndex = 1.0, radius: typing.SupportsFloat | typing.SupportsIndex = 0.02) -> Model:
    """
    The paper's n-link 3D pendulum (see hovi.models.pendulum).
    """
def real_array(x: numpy.typing.ArrayLike, name: str) -> numpy.typing.NDArray[numpy.float64]:
    """
    x: an array of any shape, e.g. (n,) or (B, n); returns it as float64 (the same shape), as every array argument of hovi._core is read: ValueError naming `name` for complex numbers (never cast to real), text, Python objects (None is not NaN), booleans, None or a ragged list. The values are not checked (NaN passes).
    """
march: str = ''
