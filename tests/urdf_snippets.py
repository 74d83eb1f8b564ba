"""Small URDF documents built in code for the loader tests."""


def link(name, mass=1.0, inertia=(0.1, 0, 0, 0.1, 0, 0.1), origin="0 0 0", rpy="0 0 0"):
    ixx, ixy, ixz, iyy, iyz, izz = inertia
    return (f'<link name="{name}"><inertial><origin xyz="{origin}" rpy="{rpy}"/><mass value="{mass}"/>'
            f'<inertia ixx="{ixx}" ixy="{ixy}" ixz="{ixz}" iyy="{iyy}" iyz="{iyz}" izz="{izz}"/>'
            f'</inertial></link>')


def joint(name, parent, child, kind="revolute", xyz="0 0 0", rpy="0 0 0", axis="0 0 1", extra=""):
    return (f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
            f'<origin xyz="{xyz}" rpy="{rpy}"/><axis xyz="{axis}"/>'
            f'<limit lower="-1" upper="1" effort="10" velocity="2"/>{extra}</joint>')


def robot(*parts, name="r"):
    return f'<robot name="{name}">' + "".join(parts) + "</robot>"


# Every number attribute urdfdom reads, in FULL_ROBOT: placeholder -> (good value, where the loader's
# error message puts it, attribute name).
NUMBER_ATTRIBUTES = {
    "material_rgba": ("1 0 0 1", "material 'red': <color", "rgba"),
    "inertial_xyz": ("0 0 -0.1", "link 'arm': <inertial><origin", "xyz"),
    "inertial_rpy": ("0 0 0", "link 'arm': <inertial><origin", "rpy"),
    "mass": ("1", "link 'arm': <inertial><mass", "value"),
    **{i: (v, "link 'arm': <inertial><inertia", i)
       for i, v in [("ixx", "0.1"), ("ixy", "0"), ("ixz", "0"), ("iyy", "0.1"), ("iyz", "0"), ("izz", "0.1")]},
    **{f"{kind}_xyz": ("0 0 0", f"link 'arm': <{kind}><origin", "xyz") for kind in ("visual", "collision")},
    **{f"{kind}_rpy": ("0 0 0", f"link 'arm': <{kind}><origin", "rpy") for kind in ("visual", "collision")},
    **{f"{kind}_box": ("1 1 1", f"link 'arm': <{kind}><geometry><box", "size") for kind in ("visual", "collision")},
    **{f"{kind}_cylinder_{a}": ("1", f"link 'arm': <{kind}><geometry><cylinder", a)
       for kind in ("visual", "collision") for a in ("radius", "length")},
    **{f"{kind}_sphere": ("1", f"link 'arm': <{kind}><geometry><sphere", "radius") for kind in ("visual", "collision")},
    **{f"{kind}_mesh": ("1 1 1", f"link 'arm': <{kind}><geometry><mesh", "scale") for kind in ("visual", "collision")},
    "visual_rgba": ("0 0 1 1", "link 'arm': <visual><material><color", "rgba"),
    "joint_xyz": ("0 0 0.5", "joint 'j1': <origin", "xyz"),
    "joint_rpy": ("0 0.2 0", "joint 'j1': <origin", "rpy"),
    "axis": ("1 0 0", "joint 'j1': <axis", "xyz"),
    **{a: (v, "joint 'j1': <limit", a)
       for a, v in [("lower", "-1"), ("upper", "1"), ("effort", "10"), ("velocity", "2")]},
    **{a: (v, "joint 'j1': <dynamics", a) for a, v in [("damping", "0.5"), ("friction", "0.1")]},
    **{a: (v, "joint 'j1': <safety_controller", a) for a, v in [
        ("soft_lower_limit", "-0.9"), ("soft_upper_limit", "0.9"), ("k_position", "10"), ("k_velocity", "1")]},
    **{a: (v, "joint 'j1': <calibration", a) for a, v in [("rising", "0.1"), ("falling", "0.2")]},
    **{a: (v, "joint 'j2': <mimic", a) for a, v in [("multiplier", "2"), ("offset", "0.1")]},
}

# Four <visual> or <collision> elements (KIND), one per geometry, the first with an origin.
_SHAPES = ('<KIND><origin xyz="{KIND_xyz}" rpy="{KIND_rpy}"/><geometry><box size="{KIND_box}"/></geometry></KIND>'
           '<KIND><geometry><cylinder radius="{KIND_cylinder_radius}" length="{KIND_cylinder_length}"/>'
           '</geometry></KIND>'
           '<KIND><geometry><sphere radius="{KIND_sphere}"/></geometry></KIND>'
           '<KIND><geometry><mesh filename="part.stl" scale="{KIND_mesh}"/></geometry></KIND>')

FULL_ROBOT = robot(
    '<material name="red"><color rgba="{material_rgba}"/></material>',
    link("base"),
    '<link name="arm"><inertial><origin xyz="{inertial_xyz}" rpy="{inertial_rpy}"/><mass value="{mass}"/>'
    '<inertia ixx="{ixx}" ixy="{ixy}" ixz="{ixz}" iyy="{iyy}" iyz="{iyz}" izz="{izz}"/></inertial>'
    + _SHAPES.replace("KIND", "visual") + _SHAPES.replace("KIND", "collision")
    + '<visual><geometry><sphere radius="1"/></geometry><material name="blue"><color rgba="{visual_rgba}"/></material>'
    '</visual></link>',
    link("b"),
    '<joint name="j1" type="revolute"><parent link="base"/><child link="arm"/>'
    '<origin xyz="{joint_xyz}" rpy="{joint_rpy}"/><axis xyz="{axis}"/>'
    '<limit lower="{lower}" upper="{upper}" effort="{effort}" velocity="{velocity}"/>'
    '<dynamics damping="{damping}" friction="{friction}"/>'
    '<safety_controller soft_lower_limit="{soft_lower_limit}" soft_upper_limit="{soft_upper_limit}" '
    'k_position="{k_position}" k_velocity="{k_velocity}"/>'
    '<calibration rising="{rising}" falling="{falling}"/></joint>',
    joint("j2", "arm", "b", xyz="0 0 -0.2", extra='<mimic joint="j1" multiplier="{multiplier}" offset="{offset}"/>'),
)


def full_robot(**values):
    """FULL_ROBOT, a robot using every number attribute urdfdom reads, with `values` in place of the good ones."""
    return FULL_ROBOT.format(**{key: good for key, (good, _, _) in NUMBER_ATTRIBUTES.items()} | values)
