"""Creating the scene's bodies on a PyBullet client: surfaces, objects, robots and the
UAV, each in its collision filter group (``world.py`` keeps the names and the state).

The groups keep the broadphase to the pairs collision checks ask about: the robot and
the held object against movable objects and surfaces (and the robot against itself);
objects resting on a table are never compared with each other.
"""

from __future__ import annotations

from stampc.diagnostics import Span, StampcError, error
from stampc.worlds.pybullet._pb import p, quiet_stdout
from stampc.worlds.pybullet.scene import ROBOT_MODELS, BoxSpec, ObjectSpec, RobotSpec, UavSpec
from stampc.worlds.pybullet.state import Arm, Geometry
from stampc.worlds.pybullet.values import quat_from_yaw

# collision filter groups (bit masks)
G_ROBOT, G_HELD, G_MOVABLE, G_STATIC, G_UAV = 1, 2, 4, 8, 16


def _visual_shape(cid: int, visuals: bool, **shape) -> int:
    """A visual shape, or -1 (none) in a world that never renders."""
    return p.createVisualShape(physicsClientId=cid, **shape) if visuals else -1


def add_box(cid: int, s: BoxSpec, visuals: bool) -> int:
    """A static box (a table, a shelf): only robots, held objects and the UAV meet it."""
    half = [v / 2.0 for v in s.size]
    col = p.createCollisionShape(p.GEOM_BOX, halfExtents=half, physicsClientId=cid)
    vis = _visual_shape(cid, visuals, shapeType=p.GEOM_BOX, halfExtents=half, rgbaColor=s.color)
    body = p.createMultiBody(0.0, col, vis, s.position, physicsClientId=cid)
    p.setCollisionFilterGroupMask(body, -1, G_STATIC, G_ROBOT | G_HELD | G_UAV,
                                  physicsClientId=cid)
    return body


def add_object(cid: int, o: ObjectSpec, verbose: bool, visuals: bool) -> tuple[int, Geometry]:
    """A movable object (box, cylinder or URDF) and its collision geometry."""
    if o.shape == "urdf":
        body = _load_urdf_object(cid, o, verbose, visuals)
        lo, hi = p.getAABB(body, -1, physicsClientId=cid)
        geometry = Geometry("box", tuple(h - l for l, h in zip(lo, hi)))
    else:
        if o.shape == "cylinder":
            r, h = o.dims
            kw = {"shapeType": p.GEOM_CYLINDER, "radius": r}
            col = p.createCollisionShape(height=h, physicsClientId=cid, **kw)
            vis = _visual_shape(cid, visuals, length=h, rgbaColor=o.color, **kw)
        else:
            half = [v / 2.0 for v in o.dims]
            col = p.createCollisionShape(p.GEOM_BOX, halfExtents=half, physicsClientId=cid)
            vis = _visual_shape(cid, visuals, shapeType=p.GEOM_BOX, halfExtents=half,
                                rgbaColor=o.color)
        body = p.createMultiBody(o.mass, col, vis, o.position, quat_from_yaw(o.yaw),
                                 physicsClientId=cid)
        geometry = Geometry(o.shape, o.dims)
    p.setCollisionFilterGroupMask(body, -1, G_MOVABLE, G_ROBOT | G_HELD | G_UAV,
                                  physicsClientId=cid)
    return body, geometry


def _urdf_flags(visuals: bool) -> int:
    # a mesh robot's visual shapes take ~90 % of its load (Panda: 0.29 s against 0.03 s)
    return 0 if visuals else p.URDF_IGNORE_VISUAL_SHAPES


def _load_urdf_object(cid: int, o: ObjectSpec, verbose: bool, visuals: bool) -> int:
    try:
        with quiet_stdout(not verbose):
            body = p.loadURDF(o.urdf, o.position, quat_from_yaw(o.yaw), globalScaling=o.scale,
                              flags=_urdf_flags(visuals), physicsClientId=cid)
    except p.error:
        body = -1
    if body < 0:
        raise StampcError([error("PB002", f"cannot load URDF {o.urdf!r} for '{o.name}'",
                                 Span.point("<scene objects>"),
                                 "paths are relative to pybullet_data or absolute")])
    p.changeDynamics(body, -1, mass=o.mass, physicsClientId=cid)
    p.resetBasePositionAndOrientation(body, o.position, (0, 0, 0, 1), physicsClientId=cid)
    return body


def add_robot(cid: int, spec: RobotSpec, verbose: bool, visuals: bool) -> Arm:
    """A fixed-base robot from its model's URDF, fingers open (closed on a held object
    later: ``PyBulletWorld._grip_openings``)."""
    model = ROBOT_MODELS[spec.model]
    flags = (p.URDF_USE_SELF_COLLISION if model.self_collision else 0) | _urdf_flags(visuals)
    with quiet_stdout(not verbose):
        body = p.loadURDF(model.urdf, spec.base, quat_from_yaw(spec.yaw),
                          useFixedBase=True, flags=flags, physicsClientId=cid)
    for a, b in model.ignored_self_pairs:
        p.setCollisionFilterPair(body, body, a, b, 0, physicsClientId=cid)
    # G_ROBOT in the mask: self-collision (if the URDF flag is on) and other robots
    mask = G_MOVABLE | G_STATIC | G_ROBOT
    n_joints = p.getNumJoints(body, physicsClientId=cid)
    for link in range(-1, n_joints):
        p.setCollisionFilterGroupMask(body, link, G_ROBOT, mask, physicsClientId=cid)
    infos = [p.getJointInfo(body, j, physicsClientId=cid) for j in model.arm_joints]
    for j in model.finger_joints:
        p.resetJointState(body, j, model.finger_open, physicsClientId=cid)
    movable = tuple(j for j in range(n_joints)
                    if p.getJointInfo(body, j, physicsClientId=cid)[2] != p.JOINT_FIXED)
    return Arm(spec.name, body, model, tuple(i[8] for i in infos),
               tuple(i[9] for i in infos), movable, spec)


def add_uav(cid: int, u: UavSpec, visuals: bool) -> int:
    """The UAV's box: it meets surfaces and objects (mass > 0: PyBullet skips pairs of
    two static bodies)."""
    half = [v / 2.0 for v in u.size]
    col = p.createCollisionShape(p.GEOM_BOX, halfExtents=half, physicsClientId=cid)
    vis = _visual_shape(cid, visuals, shapeType=p.GEOM_BOX, halfExtents=half,
                        rgbaColor=(0.1, 0.1, 0.1, 1))
    body = p.createMultiBody(u.mass, col, vis, u.position, physicsClientId=cid)
    p.setCollisionFilterGroupMask(body, -1, G_UAV, G_STATIC | G_MOVABLE, physicsClientId=cid)
    return body
